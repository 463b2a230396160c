#pragma once
// Watertight ray-triangle intersection (Woop, Benthin, Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2013): the ray is sheared so it points along
// +z, edge functions are evaluated in 2D, and exact-zero edge values are redone
// in double so rays through shared edges and vertices hit exactly one triangle.
#include "rtmini/geometry/ray.hpp"

namespace rtmini {

namespace detail {
// Edge functions must be evaluated identically (up to sign) for the two
// triangles sharing an edge; a fused multiply-add breaks that symmetry and
// leaks rays through shared edges. CUDA contracts a*b - c*d into an FMA by
// default, so the products are rounded explicitly there; host builds use
// -ffp-contract=off (set in CMake).
KOKKOS_INLINE_FUNCTION float mul_rn(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_rn(a, b);
#else
  return a * b;
#endif
}
KOKKOS_INLINE_FUNCTION double mul_rn(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dmul_rn(a, b);
#else
  return a * b;
#endif
}
}  // namespace detail

struct Triangle {
  Vec3 a, b, c;
};

// Per-ray shear constants, computed once per ray (not per triangle).
struct WatertightRay {
  Vec3 org;
  int kx, ky, kz;
  Real sx, sy, sz;

  WatertightRay() = default;  // (arrays of rays, filled ray by ray)
  // The axes by selects and loads from a small array, not branches: on random directions (AO,
  // diffuse bounces) the branches on the dominant axis mispredict often, which made this
  // ~4 % of a packet trace of the dragon's diffuse rays (perf, results/bvh/README.md). The
  // values are max_dimension(vabs(d))'s and the winding-keeping swap's, as before.
  KOKKOS_INLINE_FUNCTION WatertightRay(const Vec3& o, const Vec3& d) : org(o) {
    const Real dv[3] = {d.x, d.y, d.z};
    const Real ax = math::fabs(d.x), ay = math::fabs(d.y), az = math::fabs(d.z);
    const bool x_over_y = ax > ay;
    const Real axy = x_over_y ? ax : ay;
    kz = axy > az ? (x_over_y ? 0 : 1) : 2;
    const int next = kz == 2 ? 0 : kz + 1;
    const int after = next == 2 ? 0 : next + 1;
    const bool flip = dv[kz] < Real(0);  // keep the winding so edge signs stay consistent
    kx = flip ? after : next;
    ky = flip ? next : after;
    sz = Real(1) / dv[kz];
    sx = dv[kx] * sz;
    sy = dv[ky] * sz;
  }
};

// The watertight test from the vertices relative to the ray's origin, already permuted
// (x, y, z along the ray's kx, ky, kz): shear, edge functions, sign test, t. Shared by
// intersect_triangle and the GPU's stored-triangle walk, which load the permuted coordinates
// differently, so that both give the same bits.
KOKKOS_FORCEINLINE_FUNCTION bool intersect_permuted(const WatertightRay& r, Real Ax, Real Ay,
                                                    Real Az, Real Bx, Real By, Real Bz, Real Cx,
                                                    Real Cy, Real Cz, Real tmin, Real tmax,
                                                    Real& t_out, Real& u_out, Real& v_out) {
  const Real ax = Ax - r.sx * Az, ay = Ay - r.sy * Az;
  const Real bx = Bx - r.sx * Bz, by = By - r.sy * Bz;
  const Real cx = Cx - r.sx * Cz, cy = Cy - r.sy * Cz;
  using detail::mul_rn;
  Real U = mul_rn(cx, by) - mul_rn(cy, bx);
  Real V = mul_rn(ax, cy) - mul_rn(ay, cx);
  Real W = mul_rn(bx, ay) - mul_rn(by, ax);
  if (sizeof(Real) == 4 && (U == Real(0) || V == Real(0) || W == Real(0))) {
    U = Real(mul_rn(double(cx), double(by)) - mul_rn(double(cy), double(bx)));
    V = Real(mul_rn(double(ax), double(cy)) - mul_rn(double(ay), double(cx)));
    W = Real(mul_rn(double(bx), double(ay)) - mul_rn(double(by), double(ax)));
  }
  if ((U < Real(0) || V < Real(0) || W < Real(0)) && (U > Real(0) || V > Real(0) || W > Real(0)))
    return false;
  const Real det = U + V + W;
  if (det == Real(0)) return false;
  const Real az = r.sz * Az, bz = r.sz * Bz, cz = r.sz * Cz;
  const Real T = U * az + V * bz + W * cz;
  // Divide first, then compare t itself, so every caller (BVH, brute force,
  // any ordering of leaves) accepts exactly the same t for the same interval.
  const Real inv = Real(1) / det;
  const Real t = T * inv;
  if (!(t >= tmin && t <= tmax)) return false;
  t_out = t;
  u_out = V * inv;
  v_out = W * inv;
  return true;
}

// Returns true when the ray hits the triangle with t in (tmin, tmax); then t,
// u (weight of b) and v (weight of c) are set. Both windings are hit.
KOKKOS_INLINE_FUNCTION bool intersect_triangle(const WatertightRay& r, const Vec3& a, const Vec3& b,
                                               const Vec3& c, Real tmin, Real tmax, Real& t_out,
                                               Real& u_out, Real& v_out) {
  // Index the permuted axes through small arrays: one load each instead of a
  // compare-and-select chain per access.
  const Real A[3] = {a.x - r.org.x, a.y - r.org.y, a.z - r.org.z};
  const Real B[3] = {b.x - r.org.x, b.y - r.org.y, b.z - r.org.z};
  const Real C[3] = {c.x - r.org.x, c.y - r.org.y, c.z - r.org.z};
  return intersect_permuted(r, A[r.kx], A[r.ky], A[r.kz], B[r.kx], B[r.ky], B[r.kz], C[r.kx],
                            C[r.ky], C[r.kz], tmin, tmax, t_out, u_out, v_out);
}

// Exactly zero area in the working precision (repeated or collinear vertices). The sheared
// 2D test above can still see a sliver there after rounding, so the BVH builders store such
// a triangle as a point (never hit: U = V = W = 0) and brute force skips it.
KOKKOS_INLINE_FUNCTION bool is_zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = cross(b - a, c - a);
  return n.x == Real(0) && n.y == Real(0) && n.z == Real(0);
}

KOKKOS_INLINE_FUNCTION Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  return normalize(cross(b - a, c - a));
}

KOKKOS_INLINE_FUNCTION Real triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return Real(0.5) * length(cross(b - a, c - a));
}

// Point from barycentrics: more accurate than org + t * dir for far hits
// (Wächter & Binder, Ray Tracing Gems ch. 6).
KOKKOS_INLINE_FUNCTION Vec3 barycentric_point(const Vec3& a, const Vec3& b, const Vec3& c, Real u,
                                              Real v) {
  return a * (Real(1) - u - v) + b * u + c * v;
}

}  // namespace rtmini
