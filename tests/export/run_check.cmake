# One export check, run by ctest: the scene is exported with examples/export_scene to the
# formats the check needs, then the independent reader checks the files.
#   -DEXPORT=export_scene -DSCENE=x.json -DOUT=dir -DKIND=npz|gltf|fidelity|validate
#   -DPYTHON=python -DCHECKS=tests/export -DNODE=node -DNODE_MODULES=dir
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code)
  if(NOT code EQUAL 0)
    string(REPLACE ";" " " line "${ARGN}")
    message(FATAL_ERROR "failed (${code}): ${line}")
  endif()
endfunction()

get_filename_component(name ${SCENE} NAME_WE)
file(MAKE_DIRECTORY ${OUT})
set(base ${OUT}/${name})
if(KIND STREQUAL "npz")
  run(${EXPORT} ${SCENE} ${base}.csv)
  run(${EXPORT} ${SCENE} ${base}.npz)
  run(${PYTHON} ${CHECKS}/check_npz.py ${base}.npz ${base}.csv)
elseif(KIND STREQUAL "gltf")
  run(${EXPORT} ${SCENE} ${base}.csv)
  run(${EXPORT} ${SCENE} ${base}.glb)
  run(${EXPORT} ${SCENE} ${base}.gltf)
  run(${EXPORT} ${SCENE} ${base}-linear.glb 0 linear)
  run(${PYTHON} ${CHECKS}/check_gltf.py ${base}.glb ${base}.csv)
  run(${PYTHON} ${CHECKS}/check_gltf.py ${base}.gltf ${base}.csv)
  run(${PYTHON} ${CHECKS}/check_gltf.py ${base}-linear.glb ${base}.csv)
elseif(KIND STREQUAL "fidelity")
  # keys at 24 fps; the reference is the same run at 16 x 24 = 384 fps (an adaptive method:
  # frames come from its interpolant, so the frame rate does not change the solution)
  run(${EXPORT} ${SCENE} ${base}.csv 24)
  run(${EXPORT} ${SCENE} ${base}.glb 24)
  run(${EXPORT} ${SCENE} ${base}-linear.glb 24 linear)
  run(${EXPORT} ${SCENE} ${base}-reference.csv 384)
  run(${PYTHON} ${CHECKS}/check_gltf.py ${base}.glb ${base}.csv --reference ${base}-reference.csv
      --max-degrees 0.05)
  # LINEAR is measured and printed for the docs; it is not held to the cubic's bound
  run(${PYTHON} ${CHECKS}/check_gltf.py ${base}-linear.glb ${base}.csv
      --reference ${base}-reference.csv)
elseif(KIND STREQUAL "validate")
  run(${EXPORT} ${SCENE} ${base}.glb)
  run(${EXPORT} ${SCENE} ${base}.gltf)
  run(${EXPORT} ${SCENE} ${base}-linear.glb 0 linear)
  set(ENV{NODE_PATH} ${NODE_MODULES})
  run(${NODE} ${CHECKS}/validate_gltf.js ${base}.glb ${base}.gltf ${base}-linear.glb)
else()
  message(FATAL_ERROR "KIND: ${KIND}")
endif()
