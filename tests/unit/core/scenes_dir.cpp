#include "test_space.hpp"

namespace rtmini::test {
const char* scenes_dir() { return RTMINI_SCENES_DIR; }
}  // namespace rtmini::test
