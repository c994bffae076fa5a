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
