# The layering check itself: a tree whose model includes the runtime (an upward include)
# and whose sim includes the model's internals (downward, allowed) is refused, naming the
# upward file and line only; the real tree passes.
#   cmake -DSRC=<source dir> -DOUT=<scratch> -P check_layering_refuses.cmake
file(REMOVE_RECURSE ${OUT}/tree)
file(WRITE ${OUT}/tree/src/model/bad.cpp "#include \"tmpc/model/config.hpp\"\n#include \"tmpc/runtime/telemetry.hpp\"\n")
file(WRITE ${OUT}/tree/src/sim/ok.cpp "#include \"../model/yaml_section.hpp\"\n#include \"tmpc/model/config.hpp\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} -DSRC=${SRC} -DROOT=${OUT}/tree -P ${SRC}/cmake/check_layering.cmake
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
if(rc EQUAL 0)
  message(FATAL_ERROR "an upward include was accepted")
endif()
string(REGEX REPLACE "[ \n]+" " " err "${err}")  # message() wraps long lines
if(NOT err MATCHES "src/model/bad.cpp: #include \"tmpc/runtime/telemetry.hpp\": module 'model' may not use 'runtime'")
  message(FATAL_ERROR "the refusal does not name the file, the line and the rule: ${err}")
endif()
if(err MATCHES "ok.cpp")
  message(FATAL_ERROR "a downward include was refused: ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -DSRC=${SRC} -P ${SRC}/cmake/check_layering.cmake RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the source tree breaks its own layering: ${err}")
endif()
