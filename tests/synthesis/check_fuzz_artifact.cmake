# Build the artifact loader's libFuzzer target with clang (ASan + UBSan) from the
# sources it needs, run it once on the payload of a quick real design (4 MB, 97 % of it
# the RPI zonotope's generators: accepted and written back byte for byte), then fuzz for a
# bounded time from that payload with the zonotope cut to its first term
# (shrink_artifact_seed.py: 110 kB, still an accepted artifact). From the full payload
# libFuzzer ran about 2 inputs a second (102 runs in 60 s); from the cut one about 50
# (README "Offline synthesis", the artifact's paragraph, has the measurement).
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
execute_process(COMMAND sh -c "tail -c +21 '${OUT}/seed.tmpc' | head -c -4 > '${OUT}/design'" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "extracting the seed payload failed")
endif()
find_program(PYTHON3 NAMES python3 PATHS /usr/bin NO_CACHE)
if(NOT PYTHON3)
  message(FATAL_ERROR "python3 not found (it cuts the seed's zonotope)")
endif()
execute_process(COMMAND ${PYTHON3} ${SRC}/tests/synthesis/shrink_artifact_seed.py ${OUT}/design ${OUT}/corpus/design_small
                RESULT_VARIABLE rc OUTPUT_VARIABLE shrunk ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cutting the seed's zonotope failed:\n${shrunk}${err}")
endif()
include(${SRC}/tests/fuzz_build.cmake)
fuzz_sources(synthesis/artifact synthesis/artifact_checks synthesis/record_file synthesis/lqr synthesis/estimator synthesis/rpi
          model/checksum model/config model/trajectory_yaml model/trajectory model/quintic_spline
          model/dynamics model/kinematic_tree model/equilibrium model/state_layout qp/mpc_qp qp/disturbance_target
          qp/parametric_qp qp/redundant_rows sets/box sets/zonotope sets/lp)
# CLP: the artifact's redundant-row certificate (qp/redundant_rows.cpp) solves LPs.
find_path(CLP_DIR ClpSimplex.hpp PATHS /usr/include/coin /usr/include/coin-or /usr/local/include/coin NO_DEFAULT_PATH)
if(NOT CLP_DIR)
  message(FATAL_ERROR "CLP headers not found")
endif()
# -gline-tables-only: file and line in a report, a fifth less compile time than -g.
fuzz_build(EXE ${OUT}/fuzz_artifact OBJDIR ${OUT}/obj
           FLAGS -std=c++17 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
                 -DEIGEN_NO_DEBUG -I${SRC}/include -isystem ${FUZZ_EIGEN_DIR} -isystem ${CLP_DIR}
           SOURCES ${SRC}/tests/synthesis/fuzz_artifact.cpp ${FUZZ_SOURCES}
           LIBS -lyaml-cpp -lClp -lCoinUtils)
# The full payload once (a file argument runs it and exits): the real design is accepted.
execute_process(COMMAND ${OUT}/fuzz_artifact -rss_limit_mb=4096 ${OUT}/design
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(REGEX MATCH "fuzz_artifact: ([0-9]+) inputs accepted" accepted "${err}")
if(NOT rc EQUAL 0 OR NOT accepted OR CMAKE_MATCH_1 EQUAL 0)
  message(FATAL_ERROR "the artifact loader did not accept the real design's payload under ASan and UBSan:\n${err}")
endif()
# -max_len: the cut seed's size and a little (libFuzzer truncates longer corpus files to
# it, and a truncated payload never passes the record parser).
file(SIZE ${OUT}/corpus/design_small seed_bytes)
math(EXPR max_len "${seed_bytes} + 4096")
fuzz_run(WHAT "the artifact loader"
         COMMAND ${OUT}/fuzz_artifact -max_total_time=${SECONDS} -runs=200000 -seed=1 -max_len=${max_len}
                 -rss_limit_mb=4096 ${OUT}/corpus)
string(REGEX MATCH "fuzz_artifact: ([0-9]+) inputs accepted" accepted "${FUZZ_ERR}")
if(NOT accepted OR CMAKE_MATCH_1 EQUAL 0)
  message(FATAL_ERROR "the artifact fuzzer accepted no input (not even the cut seed, ${seed_bytes} bytes): it fuzzed "
                      "the header parser only:\n${FUZZ_ERR}")
endif()
message(STATUS "fuzz_artifact: ${FUZZ_DONE} (${FUZZ_COV}; ${accepted}; cut seed ${seed_bytes} bytes)")
