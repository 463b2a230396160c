#pragma once
// The spherical Fibonacci point set of N points (the baking paper's viewpoints):
// z_i = 1 - (2 i + 1) / N, phi_i = 2 pi frac(i / golden ratio).
#include "rtmini/geometry/vec.hpp"

namespace rtmini {

inline constexpr double kGoldenRatio = 1.6180339887498948482;

KOKKOS_INLINE_FUNCTION Vec3 fibonacci_point(int i, int n) {
  const double z = 1.0 - (2.0 * i + 1.0) / n;
  const double r = math::sqrt(math::fmax(0.0, 1.0 - z * z));
  const double f = i / kGoldenRatio;
  const double phi = 2.0 * math::kPi * (f - math::floor(f));
  return {Real(r * math::cos(phi)), Real(r * math::sin(phi)), Real(z)};
}

}  // namespace rtmini
