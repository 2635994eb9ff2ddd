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
foreach(file share/tumble/docs/scene-format.md share/tumble/docs/scene-format.schema.json
             share/tumble/scenes/tumbling_box.json
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
# The link lines name libraries (-l) and tumble's own ${libdir}, never a path of the machine
# that built it (gcc's /usr/lib/gcc/<triplet>/12/libgomp.so was there): another machine, or
# another compiler version, would not have it.
file(STRINGS ${pc_files} pc_libs REGEX "^Libs")
foreach(line IN LISTS pc_libs)
  string(REGEX REPLACE "\\$\\{libdir\\}" "" stripped "${line}")
  if(stripped MATCHES "/")
    message(FATAL_ERROR "tumble.pc names a path on a link line: '${line}'")
  endif()
endforeach()
function(pkg_flags out)
  execute_process(COMMAND ${PKG_CONFIG} ${ARGN} tumble
                  OUTPUT_VARIABLE flags RESULT_VARIABLE code OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "pkg-config ${ARGN} tumble failed")
  endif()
  separate_arguments(flags UNIX_COMMAND "${flags}")
  set(${out} ${flags} PARENT_SCOPE)
endfunction()
pkg_flags(libdir --variable=libdir)
# A program linked by exactly what pkg-config prints starts: --static always (a static libtumble
# needs it), and plain --libs when libtumble is shared (for a static one, plain --libs leaves its
# dependencies out, as pkg-config means it to). Nothing in tumble.pc adds a run path, as in
# the distributions' .pc files: a shared libtumble in a prefix the dynamic loader does not
# search is found through LD_LIBRARY_PATH, or through a run path the program is linked with
# (docs/install.md, "Installing and embedding"), both tried below; the installed tumble command needs neither.
if(EXISTS ${libdir}/libtumble.so)
  set(link_kinds plain static)
else()
  set(link_kinds static)
endif()
foreach(kind IN LISTS link_kinds)
  if(kind STREQUAL "static")
    pkg_flags(flags --cflags --libs --static)
  else()
    pkg_flags(flags --cflags --libs)
  endif()
  set(program ${WORK}/pkgconfig_consumer_${kind})
  run(${CC} -std=c11 -I${SOURCE} ${SOURCE}/pkgconfig_c/main.c ${flags} -o ${program})
  set(ENV{LD_LIBRARY_PATH} ${libdir})
  run(${program})
  unset(ENV{LD_LIBRARY_PATH})
  run(${CC} -std=c11 -I${SOURCE} ${SOURCE}/pkgconfig_c/main.c ${flags} -Wl,-rpath,${libdir}
      -o ${program}_rpath)
  run(${program}_rpath)
endforeach()
