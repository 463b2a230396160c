#pragma once
// Ray origin offset against self-intersection, sized by a floating-point error bound.
//
// Why this bound. A point that leaves a surface (a barycentric hit point, or a stored vertex)
// and the intersection test that must not find that surface again both round in proportion to
// the coordinates involved, not to the point's own coordinates:
//  - the barycentric hit point b0 p0 + b1 p1 + b2 p2 is off by at most
//    gamma(7) (|b0 p0| + |b1 p1| + |b2 p2|) per component (Pharr, Jakob, Humphreys,
//    "Physically Based Rendering", 4th ed., section 6.8), <= gamma(7) M when every coordinate
//    is at most M in magnitude;
//  - the watertight test (geometry/triangle.hpp) translates the vertices to the ray origin
//    (error <= u M), shears and forms 2D edge functions and their weighted z: the computed t of
//    the surface the ray leaves errs by about gamma(12) times the largest translated
//    coordinate, <= gamma(12) 2 M (PBRT's triangle t bound, same analysis).
// Moving the origin along the geometric normal by gamma(kOffsetRoundings) M with
// kOffsetRoundings = 32 clears both with a margin, for any ray direction (a grazing ray only
// lengthens the distance to the plane along the ray). M is the bound on every vertex
// coordinate the kernels see: DeviceMesh::coordinate_bound. It is a property of the scene,
// not of the point, so the offset also covers neighbouring triangles of other sizes and
// vertex origins (bake), where no barycentrics exist.
//
// Why recentring. M grows with the distance of the scene from the origin, and so does every
// rounding error in the kernels (a scene of size 1 at 1e6 has float coordinates 0.06 apart).
// The uploads therefore move the scene's bounding-box centre to the origin in double on the
// host (upload_mesh's `origin`, sketchtrace's build_scene): M is then half the scene's extent
// whatever its placement, and translation costs no precision at all. Scale is free as well:
// the offset is relative to M. What a precision cannot hold is a scene whose extent squared
// leaves its normal range (cross products and squared lengths underflow or overflow):
// check_representable refuses those with exit 2.
//
// The previous scheme (Wächter & Binder, Ray Tracing Gems ch. 6: 256 ulps of the point's own
// coordinates, 1/65536 absolute near the origin) sized the offset by the point's distance from
// the origin: 16 units at 1e6, and 16 times the scene at scale 1e-6.
#include <limits>

#include "rtmini/geometry/vec.hpp"

namespace rtmini {

// Higham's gamma(n) = n u / (1 - n u), u the unit roundoff of Real: the relative error bound of
// n successive roundings.
KOKKOS_INLINE_FUNCTION constexpr Real rounding_gamma(int n) {
  // 2^-24 or 2^-53 spelled out: std::numeric_limits is host-only code for nvcc.
  constexpr Real u = sizeof(Real) == sizeof(float) ? Real(5.9604644775390625e-8)
                                                   : Real(1.1102230246251565e-16);
  static_assert(u == std::numeric_limits<Real>::epsilon() / Real(2), "unit roundoff");
  return Real(n) * u / (Real(1) - Real(n) * u);
}

// Number of roundings the offset distance covers (argued above).
constexpr int kOffsetRoundings = 32;

namespace detail {
// The next representable value away from p in the direction of sign(n): the offset origin is
// never rounded back onto the surface.
KOKKOS_INLINE_FUNCTION float step_away(float q, float n) {
  if (n == 0.f) return q;
  if (q == 0.f)
    return n > 0.f ? std::numeric_limits<float>::denorm_min()
                   : -std::numeric_limits<float>::denorm_min();
  const int bits = compat::bit_cast<int>(q);
  return compat::bit_cast<float>(bits + (((q > 0.f) == (n > 0.f)) ? 1 : -1));
}
KOKKOS_INLINE_FUNCTION double step_away(double q, double n) {
  if (n == 0.0) return q;
  if (q == 0.0)
    return n > 0.0 ? std::numeric_limits<double>::denorm_min()
                   : -std::numeric_limits<double>::denorm_min();
  const long long bits = compat::bit_cast<long long>(q);
  return compat::bit_cast<double>(bits + (((q > 0.0) == (n > 0.0)) ? 1 : -1));
}
}  // namespace detail

// Distance along the normal that clears the rounding of points and intersection tests in a
// scene whose coordinates are at most `coordinate_bound` in magnitude.
KOKKOS_INLINE_FUNCTION Real offset_distance(Real coordinate_bound) {
  return rounding_gamma(kOffsetRoundings) * coordinate_bound;
}

// p: a point on a surface; n: the geometric normal (unit length) on the side the new ray
// leaves from (flip it for transmission or for the back side); coordinate_bound: the scene's
// DeviceMesh::coordinate_bound.
KOKKOS_INLINE_FUNCTION Vec3 offset_ray_origin(const Vec3& p, const Vec3& n, Real coordinate_bound) {
  const Vec3 q = p + n * offset_distance(coordinate_bound);
  return {detail::step_away(q.x, n.x), detail::step_away(q.y, n.y), detail::step_away(q.z, n.z)};
}

}  // namespace rtmini
