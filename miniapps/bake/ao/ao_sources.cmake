# bake --mode ao sources, for the bake executable (miniapps/bake/CMakeLists.txt),
# the standalone rtmini-ao and the rtmini_unit_ao tests. Link ${BAKE_AO_LIBS}.
find_package(Eigen3 REQUIRED NO_MODULE)
set(BAKE_AO_DIR ${CMAKE_CURRENT_LIST_DIR})
list(APPEND BAKE_AO_SOURCES
     ${BAKE_AO_DIR}/affine.cpp
     ${BAKE_AO_DIR}/ao_mode.cpp
     ${BAKE_AO_DIR}/ao_options.cpp
     ${BAKE_AO_DIR}/ao_output.cpp
     ${BAKE_AO_DIR}/ao_scene.cpp
     ${BAKE_AO_DIR}/ao_trace.cpp
     ${BAKE_AO_DIR}/device_scene.cpp
     ${BAKE_AO_DIR}/gltf_writer.cpp
     ${BAKE_AO_DIR}/sample_plan.cpp
     ${BAKE_AO_DIR}/vertex_mapping.cpp)
set(BAKE_AO_LIBS Eigen3::Eigen)
set(RTMINI_BAKE_HAVE_AO ON)
