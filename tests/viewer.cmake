# The web viewer's end-to-end tests (miniapps/bake/viewer/tests/run.mjs): node serves the
# page on localhost, playwright-core drives Debian's headless chromium (SwiftShader WebGL).
#   viewer.playwright  the page on the bundled test maps (checks 1-6), about 25 s
#   viewer.agreement   the page against `bake render` on a freshly baked Cornell box, about 30 s
# Both exit 77 (skipped) when node_modules (npm ci) or /usr/bin/chromium are missing.
find_program(RTMINI_NODE_EXECUTABLE node)
set(_viewer_run ${PROJECT_SOURCE_DIR}/miniapps/bake/viewer/tests/run.mjs)
if(RTMINI_NODE_EXECUTABLE)
  add_test(NAME viewer.playwright COMMAND ${RTMINI_NODE_EXECUTABLE} ${_viewer_run} --checks page
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  if(TARGET bake AND TARGET rtmini_bake_render)
    add_test(NAME viewer.agreement
             COMMAND ${RTMINI_NODE_EXECUTABLE} ${_viewer_run} --checks agreement --bake
                     $<TARGET_FILE:bake>
             WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  else()
    add_test(NAME viewer.agreement COMMAND sh -c "echo 'SKIP: bake render not built'; exit 77")
  endif()
else()
  add_test(NAME viewer.playwright COMMAND sh -c "echo 'SKIP: node not found'; exit 77")
  add_test(NAME viewer.agreement COMMAND sh -c "echo 'SKIP: node not found'; exit 77")
endif()
set_tests_properties(viewer.playwright viewer.agreement PROPERTIES LABELS "viewer" SKIP_RETURN_CODE 77
                                                                   TIMEOUT 240)
