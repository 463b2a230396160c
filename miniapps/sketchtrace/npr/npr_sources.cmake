# sketchtrace's hand-drawn post-process. Included by miniapps/sketchtrace/CMakeLists.txt
# (which adds SKETCH_NPR_SOURCES to the renderer) and by tests/unit/npr; the
# targets below are defined once, whoever includes this first.
set(RTMINI_SKETCH_NPR_DIR ${CMAKE_CURRENT_LIST_DIR})
set(_rtmini_npr_sources
    ${RTMINI_SKETCH_NPR_DIR}/apply_passes.cpp
    ${RTMINI_SKETCH_NPR_DIR}/device_image.cpp
    ${RTMINI_SKETCH_NPR_DIR}/edge_pass.cpp
    ${RTMINI_SKETCH_NPR_DIR}/hatching.cpp
    ${RTMINI_SKETCH_NPR_DIR}/npr_config.cpp
    ${RTMINI_SKETCH_NPR_DIR}/paper.cpp
    ${RTMINI_SKETCH_NPR_DIR}/paper_pass.cpp
    ${RTMINI_SKETCH_NPR_DIR}/post_inputs.cpp
    ${RTMINI_SKETCH_NPR_DIR}/quality.cpp
    ${RTMINI_SKETCH_NPR_DIR}/tone_pass.cpp)
list(APPEND SKETCH_NPR_SOURCES ${_rtmini_npr_sources})
set(RTMINI_SKETCH_HAVE_NPR ON)

if(NOT TARGET rtmini_sketch_npr)
  # The same sources as a library, for the post-process CLI and the unit tests
  # (the renderer may link it instead of compiling SKETCH_NPR_SOURCES itself).
  add_library(rtmini_sketch_npr STATIC ${_rtmini_npr_sources})
  target_include_directories(rtmini_sketch_npr PUBLIC ${RTMINI_SKETCH_NPR_DIR})
  target_link_libraries(rtmini_sketch_npr PUBLIC rtmini::common)

  add_executable(sketchtrace-post ${RTMINI_SKETCH_NPR_DIR}/post_main.cpp)
  target_link_libraries(sketchtrace-post PRIVATE rtmini_sketch_npr)
  set_target_properties(sketchtrace-post PROPERTIES RUNTIME_OUTPUT_DIRECTORY
                                                    ${PROJECT_BINARY_DIR}/miniapps/sketchtrace)
endif()
