# Installs the built tumble into a fresh prefix and builds three separate projects against
# it: C with find_package, C with pkg-config, C++17 with find_package. Each runs and checks a
# result.
#   cmake -DBUILD=dir -DSOURCE=dir -DWORK=dir -DCC=cc -DCXX=c++ -P run.cmake
file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "failed (${code}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})

foreach(consumer cmake_c cxx)
  run(${CMAKE_COMMAND} -S ${SOURCE}/${consumer} -B ${WORK}/${consumer}
      -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_C_COMPILER=${CC} -DCMAKE_CXX_COMPILER=${CXX})
  run(${CMAKE_COMMAND} --build ${WORK}/${consumer})
endforeach()
run(${WORK}/cmake_c/consumer)
run(${WORK}/cxx/consumer_cxx)

# pkg-config, the way a Makefile would: --static adds what a static libtumble needs.
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig:${prefix}/lib64/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs --static tumble
                OUTPUT_VARIABLE flags RESULT_VARIABLE code OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "pkg-config tumble failed")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CC} -std=c11 -I${SOURCE} ${SOURCE}/pkgconfig_c/main.c ${flags} -o ${WORK}/pkgconfig_consumer)
# A shared libtumble in a private prefix is found the way a user would point at it.
set(ENV{LD_LIBRARY_PATH} ${prefix}/lib:${prefix}/lib64)
run(${WORK}/pkgconfig_consumer)
