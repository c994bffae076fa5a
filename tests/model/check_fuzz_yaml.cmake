# Build the configuration and scenario loaders' libFuzzer target with clang (ASan + UBSan)
# and fuzz it for a bounded time from the shipped configurations and scenarios. It found
# yaml-cpp 0.7's endless loop on a stray ',' (README "Bad input").
#   cmake -DCLANG=clang++ -DSRC=<source dir> -DOUT=<scratch dir> [-DSECONDS=N] -P check_fuzz_yaml.cmake
if(NOT SECONDS)
  set(SECONDS 60)
endif()
file(REMOVE_RECURSE ${OUT}/corpus)
file(MAKE_DIRECTORY ${OUT}/corpus)
# Seeds: a leading byte 0 (configuration) or 1 (scenario), then the file.
file(GLOB configs ${SRC}/config/*.yaml)
file(GLOB scenarios ${SRC}/config/scenarios/*.yaml)
set(i 0)
foreach(f ${configs} ${scenarios})
  list(FIND configs ${f} is_config)
  if(is_config EQUAL -1)
    set(kind 1)
  else()
    set(kind 0)
  endif()
  execute_process(COMMAND sh -c "printf '\\00${kind}' > '${OUT}/corpus/seed${i}' && cat '${f}' >> '${OUT}/corpus/seed${i}'"
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "writing the seed of ${f} failed")
  endif()
  math(EXPR i "${i} + 1")
endforeach()
include(${SRC}/tests/fuzz_build.cmake)
fuzz_sources(model/config model/trajectory_yaml model/trajectory model/quintic_spline model/state_layout model/perturbation
          model/dynamics model/kinematic_tree model/equilibrium model/checksum model/reference
          sim/scenario sim/disturbance sim/noise sim/actuator_fault)
fuzz_build(EXE ${OUT}/fuzz_yaml OBJDIR ${OUT}/obj
           FLAGS -std=c++17 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
                 -DEIGEN_NO_DEBUG -DTMPC_SCENARIO_DIR="${SRC}/config/scenarios" -I${SRC}/include -I${SRC}/src
                 -isystem ${FUZZ_EIGEN_DIR}
           SOURCES ${SRC}/tests/model/fuzz_yaml.cpp ${FUZZ_SOURCES}
           LIBS -lyaml-cpp)
# -timeout: an input the loaders take 5 s over (the files are at most 40 kB) is a hang.
fuzz_run(WHAT "the configuration and scenario loaders"
         COMMAND ${OUT}/fuzz_yaml -max_total_time=${SECONDS} -seed=1 -max_len=40000 -timeout=5 -rss_limit_mb=4096
                 -artifact_prefix=${OUT}/ ${OUT}/corpus)
message(STATUS "fuzz_yaml: ${FUZZ_DONE} (${FUZZ_COV})")
