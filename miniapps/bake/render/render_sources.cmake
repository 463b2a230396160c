# `bake render` (issue 9), included by ../CMakeLists.txt: the renderer is a library so that the
# unit tests can drive it directly; the CLI front end is compiled into the bake executable.
add_library(rtmini_bake_render STATIC ${CMAKE_CURRENT_LIST_DIR}/baked_map.cpp
                                      ${CMAKE_CURRENT_LIST_DIR}/render_map.cpp)
target_include_directories(rtmini_bake_render PUBLIC ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(rtmini_bake_render PUBLIC rtmini_bake_core)
list(APPEND BAKE_RENDER_SOURCES ${CMAKE_CURRENT_LIST_DIR}/render_mode.cpp)
list(APPEND BAKE_RENDER_LIBS rtmini_bake_render)
set(RTMINI_BAKE_HAVE_RENDER ON)
