# ctest install.consumer: install this build into a fresh prefix, move the prefix (the package
# must be relocatable), then configure, build and run tests/install/consumer against it with
# nothing but CMAKE_PREFIX_PATH=<prefix>; rtminiConfig.cmake finds every dependency itself.
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCXX=... -P run.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR CXX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run.cmake: -D${var}= is required")
  endif()
endforeach()

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (${rc})\n${out}\n${err}")
  endif()
  message(STATUS "install test: ${what}: ok")
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
run_step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/staged)
file(RENAME ${WORK_DIR}/staged ${WORK_DIR}/prefix)
foreach(f lib/cmake/rtmini/rtminiConfig.cmake lib/cmake/rtmini/rtminiConfigVersion.cmake
          lib/cmake/rtmini/rtminiTargets.cmake include/rtmini/bvh/traverse.hpp
          share/rtmini/inputs/meshes/CornellBox-Original.obj)
  if(NOT EXISTS ${WORK_DIR}/prefix/${f})
    message(FATAL_ERROR "install test: ${f} not installed")
  endif()
endforeach()
file(READ ${WORK_DIR}/prefix/lib/cmake/rtmini/rtminiTargets.cmake targets)
if(targets MATCHES "${SOURCE_DIR}|${BUILD_DIR}")
  message(FATAL_ERROR "install test: the exported targets name the source or build tree")
endif()
run_step("configure consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/install/consumer
         -B ${WORK_DIR}/consumer -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
run_step("build consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run_step("run consumer" ${WORK_DIR}/consumer/trace_one_mesh)
message(STATUS "${last_output}")
