# Builds a libFuzzer target from its sources in cmake's script mode (the fuzz checks run
# clang, not the project's compiler): each source compiled to its own object, as many at
# once as the machine has cores, through ccache when it is installed (a clean CI run
# recompiles only the sources that changed), then linked.
#   fuzz_build(EXE <path> OBJDIR <dir> FLAGS <compile and link flags...> SOURCES <...> [LIBS <...>])
# CLANG must be set by the caller. Stops with the compiler's message on an error.
function(fuzz_build)
  cmake_parse_arguments(F "" "EXE;OBJDIR" "FLAGS;SOURCES;LIBS" ${ARGN})
  find_program(FUZZ_CCACHE ccache)
  cmake_host_system_information(RESULT cores QUERY NUMBER_OF_LOGICAL_CORES)
  file(MAKE_DIRECTORY ${F_OBJDIR})
  set(list_file ${F_OBJDIR}/sources.txt)
  file(WRITE ${list_file} "")
  set(objs)
  foreach(src ${F_SOURCES})
    # One object per source, named after its path (two files may share a name).
    string(REGEX REPLACE "[/\\.]" "_" name "${src}")
    set(obj ${F_OBJDIR}/${name}.o)
    list(APPEND objs ${obj})
    file(APPEND ${list_file} "${src}\n${obj}\n")
  endforeach()
  # xargs hands each (source, object) pair to its own compiler run, `cores` at a time,
  # as $1 and $2 of a shell line that holds the flags, each single-quoted.
  set(launcher "")
  if(FUZZ_CCACHE)
    set(launcher "'${FUZZ_CCACHE}' ")
  endif()
  set(line "exec ${launcher}'${CLANG}'")
  foreach(flag ${F_FLAGS})
    string(APPEND line " '${flag}'")
  endforeach()
  string(APPEND line " -c \"$1\" -o \"$2\"")
  execute_process(COMMAND xargs -P ${cores} -n 2 -d "\n" sh -c "${line}" sh
                  INPUT_FILE ${list_file} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "compiling the fuzz target ${F_EXE} failed:\n${err}")
  endif()
  execute_process(COMMAND ${CLANG} ${F_FLAGS} ${objs} ${F_LIBS} -o ${F_EXE} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "linking the fuzz target ${F_EXE} failed:\n${err}")
  endif()
endfunction()

# Runs a built fuzz target (COMMAND: the executable and libFuzzer's flags) and stops,
# naming WHAT, on a finding (a crash, an escaped exception, a timeout) or when libFuzzer
# did not report its runs. Sets FUZZ_DONE ("Done N runs in T second(s)"), FUZZ_COV (the
# last status line's coverage) and FUZZ_ERR (libFuzzer's output) in the caller's scope.
#   fuzz_run(WHAT "the artifact loader" COMMAND <exe> <flags...>)
function(fuzz_run)
  cmake_parse_arguments(F "" "WHAT" "COMMAND" ${ARGN})
  execute_process(COMMAND ${F_COMMAND} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "fuzzing ${F_WHAT} found a failure:\n${err}")
  endif()
  string(REGEX MATCH "Done [0-9]+ runs[^\n]*" done "${err}")
  if(NOT done)
    message(FATAL_ERROR "the fuzzer of ${F_WHAT} did not report its runs:\n${err}")
  endif()
  string(REGEX MATCHALL "cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9a-zA-Z]+" covs "${err}")
  set(cov "")
  if(covs)
    list(GET covs -1 cov)  # the last status line: the coverage at the end
  endif()
  set(FUZZ_DONE "${done}" PARENT_SCOPE)
  set(FUZZ_COV "${cov}" PARENT_SCOPE)
  set(FUZZ_ERR "${err}" PARENT_SCOPE)
endfunction()

# The tmpc sources under src/ named as "module/file" (no extension), and the Eigen headers'
# folder: sets FUZZ_SOURCES and FUZZ_EIGEN_DIR in the caller's scope.
#   fuzz_sources(model/config sim/scenario ...)
function(fuzz_sources)
  set(srcs)
  foreach(f ${ARGN})
    list(APPEND srcs ${SRC}/src/${f}.cpp)
  endforeach()
  find_path(FUZZ_EIGEN_DIR Eigen/Core PATHS /usr/include/eigen3 /usr/local/include/eigen3 NO_DEFAULT_PATH)
  if(NOT FUZZ_EIGEN_DIR)
    message(FATAL_ERROR "Eigen headers not found")
  endif()
  set(FUZZ_SOURCES ${srcs} PARENT_SCOPE)
  set(FUZZ_EIGEN_DIR ${FUZZ_EIGEN_DIR} PARENT_SCOPE)
endfunction()
