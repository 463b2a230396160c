# ctest -P script: regenerate inputs/ao/spot_three.gltf (+ .bin) into OUT_DIR with GEN
# (rtmini-gen-inputs) from SCENE and require the committed copies in INPUTS byte for byte.
file(MAKE_DIRECTORY ${OUT_DIR})
execute_process(COMMAND ${GEN} gltf_instances --scene ${SCENE} -o ${OUT_DIR}/spot_three.gltf
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "rtmini-gen-inputs gltf_instances failed: ${rc}")
endif()
foreach(f spot_three.gltf spot_three.bin)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT_DIR}/${f} ${INPUTS}/${f} RESULT_VARIABLE diff)
  if(NOT diff EQUAL 0)
    message(FATAL_ERROR "${INPUTS}/${f} is not what rtmini-gen-inputs makes of ${SCENE}; regenerate it "
                        "(inputs/ao/spot_gltf.toml says how)")
  endif()
endforeach()
