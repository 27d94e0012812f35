# The app in a real window under Xvfb: `snert gui phantom:two-spheres --screenshot FILE
# --frames N` must draw N frames once the first result is in, save the window as a PNG of the
# window's size and exit 0. Without a display the same command must fail cleanly (exit 1, a
# one-line reason), never crash.
#   cmake -DSNERT=<snert> -DXVFB_RUN=<xvfb-run> -DOUT=<png> -P run_window_test.cmake
foreach(required SNERT XVFB_RUN OUT)
    if(NOT DEFINED ${required})
        message(FATAL_ERROR "run_window_test.cmake: ${required} is not set")
    endif()
endforeach()
get_filename_component(out_dir ${OUT} DIRECTORY)
set(config ${out_dir}/app_window_config) # keeps the user's settings out of the test
file(REMOVE_RECURSE ${config})
file(MAKE_DIRECTORY ${config})
file(REMOVE ${OUT})

execute_process(
    COMMAND ${CMAKE_COMMAND} -E env XDG_CONFIG_HOME=${config}
            ${XVFB_RUN} -a -s "-screen 0 1600x1000x24"
            ${SNERT} gui phantom:two-spheres --size 48 --window 1280x800 --screenshot ${OUT}
            --frames 8
    RESULT_VARIABLE code OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 280)
if(NOT code EQUAL 0)
    message(FATAL_ERROR "snert gui under Xvfb exited with ${code}\n${output}\n${errors}")
endif()
if(NOT EXISTS ${OUT})
    message(FATAL_ERROR "snert gui exited 0 but wrote no ${OUT}\n${output}")
endif()
# The PNG's IHDR: width and height, big-endian, at bytes 16 and 20.
file(READ ${OUT} header LIMIT 24 HEX)
string(SUBSTRING "${header}" 32 8 width_hex)
string(SUBSTRING "${header}" 40 8 height_hex)
math(EXPR width "0x${width_hex}")
math(EXPR height "0x${height_hex}")
if(NOT width EQUAL 1280 OR NOT height EQUAL 800)
    message(FATAL_ERROR "${OUT} is ${width}x${height}, expected the window's 1280x800")
endif()
file(SIZE ${OUT} bytes)
if(bytes LESS 60000) # an empty or single-colour window compresses to a few kB
    message(FATAL_ERROR "${OUT} has only ${bytes} bytes: the window looks empty")
endif()
if(EXISTS ${config}/snert/settings.ini)
    message(FATAL_ERROR "the automation run wrote settings into ${config}")
endif()

# No display: a clear message and exit code 1.
execute_process(
    COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY
            XDG_CONFIG_HOME=${config} ${SNERT} gui phantom:sphere
    RESULT_VARIABLE code OUTPUT_VARIABLE output ERROR_VARIABLE errors TIMEOUT 60)
if(NOT code EQUAL 1 OR NOT errors MATCHES "cannot open a window")
    message(FATAL_ERROR "without a display: exit ${code}, expected 1 and 'cannot open a "
                        "window'\n${errors}")
endif()
message(STATUS "window ${width}x${height}, ${bytes} bytes: ${OUT}")
