#pragma once
// Axis-aligned boxes and the NaN-safe slab test.
#include "rtmini/geometry/vec.hpp"

namespace rtmini {

struct Aabb {
  Vec3 lo{Real(1e30)};
  Vec3 hi{Real(-1e30)};

  KOKKOS_INLINE_FUNCTION void expand(const Vec3& p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  KOKKOS_INLINE_FUNCTION void expand(const Aabb& b) {
    lo = vmin(lo, b.lo);
    hi = vmax(hi, b.hi);
  }
  KOKKOS_INLINE_FUNCTION bool empty() const {
    return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z);
  }
  KOKKOS_INLINE_FUNCTION Vec3 extent() const { return empty() ? Vec3(0) : hi - lo; }
  KOKKOS_INLINE_FUNCTION Vec3 center() const { return (lo + hi) * Real(0.5); }
  KOKKOS_INLINE_FUNCTION Real surface_area() const {
    if (empty()) return Real(0);
    const Vec3 e = hi - lo;
    return Real(2) * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  KOKKOS_INLINE_FUNCTION Real diagonal() const { return length(extent()); }
};

// Reduction functor support so Kokkos::parallel_reduce can build a box.
struct AabbUnion {
  KOKKOS_INLINE_FUNCTION void operator()(Aabb& dst, const Aabb& src) const { dst.expand(src); }
};

// Per-ray constants for the slab test. A zero direction component gets a huge
// finite reciprocal instead of inf, so (lo - org) * inv is never 0 * inf = NaN:
// a ray lying in a slab plane counts as inside (conservative), one outside misses.
KOKKOS_INLINE_FUNCTION Real safe_reciprocal(Real d) {
  constexpr Real kHuge = sizeof(Real) == 4 ? Real(1e30) : Real(1e300);
  return d == Real(0) ? math::copysign(kHuge, d) : Real(1) / d;
}

struct RaySlab {
  Vec3 org;
  Vec3 inv;
  KOKKOS_INLINE_FUNCTION RaySlab(const Vec3& o, const Vec3& d)
      : org(o), inv(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z)) {}
};

// gamma(3) from Pharr et al.; widening tmax by (1 + 2*gamma(3)) keeps the box
// test conservative so traversal never misses a triangle that the watertight
// test would hit (Ize 2013).
KOKKOS_INLINE_FUNCTION constexpr Real slab_widening() {
  constexpr Real eps = sizeof(Real) == 4 ? Real(5.96046448e-8) : Real(1.1102230246251565e-16);
  return Real(1) + Real(2) * (3 * eps) / (1 - 3 * eps);
}

KOKKOS_INLINE_FUNCTION bool slab_test(const RaySlab& r, const Vec3& lo, const Vec3& hi, Real tmin,
                                      Real tmax, Real& tenter) {
  Real t0 = (lo.x - r.org.x) * r.inv.x, t1 = (hi.x - r.org.x) * r.inv.x;
  Real near = t0 < t1 ? t0 : t1, far = t0 < t1 ? t1 : t0;
  t0 = (lo.y - r.org.y) * r.inv.y;
  t1 = (hi.y - r.org.y) * r.inv.y;
  Real n = t0 < t1 ? t0 : t1, f = t0 < t1 ? t1 : t0;
  near = n > near ? n : near;
  far = f < far ? f : far;
  t0 = (lo.z - r.org.z) * r.inv.z;
  t1 = (hi.z - r.org.z) * r.inv.z;
  n = t0 < t1 ? t0 : t1;
  f = t0 < t1 ? t1 : t0;
  near = n > near ? n : near;
  far = f < far ? f : far;
  near = tmin > near ? tmin : near;
  // Widen after clamping to tmax too: a closest hit found earlier sets tmax,
  // and a triangle lying on this box's face may be hit at t = near - 1 ulp.
  far = (tmax < far ? tmax : far) * slab_widening();
  tenter = near;
  return near <= far;
}

}  // namespace rtmini
