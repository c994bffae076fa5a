# The code nvcc compiles stays C++14 (JetPack 4's nvcc 10.2 has no C++17; DESIGN.md
# section 5): every header shared with the device code compiles alone with
# `-std=c++14 -Wpedantic -Werror` on the host compiler, and, when NVCC is given, every
# .cu file compiles with `nvcc -std=c++14`.
#   cmake -DCXX=g++ -DSRC=<source dir> -DOUT=<scratch dir> [-DNVCC=nvcc -DARCH=90] -P check_cxx14.cmake
file(GLOB headers ${SRC}/include/tmpc/gpu/*.hpp ${SRC}/cuda/*.hpp)
file(MAKE_DIRECTORY ${OUT})
foreach(h ${headers})
  get_filename_component(name ${h} NAME_WE)
  file(WRITE ${OUT}/include_${name}.cpp "#include \"${h}\"\n")
  execute_process(COMMAND ${CXX} -std=c++14 -fsyntax-only -Wall -Wextra -Wpedantic -Werror
                          -I${SRC}/include -I${SRC}/cuda ${OUT}/include_${name}.cpp
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${h} is not C++14:\n${out}${err}")
  endif()
  message(STATUS "C++14: ${h}")
endforeach()
if(NVCC)
  file(GLOB sources ${SRC}/cuda/*.cu)
  foreach(s ${sources})
    get_filename_component(name ${s} NAME_WE)
    execute_process(COMMAND ${NVCC} -std=c++14 -arch=sm_${ARCH} -I${SRC}/include -I${SRC}/cuda -c ${s}
                            -o ${OUT}/${name}.o
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${s} does not compile with nvcc -std=c++14:\n${out}${err}")
    endif()
    message(STATUS "nvcc -std=c++14: ${s}")
  endforeach()
endif()
