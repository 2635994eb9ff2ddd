# Every dependency comes from the distribution's packages (scripts/setup.sh installs them)
# and is found the CMake way.
find_package(GSL 2.6 REQUIRED)
find_package(SUNDIALS 6 REQUIRED CONFIG COMPONENTS cvode nvecserial)
# jansson ships a pkg-config file on Debian (no CMake config).
find_package(PkgConfig REQUIRED)
pkg_check_modules(JANSSON REQUIRED IMPORTED_TARGET jansson>=2.13)
# libccd (collision detection between convex shapes; Debian's libccd-dev, pkg-config name ccd).
pkg_check_modules(CCD REQUIRED IMPORTED_TARGET ccd>=2.0)

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
