#pragma once
// Scale-aware ray origin offset against self-intersection (Wächter & Binder,
// "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems
// ch. 6): move the point along the normal by a fixed number of ulps of its own
// coordinates, so the offset grows with distance from the origin; near the
// origin, where ulps are tiny, fall back to a small absolute step.
#include "rtmini/geometry/vec.hpp"

namespace rtmini {

namespace detail {
KOKKOS_INLINE_FUNCTION float offset_coord(float p, float n) {
  constexpr float kOrigin = 1.0f / 32.0f, kFloatScale = 1.0f / 65536.0f, kIntScale = 256.0f;
  const int of = static_cast<int>(kIntScale * n);
  const int bits = compat::bit_cast<int>(p);
  const float moved = compat::bit_cast<float>(bits + (p < 0.f ? -of : of));
  return math::fabs(p) < kOrigin ? p + kFloatScale * n : moved;
}
// Same relative offset in double: 2^29 more ulps per unit of float ulp.
KOKKOS_INLINE_FUNCTION double offset_coord(double p, double n) {
  constexpr double kOrigin = 1.0 / 32.0, kFloatScale = 1.0 / 65536.0;
  constexpr double kIntScale = 256.0 * 536870912.0;
  const long long of = static_cast<long long>(kIntScale * n);
  const long long bits = compat::bit_cast<long long>(p);
  const double moved = compat::bit_cast<double>(bits + (p < 0.0 ? -of : of));
  return math::fabs(p) < kOrigin ? p + kFloatScale * n : moved;
}
}  // namespace detail

// p: a point on a surface; n: the geometric normal (unit length) on the side the
// new ray leaves from (flip it for transmission or for the back side).
KOKKOS_INLINE_FUNCTION Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
  return {detail::offset_coord(p.x, n.x), detail::offset_coord(p.y, n.y),
          detail::offset_coord(p.z, n.z)};
}

}  // namespace rtmini
