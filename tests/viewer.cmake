# The web viewer's end-to-end test (miniapps/bake/viewer/tests/run.mjs): node serves the
# page on localhost, playwright-core drives Debian's headless chromium (SwiftShader WebGL).
# It exits 77 (skipped) when node_modules (npm ci) or /usr/bin/chromium are missing.
find_program(RTMINI_NODE_EXECUTABLE node)
if(RTMINI_NODE_EXECUTABLE)
  add_test(NAME viewer.playwright
           COMMAND ${RTMINI_NODE_EXECUTABLE} miniapps/bake/viewer/tests/run.mjs
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
else()
  add_test(NAME viewer.playwright COMMAND sh -c "echo 'SKIP: node not found'; exit 77")
endif()
set_tests_properties(viewer.playwright PROPERTIES LABELS "viewer" SKIP_RETURN_CODE 77 TIMEOUT 240)
