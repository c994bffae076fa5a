# The module layering of DESIGN.md section 2, checked on every build: a file of module M
# may include the headers of M and of the modules below it, never above.
#   cmake -DSRC=<source dir> [-DROOT=<tree to check, default SRC>] -P check_layering.cmake
# ROOT holds src/<module>/, include/tmpc/<module>/ and cuda/; an include of
# "tmpc/<X>/..." or "../<X>/..." counts as a use of X. Exit status 1 with every
# offending file, line and the rule it breaks.
if(NOT ROOT)
  set(ROOT ${SRC})
endif()
# Lowest first. gpu: the kernels' header-only core (the CPU twin and the CUDA code);
# cuda: the CUDA solver (above solvers, whose factory it registers with); cli on top.
set(order model sets qp synthesis gpu solvers cuda explicit io sim runtime metrics cli)
file(GLOB_RECURSE files RELATIVE ${ROOT}
  ${ROOT}/src/*.cpp ${ROOT}/src/*.hpp ${ROOT}/include/tmpc/*.hpp
  ${ROOT}/cuda/*.cu ${ROOT}/cuda/*.cuh ${ROOT}/cuda/*.hpp ${ROOT}/cuda/*.cpp)
string(REPLACE ";" " < " order_text "${order}")
set(errors "")
foreach(f ${files})
  if(f MATCHES "^src/([a-z_]+)/")
    set(m ${CMAKE_MATCH_1})
  elseif(f MATCHES "^include/tmpc/([a-z_]+)/")
    set(m ${CMAKE_MATCH_1})
  elseif(f MATCHES "^cuda/")
    set(m cuda)
  else()
    continue()
  endif()
  list(FIND order ${m} rank)
  if(rank LESS 0)
    string(APPEND errors "${f}: module '${m}' is not in the layering (cmake/check_layering.cmake)\n")
    continue()
  endif()
  file(STRINGS ${ROOT}/${f} lines REGEX "^[ \t]*#[ \t]*include[ \t]+\"")
  foreach(line ${lines})
    if(line MATCHES "\"(tmpc|\\.\\.)/([a-z_]+)/")
      set(used ${CMAKE_MATCH_2})
      list(FIND order ${used} used_rank)
      if(used_rank GREATER rank)
        string(STRIP "${line}" line)
        string(APPEND errors "${f}: ${line}: module '${m}' may not use '${used}', which is above it (${order_text})\n")
      endif()
    endif()
  endforeach()
endforeach()
if(errors)
  message(FATAL_ERROR "tmpc layering: includes against the order of the modules:\n${errors}")
endif()
