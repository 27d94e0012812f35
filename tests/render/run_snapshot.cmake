# One snapshot test: renders with `snert render`, then compares with the golden PNG.
#   cmake -DSNERT=<snert> -DCOMPARE=<snert_snapshot_compare> -DNAME=<name>
#         -DGOLDEN_DIR=<tests/snapshots> -DOUT_DIR=<build folder> -DRENDER_ARGS=<args;...>
#         [-DTOLERANCE=8] [-DMAX_SHARE=0.002] [-DREQUIRES=<input path>] -P run_snapshot.cmake
# With REQUIRES (a real volume) the test is skipped, saying so, when that path is absent.
# The actual image stays in OUT_DIR/<name>.png; on failure the diff is OUT_DIR/<name>.diff.png.
foreach(required SNERT COMPARE NAME GOLDEN_DIR OUT_DIR RENDER_ARGS)
    if(NOT DEFINED ${required})
        message(FATAL_ERROR "run_snapshot.cmake: ${required} is not set")
    endif()
endforeach()
if(NOT DEFINED TOLERANCE)
    set(TOLERANCE 8)
endif()
if(NOT DEFINED MAX_SHARE)
    set(MAX_SHARE 0.002)
endif()
if(DEFINED REQUIRES AND NOT EXISTS "${REQUIRES}")
    message("SNAPSHOT SKIPPED: ${REQUIRES} is absent")
    return()
endif()
file(MAKE_DIRECTORY ${OUT_DIR})
set(actual ${OUT_DIR}/${NAME}.png)
set(diff ${OUT_DIR}/${NAME}.diff.png)
file(REMOVE ${actual} ${diff})

execute_process(COMMAND ${SNERT} render ${RENDER_ARGS} --gl osmesa --out ${actual}
                RESULT_VARIABLE rendered)
if(NOT rendered EQUAL 0)
    message(FATAL_ERROR "snert render ${RENDER_ARGS} failed (exit code ${rendered})")
endif()
execute_process(COMMAND ${COMPARE} ${GOLDEN_DIR}/${NAME}.png ${actual} ${diff}
                        --tolerance ${TOLERANCE} --max-share ${MAX_SHARE}
                RESULT_VARIABLE compared)
if(NOT compared EQUAL 0)
    message(FATAL_ERROR "snapshot ${NAME} does not match its golden image")
endif()
