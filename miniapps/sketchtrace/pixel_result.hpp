#pragma once
// One rendered pixel, in a header of its own without Kokkos: the checkpoint reader
// (checkpoint.hpp) stores these as bytes and is also built by the fuzz sub-build
// (tests/fuzz), which compiles readers without Kokkos.
#include <cstdint>

namespace rtmini::sketch {

// One rendered pixel (host/device POD; gathered across ranks as bytes).
struct PixelResult {
  float r = 0, g = 0, b = 0;
  float depth = 1e30f;
  float nx = 0, ny = 0, nz = 0;
  int object = -1;
  float edge = 0;
  std::uint32_t rays = 0;
  std::uint64_t tests = 0;
};

}  // namespace rtmini::sketch
