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

# The installed command runs as installed (no LD_LIBRARY_PATH: a shared libtumble is found
# through its run path, relative to the prefix) on an installed example scene, and the docs,
# scenes and licence are where the install promises.
foreach(file share/tumble/docs/scene-format.md share/tumble/scenes/tumbling_box.json
             share/doc/tumble/LICENSE share/doc/tumble/README.md)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "the install has no ${file}")
  endif()
endforeach()
file(READ ${prefix}/share/doc/tumble/LICENSE licence LIMIT 200)
if(NOT licence MATCHES "GNU GENERAL PUBLIC LICENSE[ \n]+Version 3")
  message(FATAL_ERROR "share/doc/tumble/LICENSE is not the GPL version 3")
endif()
unset(ENV{LD_LIBRARY_PATH})
run(${prefix}/bin/tumble check ${prefix}/share/tumble/scenes/tumbling_box.json)
run(${prefix}/bin/tumble run ${prefix}/share/tumble/scenes/tumbling_box.json --duration 0.1
    --out ${WORK}/installed_run.csv)
file(STRINGS ${WORK}/installed_run.csv rows)
list(LENGTH rows row_count)
if(NOT row_count GREATER 1)
  message(FATAL_ERROR "the installed tumble wrote no frames")
endif()

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
file(GLOB pc_files ${prefix}/lib*/pkgconfig/tumble.pc)
file(STRINGS ${pc_files} pc_licence REGEX "^License: ")
if(NOT pc_licence STREQUAL "License: GPL-3.0-or-later")
  message(FATAL_ERROR "tumble.pc says '${pc_licence}', expected License: GPL-3.0-or-later")
endif()
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
