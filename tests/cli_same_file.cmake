# --out naming the scene file by another path (a symbolic link, a hard link, a path through
# "..") is refused with exit 2, and the scene file is unchanged.
#   cmake -DTUMBLE=path -DSCENE=path -DWORK=dir -P cli_same_file.cmake
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/sub)
configure_file(${SCENE} ${WORK}/scene.json COPYONLY)
file(CREATE_LINK ${WORK}/scene.json ${WORK}/symbolic.csv SYMBOLIC)
file(CREATE_LINK ${WORK}/scene.json ${WORK}/hard.csv)
foreach(out ${WORK}/symbolic.csv ${WORK}/hard.csv ${WORK}/sub/../scene.json)
  execute_process(COMMAND ${TUMBLE} run ${WORK}/scene.json --out ${out}
                  RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT code EQUAL 2 OR NOT err MATCHES "is the scene file .*refusing to overwrite it")
    message(FATAL_ERROR "--out ${out}: exit ${code}, expected 2 and a refusal:\n${err}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${SCENE} ${WORK}/scene.json
                  RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "--out ${out} changed the scene file")
  endif()
endforeach()
message(STATUS "--out naming the scene file by three other paths: refused, scene unchanged")
