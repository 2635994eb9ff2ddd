# Runs the same scene twice and requires byte-identical output.
#   cmake -DTUMBLE=path -DSCENE=path -DOUT=dir [-DARGS=a|b] -P cli_deterministic.cmake
string(REPLACE "|" ";" extra "${ARGS}")
foreach(run IN ITEMS first second)
  execute_process(COMMAND ${TUMBLE} run ${SCENE} ${extra} --out ${OUT}/${run}.csv
                  RESULT_VARIABLE code ERROR_QUIET)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "run ${run} exited with ${code}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/first.csv ${OUT}/second.csv
                RESULT_VARIABLE differ)
if(differ)
  message(FATAL_ERROR "two runs of ${SCENE} gave different output")
endif()
file(SIZE ${OUT}/first.csv bytes)
message(STATUS "two runs of ${SCENE}: identical, ${bytes} bytes")
