# cmake --install: headers, the library, the tumble command, a CMake package
# (find_package(tumble CONFIG) -> tumble::tumble), a pkg-config file (tumble.pc), the docs and
# example scenes (share/tumble/) and the licence (share/doc/tumble/).
# tumble is GPL-3.0-or-later (LICENSE): it links GSL, which is GPL-3.0-or-later.
include(CMakePackageConfigHelpers)
set(TUMBLE_LICENSE "GPL-3.0-or-later")

# The installed command finds the installed shared libtumble wherever the prefix is moved:
# its run path is relative to the executable ($ORIGIN/../lib), not the build tree.
file(RELATIVE_PATH tumble_bin_to_lib /root/${CMAKE_INSTALL_BINDIR} /root/${CMAKE_INSTALL_LIBDIR})
set_target_properties(tumble_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${tumble_bin_to_lib}")

install(TARGETS tumble tumble_cli
  EXPORT tumbleTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY include/tumble DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/include/tumble/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/tumble)

set(TUMBLE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/tumble)
install(EXPORT tumbleTargets NAMESPACE tumble:: DESTINATION ${TUMBLE_CMAKE_DIR})
if(BUILD_SHARED_LIBS)
  set(TUMBLE_SHARED TRUE)
else()
  set(TUMBLE_SHARED FALSE)
endif()
configure_package_config_file(cmake/tumbleConfig.cmake.in
  ${PROJECT_BINARY_DIR}/tumbleConfig.cmake INSTALL_DESTINATION ${TUMBLE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/tumbleConfigVersion.cmake
  COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/tumbleConfig.cmake
  ${PROJECT_BINARY_DIR}/tumbleConfigVersion.cmake DESTINATION ${TUMBLE_CMAKE_DIR})

# pkg-config: a static library needs its dependencies on the link line (pkg-config --static).
# GSL, jansson, libccd and libdeflate come through their own .pc files (Requires.private in
# tumble.pc.in); SUNDIALS ships none, so it and the compiler's OpenMP runtime are named by -l
# only: never the absolute paths CMake found them at (/usr/lib/gcc/x86_64-linux-gnu/12/...),
# which name one toolchain's private directory. The install_consumers test checks no path is left.
set(TUMBLE_PC_PRIVATE_LIBS "-lsundials_cvode -lsundials_arkode -lsundials_nvecserial")
if(TUMBLE_KLU)
  string(APPEND TUMBLE_PC_PRIVATE_LIBS
    " -lsundials_sunlinsolklu -lsundials_sunmatrixsparse -lklu -lamd -lcolamd -lbtf -lsuitesparseconfig")
endif()
if(TUMBLE_OPENMP)
  foreach(library IN LISTS OpenMP_C_LIB_NAMES)
    string(APPEND TUMBLE_PC_PRIVATE_LIBS " -l${library}")
  endforeach()
endif()
if(CMAKE_THREAD_LIBS_INIT) # empty with glibc >= 2.34, where threads are in libc
  string(APPEND TUMBLE_PC_PRIVATE_LIBS " ${CMAKE_THREAD_LIBS_INIT}")
endif()
# Relocatable: the prefix is found from the .pc file's own place.
file(RELATIVE_PATH TUMBLE_PC_TO_PREFIX /root/${CMAKE_INSTALL_LIBDIR}/pkgconfig /root)
configure_file(cmake/tumble.pc.in ${PROJECT_BINARY_DIR}/tumble.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/tumble.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tumble/docs)
install(DIRECTORY examples/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/tumble/scenes)
install(FILES LICENSE README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
