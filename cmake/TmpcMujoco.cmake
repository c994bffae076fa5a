# Optional MuJoCo plant (Debian libmujoco-dev 2.2.2): TMPC_WITH_MUJOCO = AUTO | ON | OFF.
# Debian's mujocoConfig.cmake lists /usr/include/libqhull_r/ in its include path
# without depending on the package that provides it, so CMake rejects the imported
# target; we locate the header and the library ourselves.
set(TMPC_MUJOCO_ENABLED OFF)
string(TOUPPER "${TMPC_WITH_MUJOCO}" _tmpc_mj_mode)
if(NOT _tmpc_mj_mode STREQUAL "OFF")
  find_path(TMPC_MUJOCO_INCLUDE_DIR mujoco/mujoco.h)
  find_library(TMPC_MUJOCO_LIBRARY NAMES mujoco)
  if(TMPC_MUJOCO_INCLUDE_DIR AND TMPC_MUJOCO_LIBRARY)
    set(TMPC_MUJOCO_ENABLED ON)
    message(STATUS "tmpc: MuJoCo found (${TMPC_MUJOCO_LIBRARY}), building the MuJoCo plant")
  elseif(_tmpc_mj_mode STREQUAL "ON")
    message(FATAL_ERROR "TMPC_WITH_MUJOCO=ON but MuJoCo was not found (apt-get install libmujoco-dev)")
  else()
    message(STATUS "tmpc: MuJoCo not found, the mujoco plant is unavailable")
  endif()
endif()
