# Every dependency comes from the distribution's packages (scripts/setup.sh installs them)
# and is found the CMake way.
find_package(GSL 2.6 REQUIRED)
find_package(SUNDIALS 6 REQUIRED CONFIG COMPONENTS cvode arkode nvecserial
  OPTIONAL_COMPONENTS sunlinsolklu sunmatrixsparse)
# KLU (SuiteSparse's sparse LU through SUNDIALS' sunlinsolklu, klu.h from libsuitesparse-dev):
# BDF's sparse linear solver (src/ode/cvode_sparse.c). Optional: without it that one solver is
# refused (TB_STATUS_UNSUPPORTED) and the dense and Krylov solvers work as before.
option(TUMBLE_WITH_KLU "BDF's sparse linear solver through SUNDIALS' KLU, when found" ON)
set(TUMBLE_KLU OFF)
if(TUMBLE_WITH_KLU AND TARGET SUNDIALS::sunlinsolklu AND TARGET SUNDIALS::sunmatrixsparse)
  get_target_property(_tumble_klu_includes SUNDIALS::KLU INTERFACE_INCLUDE_DIRECTORIES)
  find_path(TUMBLE_KLU_INCLUDE klu.h HINTS ${_tumble_klu_includes} PATH_SUFFIXES suitesparse)
  if(TUMBLE_KLU_INCLUDE)
    set(TUMBLE_KLU ON)
  endif()
endif()
if(TUMBLE_KLU)
  message(STATUS "KLU: found (BDF's sparse linear solver)")
else()
  message(STATUS "KLU: not found or TUMBLE_WITH_KLU off (BDF's sparse linear solver refused)")
endif()
find_package(Threads REQUIRED) # the npz writer's thread
# jansson ships a pkg-config file on Debian (no CMake config).
find_package(PkgConfig REQUIRED)
pkg_check_modules(JANSSON REQUIRED IMPORTED_TARGET jansson>=2.13)
# libccd (collision detection between convex shapes; Debian's libccd-dev, pkg-config name ccd).
pkg_check_modules(CCD REQUIRED IMPORTED_TARGET ccd>=2.0)
# libdeflate: the CRC-32 of the .npz writer's zip members (vectorised, about 4 times our table's speed).
pkg_check_modules(LIBDEFLATE REQUIRED IMPORTED_TARGET libdeflate)

if(TUMBLE_BUILD_TESTS)
  # CMocka 1.1.5 ships a config that only sets variables; wrap them in an imported target.
  find_package(cmocka CONFIG REQUIRED)
  if(NOT TARGET cmocka::cmocka)
    add_library(cmocka::cmocka INTERFACE IMPORTED)
    set_target_properties(cmocka::cmocka PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${CMOCKA_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES "${CMOCKA_LIBRARIES}")
  endif()
endif()
