# Build the artifact loader's libFuzzer target with clang (ASan + UBSan) from the
# sources it needs, seed it with the payload of a quick real design, and fuzz for a
# bounded time (each accepted input runs the semantic checks: about half a second for the
# 4 MB seed, 97 % of it the RPI zonotope's generators; 102 runs, 14 accepted, in 60 s here).
#   cmake -DCLANG=clang++ -DTMPC=<tmpc executable> -DSRC=<source dir> -DOUT=<scratch dir> [-DSECONDS=N] -P ...
if(NOT SECONDS)
  set(SECONDS 60)
endif()
file(REMOVE_RECURSE ${OUT}/corpus)
file(MAKE_DIRECTORY ${OUT}/corpus)
# The seed: a real artifact (the default configuration without the LMI comparison).
file(READ ${SRC}/config/tiltrotor.yaml text)
string(REPLACE "compare_gains: true" "compare_gains: false" text "${text}")
string(REPLACE "verify_directions: 2000" "verify_directions: 100" text "${text}")
# The envelope's scenario files, named from the copy's folder.
string(REGEX REPLACE "([[ ,])scenarios/" "\\1${SRC}/config/scenarios/" text "${text}")
file(WRITE ${OUT}/quick.yaml "${text}")
execute_process(COMMAND ${TMPC} design --config ${OUT}/quick.yaml --out ${OUT}/seed.tmpc --report ${OUT}/seed.json
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "designing the seed artifact failed:\n${err}")
endif()
# Payload only: drop the 20-byte header and the 4-byte CRC.
execute_process(COMMAND sh -c "tail -c +21 '${OUT}/seed.tmpc' | head -c -4 > '${OUT}/corpus/design'" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "extracting the seed payload failed")
endif()
set(srcs)
foreach(f synthesis/artifact synthesis/artifact_checks synthesis/record_file synthesis/lqr synthesis/estimator synthesis/rpi
          model/checksum model/config model/trajectory_yaml model/trajectory model/quintic_spline
          model/dynamics model/kinematic_tree model/equilibrium model/state_layout qp/mpc_qp qp/disturbance_target
          qp/parametric_qp qp/redundant_rows sets/box sets/zonotope sets/lp)
  list(APPEND srcs ${SRC}/src/${f}.cpp)
endforeach()
find_path(EIGEN_DIR Eigen/Core PATHS /usr/include/eigen3 /usr/local/include/eigen3 NO_DEFAULT_PATH)
if(NOT EIGEN_DIR)
  message(FATAL_ERROR "Eigen headers not found")
endif()
# CLP: the artifact's redundant-row certificate (qp/redundant_rows.cpp) solves LPs.
find_path(CLP_DIR ClpSimplex.hpp PATHS /usr/include/coin /usr/include/coin-or /usr/local/include/coin NO_DEFAULT_PATH)
if(NOT CLP_DIR)
  message(FATAL_ERROR "CLP headers not found")
endif()
# -gline-tables-only: file and line in a report, a fifth less compile time than -g.
include(${SRC}/tests/fuzz_build.cmake)
fuzz_build(EXE ${OUT}/fuzz_artifact OBJDIR ${OUT}/obj
           FLAGS -std=c++17 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
                 -DEIGEN_NO_DEBUG -I${SRC}/include -isystem ${EIGEN_DIR} -isystem ${CLP_DIR}
           SOURCES ${SRC}/tests/synthesis/fuzz_artifact.cpp ${srcs}
           LIBS -lyaml-cpp -lClp -lCoinUtils)
# -max_len: the seed's size (libFuzzer truncates longer corpus files to it, and a
# truncated payload never passes the record parser).
file(SIZE ${OUT}/corpus/design seed_bytes)
execute_process(COMMAND ${OUT}/fuzz_artifact -max_total_time=${SECONDS} -runs=200000 -seed=1 -max_len=${seed_bytes}
                        -rss_limit_mb=4096 ${OUT}/corpus
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fuzzing the artifact loader found a failure:\n${err}")
endif()
string(REGEX MATCH "Done [0-9]+ runs[^\n]*" done "${err}")
string(REGEX MATCH "cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9a-zA-Z]+" cov "${err}")
if(NOT done)
  message(FATAL_ERROR "the artifact fuzzer did not report its runs:\n${err}")
endif()
string(REGEX MATCH "fuzz_artifact: ([0-9]+) inputs accepted" accepted "${err}")
if(NOT accepted OR CMAKE_MATCH_1 EQUAL 0)
  message(FATAL_ERROR "the artifact fuzzer accepted no input (not even the seed, ${seed_bytes} bytes): it fuzzed "
                      "the header parser only:\n${err}")
endif()
message(STATUS "fuzz_artifact: ${done} (${cov}; ${accepted}; seed ${seed_bytes} bytes)")
