# One export check, run by ctest: the scene is exported with examples/export_scene to the
# formats the check needs, then the independent reader checks the files.
#   -DEXPORT=export_scene -DSCENE=x.json -DOUT=dir -DKIND=npz|gltf|fidelity|validate|usd|usd_fidelity
#   -DPYTHON=python -DCHECKS=tests/export -DNODE=node -DNODE_MODULES=dir
#   usd_fidelity: -DFPS=scene's fps -DFACTOR=reference rate / FPS
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
elseif(KIND STREQUAL "usd")
  run(${EXPORT} ${SCENE} ${base}.csv)
  run(${EXPORT} ${SCENE} ${base}.usda)
  run(${PYTHON} ${CHECKS}/check_usd.py ${base}.usda ${base}.csv --scene ${SCENE})
elseif(KIND STREQUAL "usd_fidelity")
  # the reference is the same run at FACTOR x the frame rate: an adaptive method's frames come
  # from its interpolant, and a fixed step that divides the reference's frame interval takes the
  # same steps, so the reference is the simulation between frames; USD's slerp between the
  # samples is held to 0.1 degree of it
  math(EXPR reference_fps "${FPS} * ${FACTOR}")
  run(${EXPORT} ${SCENE} ${base}-frames.csv)
  run(${EXPORT} ${SCENE} ${base}.usda)
  run(${EXPORT} ${SCENE} ${base}-slerp.usda 0 linear)
  run(${EXPORT} ${SCENE} ${base}-reference.csv ${reference_fps})
  run(${PYTHON} ${CHECKS}/check_usd.py ${base}.usda ${base}-frames.csv --scene ${SCENE}
      --reference ${base}-reference.csv --max-degrees 0.1)
  # samples at the frames only are measured and printed for the docs, not held to the bound
  run(${PYTHON} ${CHECKS}/check_usd.py ${base}-slerp.usda ${base}-frames.csv --scene ${SCENE}
      --reference ${base}-reference.csv --max-degrees 360)
else()
  message(FATAL_ERROR "KIND: ${KIND}")
endif()
