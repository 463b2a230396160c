#pragma once
// Warping of uniform numbers to directions and points.
#include "rtmini/geometry/vec.hpp"

namespace rtmini {

// Orthonormal basis with n as z (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017): branch-free and continuous except at n.z = -0.
struct Frame {
  Vec3 t, b, n;
  KOKKOS_INLINE_FUNCTION explicit Frame(const Vec3& nn) : n(nn) {
    const Real s = math::copysign(Real(1), n.z);
    const Real a = Real(-1) / (s + n.z);
    const Real c = n.x * n.y * a;
    t = Vec3(Real(1) + s * n.x * n.x * a, s * c, -s * n.x);
    b = Vec3(c, s + n.y * n.y * a, -n.y);
  }
  KOKKOS_INLINE_FUNCTION Vec3 to_world(const Vec3& l) const { return t * l.x + b * l.y + n * l.z; }
  KOKKOS_INLINE_FUNCTION Vec3 to_local(const Vec3& w) const {
    return {dot(w, t), dot(w, b), dot(w, n)};
  }
};

// Cosine-weighted direction in the local frame (z up), pdf = cos(theta)/pi.
KOKKOS_INLINE_FUNCTION Vec3 cosine_hemisphere(Real u1, Real u2) {
  const Real r = math::sqrt(u1);
  const Real phi = Real(2 * math::kPi) * u2;
  return {r * math::cos(phi), r * math::sin(phi), math::sqrt(math::fmax(Real(0), Real(1) - u1))};
}

// Uniform direction on the unit sphere.
KOKKOS_INLINE_FUNCTION Vec3 uniform_sphere(Real u1, Real u2) {
  const Real z = Real(1) - Real(2) * u1;
  const Real r = math::sqrt(math::fmax(Real(0), Real(1) - z * z));
  const Real phi = Real(2 * math::kPi) * u2;
  return {r * math::cos(phi), r * math::sin(phi), z};
}

// Stratum (i, j) of an n x n grid jittered by (u1, u2): a point in [0,1)^2.
KOKKOS_INLINE_FUNCTION void stratified_2d(int index, int n, Real u1, Real u2, Real& x, Real& y) {
  const int i = index % n, j = index / n;
  x = (Real(i) + u1) / Real(n);
  y = (Real(j) + u2) / Real(n);
}

// Uniform point on a triangle as barycentrics (u, v) of the 2nd and 3rd vertex;
// the square-root warp u = 1 - sqrt(r1), v = r2 sqrt(r1) of the AO-baking sample.
KOKKOS_INLINE_FUNCTION void uniform_triangle(Real r1, Real r2, Real& u, Real& v) {
  const Real s = math::sqrt(r1);
  u = Real(1) - s;
  v = r2 * s;
}

// Light-weight integer hash (used to decorrelate stratum order etc.).
KOKKOS_INLINE_FUNCTION std::uint32_t hash_u32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

}  // namespace rtmini
