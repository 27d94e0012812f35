# The app's UI snapshot: runs snert_app_ui_snapshot (scripted input, state checks), then
# compares its picture with the golden one (the renderer's compare tool and tolerances).
#   cmake -DDRIVER=<snert_app_ui_snapshot> -DCOMPARE=<snert_snapshot_compare> -DNAME=<name>
#         -DGOLDEN_DIR=<tests/snapshots> -DOUT_DIR=<build folder> -P run_ui_snapshot.cmake
# SNERT_UPDATE_SNAPSHOTS=1 regenerates the golden (see tests/README.md).
foreach(required DRIVER COMPARE NAME GOLDEN_DIR OUT_DIR)
    if(NOT DEFINED ${required})
        message(FATAL_ERROR "run_ui_snapshot.cmake: ${required} is not set")
    endif()
endforeach()
file(MAKE_DIRECTORY ${OUT_DIR})
set(actual ${OUT_DIR}/${NAME}.png)
set(diff ${OUT_DIR}/${NAME}.diff.png)
file(REMOVE ${actual} ${diff})
execute_process(COMMAND ${DRIVER} ${actual} RESULT_VARIABLE driven)
if(NOT driven EQUAL 0)
    message(FATAL_ERROR "the scripted UI run failed (exit code ${driven})")
endif()
# Text and lines cover much of a UI: a slightly larger share of differing pixels is allowed
# than for the figures, for rasterisation differences between Mesa versions.
execute_process(COMMAND ${COMPARE} ${GOLDEN_DIR}/${NAME}.png ${actual} ${diff}
                        --tolerance 8 --max-share 0.004
                RESULT_VARIABLE compared)
if(NOT compared EQUAL 0)
    message(FATAL_ERROR "snapshot ${NAME} does not match its golden image")
endif()
