#pragma once
// Compile-time numeric precision: float by default, double with RTMINI_DOUBLE=ON,
// so the cost and error of each can be measured rather than guessed.
#include <cstdint>

namespace rtmini {
#ifdef RTMINI_USE_DOUBLE
using Real = double;
#else
using Real = float;
#endif
}  // namespace rtmini
