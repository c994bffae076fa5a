# Build the protocol parser's libFuzzer target with clang (ASan + UBSan) and run it
# for a fixed number of inputs from a seed corpus of valid frame streams.
#   cmake -DCLANG=clang++ -DSRC=<source dir> -DOUT=<scratch dir> [-DRUNS=N] -P check_fuzz.cmake
if(NOT RUNS)
  set(RUNS 300000)
endif()
file(REMOVE_RECURSE ${OUT}/corpus)
file(MAKE_DIRECTORY ${OUT}/corpus)
set(common -std=c++17 -I${SRC}/include ${SRC}/src/io/protocol.cpp ${SRC}/src/model/checksum.cpp)
include(${SRC}/tests/fuzz_build.cmake)
fuzz_build(EXE ${OUT}/fuzz_protocol OBJDIR ${OUT}/obj
           FLAGS -std=c++17 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
                 -I${SRC}/include
           SOURCES ${SRC}/tests/io/fuzz_protocol.cpp ${SRC}/src/io/protocol.cpp ${SRC}/src/model/checksum.cpp)
execute_process(COMMAND ${CLANG} -O1 ${SRC}/tests/io/fuzz_seeds.cpp ${common} -o ${OUT}/fuzz_seeds
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the seed generator failed:\n${err}")
endif()
execute_process(COMMAND ${OUT}/fuzz_seeds ${OUT}/corpus RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "writing the seed corpus failed")
endif()
fuzz_run(WHAT "the protocol parser" COMMAND ${OUT}/fuzz_protocol -runs=${RUNS} -seed=1 -max_len=1024 ${OUT}/corpus)
message(STATUS "fuzz_protocol: ${FUZZ_DONE} (${FUZZ_COV})")
