#pragma once
// Iterative BVH traversal with a short fixed stack (no recursion, GPU-safe):
// closest hit with a deterministic tie-break (equal t -> lower triangle id, so
// results match the brute-force reference exactly) and any hit for shadow/AO.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>
#if defined(__GNUC__) && !defined(__CUDACC__) && defined(__SSE__)
#include <immintrin.h>
#endif

#include "rtmini/bvh/bvh.hpp"
#include "rtmini/bvh/traverse_gpu.hpp"

namespace rtmini::bvh {

// Statistics a caller may ask for (ray-primitive tests per ray against brute force).
struct TraversalStats {
  std::uint32_t nodes = 0;
  std::uint32_t tests = 0;
};

// Rays per packet of the packet traversal (closest_hit_packet, any_hit_packet below).
inline constexpr int kPacketSize = 8;

namespace detail {

template <class BvhT, bool kAnyHit, bool kStats>
KOKKOS_INLINE_FUNCTION bool traverse(const BvhT& bvh, const Ray& ray, Hit& hit,
                                     TraversalStats* stats) {
  if (bvh.num_prims == 0) return false;
  const WatertightRay wr(ray.org, ray.dir);
  const RaySlab rs(ray.org, ray.dir);
  Real tmax = ray.tmax;
  std::uint32_t stack[kStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  bool found = false;
  while (true) {
    const BvhNode& nd = bvh.nodes(node);
    if (kStats) ++stats->nodes;
    Real t0, t1;
    bool h0 = slab_test(rs, Vec3(nd.lo_x[0], nd.lo_y[0], nd.lo_z[0]),
                        Vec3(nd.hi_x[0], nd.hi_y[0], nd.hi_z[0]), ray.tmin, tmax, t0);
    bool h1 = slab_test(rs, Vec3(nd.lo_x[1], nd.lo_y[1], nd.lo_z[1]),
                        Vec3(nd.hi_x[1], nd.hi_y[1], nd.hi_z[1]), ray.tmin, tmax, t1);
    const std::uint32_t c[2] = {nd.child[0], nd.child[1]};
    bool hk[2] = {h0, h1};
    for (int k = 0; k < 2; ++k) {
      if (!hk[k] || !is_leaf(c[k])) continue;
      hk[k] = false;
      if (c[k] == kEmptyLeaf) continue;
      const std::uint32_t first = leaf_first(c[k]), end = first + leaf_count(c[k]);
      for (std::uint32_t i = first; i < end; ++i) {
        const Triangle& tri = bvh.tris(i);
        if (kStats) ++stats->tests;
        Real t, u, v;
        if (!intersect_triangle(wr, tri.a, tri.b, tri.c, ray.tmin, tmax, t, u, v)) continue;
        const int id = bvh.prim(i);
        if (kAnyHit) {
          hit.t = t;
          hit.u = u;
          hit.v = v;
          hit.prim = id;
          return true;
        }
        if (t < tmax || id < hit.prim || !found) {
          tmax = t;
          hit.t = t;
          hit.u = u;
          hit.v = v;
          hit.prim = id;
          found = true;
        }
      }
    }
    h0 = hk[0];
    h1 = hk[1];
    if (h0 && h1) {
      const bool first0 = t0 <= t1;
      stack[sp++] = first0 ? c[1] : c[0];
      node = first0 ? c[0] : c[1];
    } else if (h0) {
      node = c[0];
    } else if (h1) {
      node = c[1];
    } else {
      if (sp == 0) break;
      node = stack[--sp];
    }
  }
  return found;
}

#if defined(__GNUC__) && !defined(__CUDACC__)
// kWidth box tests at once with GCC/Clang vector extensions (SSE/AVX/NEON as available).
typedef Real RealLanes __attribute__((vector_size(kWidth * sizeof(Real))));
typedef std::conditional_t<sizeof(Real) == 4, std::int32_t, std::int64_t> LaneInt;
typedef LaneInt IntLanes __attribute__((vector_size(kWidth * sizeof(Real))));
static_assert(kMaxLeafSize == kWidth, "leaf lanes share the node lanes' vector type");
static_assert(offsetof(TriangleLanes, cz) == 8 * kMaxLeafSize * sizeof(Real),
              "TriangleLanes: nine rows a.x .. c.z, one after another");

__attribute__((always_inline)) inline RealLanes load_lanes(const Real* p) {
  RealLanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// A row of kLanes values (8, or 4 of a compact leaf) in the low lanes, zeros above.
template <int kLanes>
__attribute__((always_inline)) inline RealLanes load_row(const Real* p) {
  if constexpr (kLanes == kWidth) return load_lanes(p);
#if defined(__AVX__)
  // One 128-bit load, zero-extended (a memcpy into a zeroed vector went through the stack: a
  // store-forwarding stall per row).
  if constexpr (sizeof(Real) == 4 && kLanes == 4) {
    // (the cast is a no-op here; it keeps the double build's discarded branch well-formed)
    const __m256 w = _mm256_zextps128_ps256(_mm_loadu_ps(reinterpret_cast<const float*>(p)));
    RealLanes v;
    std::memcpy(&v, &w, sizeof v);
    return v;
  }
#endif
  RealLanes v{};
  std::memcpy(&v, p, kLanes * sizeof(Real));
  return v;
}

// One bit per lane of a comparison result (all ones = true).
__attribute__((always_inline)) inline int lane_bits(const IntLanes& m) {
#if defined(__AVX__)
  if constexpr (sizeof(Real) == 4 && kWidth == 8) {
    __m256 v;
    std::memcpy(&v, &m, sizeof v);
    return _mm256_movemask_ps(v);
  }
#endif
  int mask = 0;
  for (int k = 0; k < kWidth; ++k) mask |= (m[k] != 0 ? 1 : 0) << k;
  return mask;
}

// The lanes a leaf of `count` triangles uses.
__attribute__((always_inline)) inline IntLanes used_lanes(int count) {
  IntLanes iota;
  for (int k = 0; k < kWidth; ++k) iota[k] = k;
  return iota < LaneInt(count);
}

struct LeafLaneHits {
  int hit = 0;   // lanes hit within [tmin, tmax]
  int redo = 0;  // lanes with an exactly-zero edge function: the scalar test redoes them in double
  RealLanes t, u, v;
};

// intersect_triangle on every lane of a leaf at once (rows of kLanes values from `rows`). Each
// lane runs the scalar test's operations in the same order (and -ffp-contract=off keeps products
// unfused), so t, u and v are bit for bit the scalar results; only the double-precision redo of
// zero edge functions is left to the scalar test (flagged in `redo`).
// `rel(vertex, axis)` = the leaf's row of that vertex coordinate minus the ray origin's (the
// first operation of the scalar test, so both forms below give the same bits).
template <class RelativeRow>
__attribute__((always_inline)) inline LeafLaneHits watertight_lanes_relative(RelativeRow rel,
                                                                             int count,
                                                                             const WatertightRay& r,
                                                                             Real tmin, Real tmax) {
  const RealLanes Az = rel(0, r.kz), Bz = rel(1, r.kz), Cz = rel(2, r.kz);
  const RealLanes ax = rel(0, r.kx) - r.sx * Az;
  const RealLanes ay = rel(0, r.ky) - r.sy * Az;
  const RealLanes bx = rel(1, r.kx) - r.sx * Bz;
  const RealLanes by = rel(1, r.ky) - r.sy * Bz;
  const RealLanes cx = rel(2, r.kx) - r.sx * Cz;
  const RealLanes cy = rel(2, r.ky) - r.sy * Cz;
  const RealLanes U = cx * by - cy * bx;
  const RealLanes V = ax * cy - ay * cx;
  const RealLanes W = bx * ay - by * ax;
  const IntLanes used = used_lanes(count);
  const RealLanes zero{};
  IntLanes redo = used & ((U == zero) | (V == zero) | (W == zero));
  if (sizeof(Real) != 4) redo = IntLanes{};
  const IntLanes mixed =
      ((U < zero) | (V < zero) | (W < zero)) & ((U > zero) | (V > zero) | (W > zero));
  const RealLanes det = U + V + W;
  const RealLanes T = U * (r.sz * Az) + V * (r.sz * Bz) + W * (r.sz * Cz);
  // Lanes the scalar test rejects before dividing divide by one instead: no 0/0 or 0 * inf NaN
  // there (the unit tests trap invalid operations), and their t is masked out anyway.
  const IntLanes divide = ~mixed & (det != zero);
  const RealLanes inv = Real(1) / (divide ? det : zero + Real(1));
  LeafLaneHits out;
  out.t = T * inv;
  out.u = V * inv;
  out.v = W * inv;
  const IntLanes in_range = (out.t >= zero + tmin) & (out.t <= zero + tmax);
  out.hit = lane_bits(used & ~redo & divide & in_range);
  out.redo = lane_bits(redo);
  return out;
}

template <int kLanes>
__attribute__((always_inline)) inline LeafLaneHits watertight_lanes(const Real* rows, int count,
                                                                    const WatertightRay& r,
                                                                    Real tmin, Real tmax) {
  // Rows of the leaf by the ray's axis permutation: vertex v's axis k lies at row 3 v + k.
  auto rel = [&](int vertex, int axis) {
    return load_row<kLanes>(rows + (3 * vertex + axis) * kLanes) - r.org[axis];
  };
  return watertight_lanes_relative(rel, count, r, tmin, tmax);
}

// A leaf's nine rows relative to an origin that several rays share (a packet of AO rays from one
// point): subtracted once per leaf instead of once per ray.
struct RelativeRows {
  RealLanes row[9];
  template <int kLanes>
  __attribute__((always_inline)) void fill(const Real* rows, const Vec3& org) {
    for (int vertex = 0; vertex < 3; ++vertex)
      for (int axis = 0; axis < 3; ++axis)
        row[3 * vertex + axis] = load_row<kLanes>(rows + (3 * vertex + axis) * kLanes) - org[axis];
  }
  __attribute__((always_inline)) LeafLaneHits test(int count, const WatertightRay& r, Real tmin,
                                                   Real tmax) const {
    auto rel = [&](int vertex, int axis) { return row[3 * vertex + axis]; };
    return watertight_lanes_relative(rel, count, r, tmin, tmax);
  }
};

__attribute__((always_inline)) inline int wide_box_test(const WideNode& nd, bool neg_x, bool neg_y,
                                                        bool neg_z, Real ox, Real oy, Real oz,
                                                        const Vec3& inv, Real tmin, Real tmax,
                                                        Real* tn) {
  RealLanes lx, ly, lz, hx, hy, hz;
  std::memcpy(&lx, neg_x ? nd.hi_x : nd.lo_x, sizeof lx);
  std::memcpy(&hx, neg_x ? nd.lo_x : nd.hi_x, sizeof hx);
  std::memcpy(&ly, neg_y ? nd.hi_y : nd.lo_y, sizeof ly);
  std::memcpy(&hy, neg_y ? nd.lo_y : nd.hi_y, sizeof hy);
  std::memcpy(&lz, neg_z ? nd.hi_z : nd.lo_z, sizeof lz);
  std::memcpy(&hz, neg_z ? nd.lo_z : nd.hi_z, sizeof hz);
  const RealLanes a = (lx - ox) * inv.x, b = (ly - oy) * inv.y, c = (lz - oz) * inv.z;
  const RealLanes d = (hx - ox) * inv.x, e = (hy - oy) * inv.y, f = (hz - oz) * inv.z;
  RealLanes near = a > b ? a : b;
  near = c > near ? c : near;
  const RealLanes vmin = RealLanes{} + tmin;
  near = vmin > near ? vmin : near;
  RealLanes far = d < e ? d : e;
  far = f < far ? f : far;
  far = far * slab_widening();
  const RealLanes vmax = RealLanes{} + tmax * slab_widening();
  far = vmax < far ? vmax : far;
  std::memcpy(tn, &near, sizeof near);
  // The lane mask in one instruction where the target has it, else lane by lane.
#if defined(__AVX__)
  if constexpr (sizeof(Real) == 4 && kWidth == 8) {
    __m256 n8, f8;
    std::memcpy(&n8, &near, sizeof n8);
    std::memcpy(&f8, &far, sizeof f8);
    return _mm256_movemask_ps(_mm256_cmp_ps(n8, f8, _CMP_LE_OQ));
  }
#endif
#if defined(__SSE__)
  if constexpr (sizeof(Real) == 4 && kWidth == 4) {
    __m128 n4, f4;
    std::memcpy(&n4, &near, sizeof n4);
    std::memcpy(&f4, &far, sizeof f4);
    return _mm_movemask_ps(_mm_cmple_ps(n4, f4));
  }
#endif
  const IntLanes hit = near <= far;
  int mask = 0;
  for (int k = 0; k < kWidth; ++k) mask |= (hit[k] != 0 ? 1 : 0) << k;
  return mask;
}
#else
KOKKOS_INLINE_FUNCTION int wide_box_test(const WideNode& nd, bool neg_x, bool neg_y, bool neg_z,
                                         Real ox, Real oy, Real oz, const Vec3& inv, Real tmin,
                                         Real tmax, Real* tn) {
  const Real* nx = neg_x ? nd.hi_x : nd.lo_x;
  const Real* fx = neg_x ? nd.lo_x : nd.hi_x;
  const Real* ny = neg_y ? nd.hi_y : nd.lo_y;
  const Real* fy = neg_y ? nd.lo_y : nd.hi_y;
  const Real* nz = neg_z ? nd.hi_z : nd.lo_z;
  const Real* fz = neg_z ? nd.lo_z : nd.hi_z;
  int mask = 0;
  for (int k = 0; k < kWidth; ++k) {
    const Real a = (nx[k] - ox) * inv.x, b = (ny[k] - oy) * inv.y, c = (nz[k] - oz) * inv.z;
    const Real d = (fx[k] - ox) * inv.x, e = (fy[k] - oy) * inv.y, f = (fz[k] - oz) * inv.z;
    Real near = a > b ? a : b;
    near = c > near ? c : near;
    near = tmin > near ? tmin : near;
    Real far = d < e ? d : e;
    far = f < far ? f : far;
    far = far * slab_widening();
    const Real lim = tmax * slab_widening();
    far = lim < far ? lim : far;
    tn[k] = near;
    mask |= (near <= far ? 1 : 0) << k;
  }
  return mask;
}
#endif

// The ray's constants for the wide box tests, computed once per ray.
struct WideRay {
  Vec3 inv;      // safe reciprocal of the direction
  Vec3 org;      // origin (robust test)
  Vec3 org_inv;  // fl(org * inv) per axis (FMA test)
  Real slack;    // S of the FMA test: its absolute widening of far, in t
  bool neg_x, neg_y, neg_z;
  WideRay() = default;  // (a packet's array, filled ray by ray)
  KOKKOS_INLINE_FUNCTION explicit WideRay(const Ray& ray)
      : inv(safe_reciprocal(ray.dir.x), safe_reciprocal(ray.dir.y), safe_reciprocal(ray.dir.z)),
        org(ray.org),
        org_inv(ray.org.x * inv.x, ray.org.y * inv.y, ray.org.z * inv.z),
        neg_x(inv.x < 0),
        neg_y(inv.y < 0),
        neg_z(inv.z < 0) {
    // Plain comparisons, not fmax (a libm call per use here: measurable on short rays).
    const Real ax = math::fabs(org_inv.x), ay = math::fabs(org_inv.y), az = math::fabs(org_inv.z);
    const Real axy = ax > ay ? ax : ay;
    const Real m = az > axy ? az : axy;
    slack = kFmaSlackPerOrgInv * m + kFmaSlackFloor;
  }
  // Relative 4u and the subnormal floor of the proof below (float).
  static constexpr Real kFmaSlackPerOrgInv = Real(2.384185791015625e-7);  // 2^-22
  static constexpr Real kFmaSlackFloor = Real(1.1754943508222875e-38);    // 2^-126
};

// ---- The FMA box test (host, AVX + FMA, float) -------------------------------------------------
// The robust test above takes a subtraction and a multiplication per plane, (p - o) * inv, and
// widens far by w = slab_widening(). Embree's takes one fused multiply-subtract on the ray's
// precomputed o * inv. That form is not relative-accurate (p close to o, |o| large: cancellation),
// so it gets its own widening: far' = fma(far, W, S), with W a constant and S a per-ray bound.
// Claim: every box (and every closest-hit cull, lanes_not_after) the robust test accepts, the FMA
// test accepts too, so every guarantee of the robust test (issue 7: nothing the watertight
// triangle test hits is lost) carries over. Proof, u = 2^-24 (unit roundoff), gamma2 = 2u/(1-2u),
// one plane p of axis k, inv = the ray's (rounded) reciprocal, tau = (p - o) * inv exactly:
//   robust: a_o = fl(fl(p - o) * inv)          => |a_o - tau| <= gamma2 |tau|
//   FMA:    a_n = fl(p * inv - fl(o * inv))     => |a_n - tau| <= u |tau| + mu,
//           mu = u (1 + u) max_k |o_k inv_k|   (the rounding of o * inv, absolute: the
//           cancellation)
// From these, with c1 = (u + gamma2) / (1 - gamma2) (~3u): a_n <= a_o + c1 |a_o| + mu and
// a_n >= a_o - c1 |a_o| - mu (split on the sign of tau). x +- c1 |x| is increasing, so the max
// and min over the three axes keep the bounds: near_n <= near_o (1 + c1) + mu (near_o >= tmin >= 0)
// and m_n >= m_o (1 - c1) - mu for the far planes' minimum (m_o >= 0 where the robust test can
// accept at all). The robust test accepts when near_o <= min(fl(m_o w), fl(tmax w)), so
// m_o and tmax are both >= near_o / (w (1 + u)). The FMA test accepts when
// near_n <= fma(min(m_n, tmax), W, S) (one rounding: >= exact (1 - u)); it suffices that
//   W >= w (1 + u) (1 + c1) / ((1 - u) (1 - c1))   (~1 + 14u; W = 1 + 16u, checked below), and
//   S >= mu (W + 1 / (1 - u))                       (~2u max |o_k inv_k|; S = 4u max |fl(o_k
//   inv_k)|),
// plus 2^-126 for roundings in the subnormal range (each adds <= 2^-150 absolute). Overflow: a
// plane value that overflows the FMA form lies beyond ~3e38 >> tmax, where the robust test rejects
// as well; hence the ray's conditions: tmin >= 0, tmax <= 1e30, max |o_k inv_k| <= 1e30.
// S is an absolute slack in t, ~4u |o_k| / |d_k|: small unless one direction component is tiny
// against the others (then nearly every box would pass), so such rays keep the robust test
// (fma_box_test_pays): the choice is speed only, both tests are conservative. The constants
// are float's (u = 2^-24): a double build (RTMINI_USE_DOUBLE) keeps the robust test.
#if defined(__GNUC__) && !defined(__CUDACC__) && defined(__AVX__) && defined(__FMA__) && \
    !defined(RTMINI_USE_DOUBLE)
#define RTMINI_FMA_BOX_TEST 1
#else
#define RTMINI_FMA_BOX_TEST 0
#endif

// W of the proof: 1 + 16u.
inline constexpr Real kFmaBoxWidening = Real(1) + Real(9.5367431640625e-7);

#if RTMINI_FMA_BOX_TEST
namespace fma_box_check {
constexpr double u = 5.9604644775390625e-8;  // 2^-24
constexpr double gamma2 = 2 * u / (1 - 2 * u);
constexpr double c1 = (u + gamma2) / (1 - gamma2);
static_assert(sizeof(Real) == 4, "the FMA box test's constants are for float");
static_assert(double(kFmaBoxWidening) >=
                  double(slab_widening()) * (1 + u) * (1 + c1) / ((1 - u) * (1 - c1)),
              "W must cover the robust test's widening and both tests' rounding (proof above)");
static_assert(double(WideRay::kFmaSlackPerOrgInv) >=
                  u * (1 + u) / (1 - u) * (double(kFmaBoxWidening) + 1 / (1 - u)) / (1 - u),
              "S must cover the rounding of o * inv (proof above)");
}  // namespace fma_box_check

// The FMA test applies (see the proof's conditions) and its slack stays small: no direction
// component below 1/1024 of the largest (S <= 2^-12 |o| / max |d_k|; ~0.2 % of uniformly random
// directions fall back to the robust test).
inline bool fma_box_test_pays(const Ray& ray, const WideRay& r) {
  const Real ax = std::fabs(r.inv.x), ay = std::fabs(r.inv.y), az = std::fabs(r.inv.z);
  const Real hi_xy = ax > ay ? ax : ay, lo_xy = ax < ay ? ax : ay;
  const Real hi = az > hi_xy ? az : hi_xy, lo = az < lo_xy ? az : lo_xy;
  constexpr Real kMaxOrgInv = Real(1e30);
  // (A NaN direction gives a NaN org_inv, which fails its bound.)
  return ray.tmin >= 0 && ray.tmax <= Real(1e30) && hi <= Real(1024) * lo &&
         std::fabs(r.org_inv.x) <= kMaxOrgInv && std::fabs(r.org_inv.y) <= kMaxOrgInv &&
         std::fabs(r.org_inv.z) <= kMaxOrgInv;
}

// Eight children's boxes, six fused multiply-subtracts, far widened by fma(far, W, S).
__attribute__((always_inline)) inline int fma_box_test(const WideNode& nd, const WideRay& r,
                                                       Real tmin, Real tmax, Real* tn) {
  const __m256 ix = _mm256_set1_ps(r.inv.x), iy = _mm256_set1_ps(r.inv.y),
               iz = _mm256_set1_ps(r.inv.z);
  const __m256 qx = _mm256_set1_ps(r.org_inv.x), qy = _mm256_set1_ps(r.org_inv.y),
               qz = _mm256_set1_ps(r.org_inv.z);
  const __m256 a = _mm256_fmsub_ps(_mm256_load_ps(r.neg_x ? nd.hi_x : nd.lo_x), ix, qx);
  const __m256 b = _mm256_fmsub_ps(_mm256_load_ps(r.neg_y ? nd.hi_y : nd.lo_y), iy, qy);
  const __m256 c = _mm256_fmsub_ps(_mm256_load_ps(r.neg_z ? nd.hi_z : nd.lo_z), iz, qz);
  const __m256 d = _mm256_fmsub_ps(_mm256_load_ps(r.neg_x ? nd.lo_x : nd.hi_x), ix, qx);
  const __m256 e = _mm256_fmsub_ps(_mm256_load_ps(r.neg_y ? nd.lo_y : nd.hi_y), iy, qy);
  const __m256 f = _mm256_fmsub_ps(_mm256_load_ps(r.neg_z ? nd.lo_z : nd.hi_z), iz, qz);
  const __m256 near = _mm256_max_ps(_mm256_max_ps(a, b), _mm256_max_ps(c, _mm256_set1_ps(tmin)));
  const __m256 far =
      _mm256_fmadd_ps(_mm256_min_ps(_mm256_min_ps(d, e), _mm256_min_ps(f, _mm256_set1_ps(tmax))),
                      _mm256_set1_ps(kFmaBoxWidening), _mm256_set1_ps(r.slack));
  _mm256_storeu_ps(tn, near);
  return _mm256_movemask_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ));
}
#endif

// The node's hit lanes by the test chosen for this ray (entry distances in tn).
template <bool kFma>
KOKKOS_FORCEINLINE_FUNCTION int box_test(const WideNode& nd, const WideRay& r, Real tmin, Real tmax,
                                         Real* tn) {
#if RTMINI_FMA_BOX_TEST
  if constexpr (kFma) return fma_box_test(nd, r, tmin, tmax, tn);
#endif
  return wide_box_test(nd, r.neg_x, r.neg_y, r.neg_z, r.org.x, r.org.y, r.org.z, r.inv, tmin, tmax,
                       tn);
}

// The entry distance up to which a child found by box_test<kFma> may still hold a hit closer
// than tmax (the same widening as that test's far).
template <bool kFma>
KOKKOS_FORCEINLINE_FUNCTION Real cull_limit(Real tmax, const WideRay& r) {
#if RTMINI_FMA_BOX_TEST
  if constexpr (kFma) return std::fma(tmax, kFmaBoxWidening, r.slack);
#endif
  (void)r;
  return tmax * slab_widening();
}

// A wide leaf's rows and prim ids: kLanes values per row, nine rows a.x .. c.z, then the ids.
template <int kLanes>
struct LeafRows {
  const Real* rows;
  KOKKOS_INLINE_FUNCTION Real at(int row, int k) const { return rows[row * kLanes + k]; }
  KOKKOS_INLINE_FUNCTION int prim(int k) const {
    int id;
    // The ids are ints after the nine rows (write_leaf_rows), whatever the size of Real.
    std::memcpy(&id, reinterpret_cast<const char*>(rows + 9 * kLanes) + k * sizeof id, sizeof id);
    return id;
  }
  KOKKOS_INLINE_FUNCTION Triangle triangle(int k) const {
    return {Vec3(at(0, k), at(1, k), at(2, k)), Vec3(at(3, k), at(4, k), at(5, k)),
            Vec3(at(6, k), at(7, k), at(8, k))};
  }
};

// The rows of leaf `ref` in its block (the half its `first` names).
KOKKOS_FORCEINLINE_FUNCTION const Real* leaf_rows(const TriangleLanes& block, std::uint32_t ref) {
  return reinterpret_cast<const Real*>(reinterpret_cast<const char*>(&block) +
                                       (leaf_first(ref) & 1u) * (sizeof(TriangleLanes) / 2));
}

// One candidate from a leaf lane, under the scalar traversal's rule: closest t, and the lower
// primitive id at equal t, so the answer does not depend on the order lanes are looked at.
template <bool kAnyHit>
KOKKOS_FORCEINLINE_FUNCTION bool take_hit(Real t, Real u, Real v, int id, Real& tmax, Hit& hit,
                                          bool& found) {
  if (kAnyHit || t < tmax || id < hit.prim || !found) {
    tmax = t;
    hit.t = t;
    hit.u = u;
    hit.v = v;
    hit.prim = id;
    found = true;
  }
  return kAnyHit;
}

// The lanes `scalar_lanes` of a leaf by the scalar test (all of them without vector extensions,
// else the vector test's redo lanes): updates hit/tmax; true when any-hit may stop.
template <int kLanes, bool kAnyHit>
KOKKOS_FORCEINLINE_FUNCTION bool intersect_scalar_lanes(const LeafRows<kLanes>& l, int count,
                                                        int scalar_lanes, const WatertightRay& wr,
                                                        const Ray& ray, Real& tmax, Hit& hit,
                                                        bool& found) {
  for (int k = 0; k < count; ++k) {
    if (!(scalar_lanes >> k & 1)) continue;
    const Triangle tri = l.triangle(k);
    Real t, u, v;
    if (!intersect_triangle(wr, tri.a, tri.b, tri.c, ray.tmin, tmax, t, u, v)) continue;
    if (take_hit<kAnyHit>(t, u, v, l.prim(k), tmax, hit, found)) return true;
  }
  return false;
}

#if defined(__GNUC__) && !defined(__CUDACC__)
// Takes the hits of a leaf's vector test (watertight_lanes) in lane order, then the lanes the
// scalar test redoes: updates hit/tmax; true when any-hit may stop.
template <int kLanes, bool kAnyHit, bool kStats>
KOKKOS_FORCEINLINE_FUNCTION bool take_leaf_lanes(const Real* rows, int count,
                                                 const LeafLaneHits& lanes, const WatertightRay& wr,
                                                 const Ray& ray, Real& tmax, Hit& hit, bool& found,
                                                 TraversalStats* stats) {
  const LeafRows<kLanes> l{rows};
  if (kStats) stats->tests += count;
  for (int m = lanes.hit; m != 0; m &= m - 1) {
    const int k = __builtin_ctz(m);
    if (!(lanes.t[k] <= tmax)) continue;  // a closer hit in this leaf came first
    if (take_hit<kAnyHit>(lanes.t[k], lanes.u[k], lanes.v[k], l.prim(k), tmax, hit, found))
      return true;
  }
  return intersect_scalar_lanes<kLanes, kAnyHit>(l, count, lanes.redo, wr, ray, tmax, hit, found);
}
#endif

// A wide-tree leaf of kLanes lanes per row: updates hit/tmax; true when any-hit may stop.
template <int kLanes, bool kAnyHit, bool kStats>
KOKKOS_FORCEINLINE_FUNCTION bool intersect_leaf_rows(const Real* rows, int count,
                                                     const WatertightRay& wr, const Ray& ray,
                                                     Real& tmax, Hit& hit, bool& found,
                                                     TraversalStats* stats) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  const LeafLaneHits lanes = watertight_lanes<kLanes>(rows, count, wr, ray.tmin, tmax);
  return take_leaf_lanes<kLanes, kAnyHit, kStats>(rows, count, lanes, wr, ray, tmax, hit, found,
                                                  stats);
#else
  const LeafRows<kLanes> l{rows};
  if (kStats) stats->tests += count;
  return intersect_scalar_lanes<kLanes, kAnyHit>(l, count, (1 << count) - 1, wr, ray, tmax, hit,
                                                 found);
#endif
}

// A wide-tree leaf (compact or full by its count): updates hit/tmax; true when any-hit may stop.
template <bool kAnyHit, bool kStats>
KOKKOS_FORCEINLINE_FUNCTION bool intersect_wide_leaf(const TriangleLanes& block, std::uint32_t ref,
                                                     const WatertightRay& wr, const Ray& ray,
                                                     Real& tmax, Hit& hit, bool& found,
                                                     TraversalStats* stats) {
  const int count = static_cast<int>(leaf_count(ref));
  const Real* rows = leaf_rows(block, ref);
  if (count <= kCompactLeafSize)
    return intersect_leaf_rows<kCompactLeafSize, kAnyHit, kStats>(rows, count, wr, ray, tmax, hit,
                                                                  found, stats);
  return intersect_leaf_rows<kMaxLeafSize, kAnyHit, kStats>(rows, count, wr, ray, tmax, hit, found,
                                                            stats);
}

// Starts fetching a node the traversal will visit later (a sibling pushed on the stack), so its
// cache misses overlap the work on the current path, as Embree's BVH8 traversal does (measured:
// dragon AO 0.70-0.72x -> 0.76x Embree, results/bvh/README.md; prefetching every hit child,
// leaves included, was slower).
KOKKOS_FORCEINLINE_FUNCTION void prefetch_node(const WideNode& nd) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  const char* p = reinterpret_cast<const char*>(&nd);
  for (std::size_t line = 0; line < sizeof(WideNode); line += 64) __builtin_prefetch(p + line);
#else
  (void)nd;
#endif
}

// Starts fetching the rows of leaf `ref` (three cache lines of a compact leaf, five of a full one).
KOKKOS_FORCEINLINE_FUNCTION void prefetch_leaf(const TriangleLanes& block, std::uint32_t ref) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  const char* p = reinterpret_cast<const char*>(leaf_rows(block, ref));
  const std::size_t bytes = leaf_count(ref) <= std::uint32_t(kCompactLeafSize)
                                ? sizeof(TriangleLanes) / 2
                                : sizeof(TriangleLanes);
  for (std::size_t line = 0; line < bytes; line += 64) __builtin_prefetch(p + line);
#else
  (void)block, (void)ref;
#endif
}

// Index of the lowest set bit of a non-zero mask.
KOKKOS_FORCEINLINE_FUNCTION int lowest_bit(int m) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  return __ffs(m) - 1;
#else
  return __builtin_ctz(static_cast<unsigned>(m));
#endif
}

// Lanes whose child is a leaf (kLeafBit is the sign bit: one movemask where AVX has it).
KOKKOS_FORCEINLINE_FUNCTION int leaf_lanes(const WideNode& nd) {
#if defined(__GNUC__) && !defined(__CUDACC__) && defined(__AVX__)
  if constexpr (kWidth == 8) {
    __m256 v;
    std::memcpy(&v, nd.child, sizeof v);
    return _mm256_movemask_ps(v);
  }
#endif
  int mask = 0;
  for (int k = 0; k < kWidth; ++k) mask |= (is_leaf(nd.child[k]) ? 1 : 0) << k;
  return mask;
}

// Lanes whose entry distance is still <= limit.
KOKKOS_FORCEINLINE_FUNCTION int lanes_not_after(const Real* tn, Real limit) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  RealLanes v;
  std::memcpy(&v, tn, sizeof v);
  return lane_bits(v <= RealLanes{} + limit);
#else
  int mask = 0;
  for (int k = 0; k < kWidth; ++k) mask |= (tn[k] <= limit ? 1 : 0) << k;
  return mask;
#endif
}

// Wide traversal for host memory: the lane loops below vectorise. The near
// plane of each axis is chosen by the ray's direction sign, so an inverted
// (empty) box always has near > far and unused lanes never hit.
template <class BvhT, bool kAnyHit, bool kStats, bool kFma>
KOKKOS_INLINE_FUNCTION bool traverse_wide_with(const BvhT& bvh, const Ray& ray,
                                               const WideRay& box_ray, Hit& hit,
                                               TraversalStats* stats) {
  const WatertightRay wr(ray.org, ray.dir);
  Real tmax = ray.tmax;
  constexpr int kWideStack = (kWidth - 1) * kStackSize;  // pending siblings along one path
  std::uint32_t stack[kWideStack];
  int sp = 0;
  std::uint32_t node = 0;
  bool found = false;
  while (true) {
    const WideNode& nd = bvh.wide(node);
    if (kStats) ++stats->nodes;
    Real tn[kWidth];
    const int hitmask = box_test<kFma>(nd, box_ray, ray.tmin, tmax, tn);
    const int leaves = leaf_lanes(nd);
    // Leaves first: a closer hit shrinks tmax before inner children are ordered.
    for (int m = hitmask & leaves; m != 0; m &= m - 1) {
      const std::uint32_t c = nd.child[lowest_bit(m)];
      if (c == kEmptyLeaf) continue;
      if (intersect_wide_leaf<kAnyHit, kStats>(bvh.leaves(leaf_first(c) >> 1), c, wr, ray, tmax,
                                               hit, found, stats))
        return true;
    }
    // Inner children still within tmax (any hit: tmax has not moved since the box test).
    int inner = hitmask & ~leaves;
    if (!kAnyHit && inner != 0) inner &= lanes_not_after(tn, cull_limit<kFma>(tmax, box_ray));
    if (inner == 0) {
      if (sp == 0) break;
      node = stack[--sp];
      continue;
    }
    const int k0 = lowest_bit(inner);
    inner &= inner - 1;
    if (inner == 0) {  // one child: no stack traffic
      node = nd.child[k0];
      continue;
    }
    if (kAnyHit) {
      // Any blocker ends the ray, so no sort: lane order (measured: visiting the nearest child
      // first cost 5-10 % on dragon shadow rays and gained nothing on AO).
      node = nd.child[k0];
      for (; inner != 0; inner &= inner - 1) {
        const std::uint32_t c = nd.child[lowest_bit(inner)];
        prefetch_node(bvh.wide(c));
        stack[sp++] = c;
      }
      continue;
    }
    // Closest hit: pushed far-to-near so the nearest is visited next.
    std::uint32_t ids[kWidth];
    Real ds[kWidth];
    ids[0] = nd.child[k0];
    ds[0] = tn[k0];
    int n = 1;
    for (; inner != 0; inner &= inner - 1) {
      const int k = lowest_bit(inner);
      int j = n++;
      while (j > 0 && ds[j - 1] < tn[k]) {
        ds[j] = ds[j - 1];
        ids[j] = ids[j - 1];
        --j;
      }
      ds[j] = tn[k];
      ids[j] = nd.child[k];
    }
    for (int j = 0; j < n - 1; ++j) {
      prefetch_node(bvh.wide(ids[j]));
      stack[sp++] = ids[j];
    }
    node = ids[n - 1];
  }
  return found;
}

// The wide traversal with the box test this ray can take (the FMA test where it pays).
template <class BvhT, bool kAnyHit, bool kStats>
KOKKOS_INLINE_FUNCTION bool traverse_wide(const BvhT& bvh, const Ray& ray, Hit& hit,
                                          TraversalStats* stats) {
  const WideRay box_ray(ray);
#if RTMINI_FMA_BOX_TEST
  if (fma_box_test_pays(ray, box_ray))
    return traverse_wide_with<BvhT, kAnyHit, kStats, true>(bvh, ray, box_ray, hit, stats);
#endif
  return traverse_wide_with<BvhT, kAnyHit, kStats, false>(bvh, ray, box_ray, hit, stats);
}

// ---- Packets of coherent rays (host) -----------------------------------------------------------
// Up to kPacketSize rays traverse the wide tree together: one walk, each node visited once for
// every ray of the packet that reached it (a ray mask per stack entry), each ray testing the
// node's boxes and the leaves' triangles with the single-ray tests above. A ray reaches exactly
// the nodes and leaves its own box tests find, so its answer is the single-ray answer bit for bit
// (closest hit: the smallest t, then the lowest id, whatever the order leaves are tested in).
// What the packet saves on coherent rays (a camera's, or shadow rays toward one light) is the
// per-ray walk: one stack, one node fetch, one set of branches for eight rays, and the eight
// rays' box and leaf tests are independent, so their latencies overlap. Any-hit packets test a
// node's leaves one step late, to overlap their fetch with the next node's (occlude_packet_with);
// packets whose rays share an origin subtract it from a leaf's rows once for all their rays.
#if defined(__GNUC__) && !defined(__CUDACC__)
inline constexpr bool kHavePacketTraversal = true;
static_assert(kPacketSize == 8, "transpose_bytes and the tmax snapshot are for packets of 8");

// Byte k of the result holds bit k of every byte of `m` (bit r from byte r): an 8x8 bit matrix
// transposed (Hacker's Delight, 7-3), turning "children each ray hits" into "rays hitting each
// child".
inline std::uint64_t transpose_bytes(std::uint64_t m) {
  std::uint64_t t = (m ^ (m >> 7)) & 0x00AA00AA00AA00AAull;
  m ^= t ^ (t << 7);
  t = (m ^ (m >> 14)) & 0x0000CCCC0000CCCCull;
  m ^= t ^ (t << 14);
  t = (m ^ (m >> 28)) & 0x00000000F0F0F0F0ull;
  m ^= t ^ (t << 28);
  return m;
}

KOKKOS_FORCEINLINE_FUNCTION int byte_of(std::uint64_t m, int k) {
  return static_cast<int>((m >> (8 * k)) & 0xffu);
}

// A packet's rays with their per-ray constants; `live` = rays still traversing.
struct PacketRays {
  const Ray* rays;
  WideRay box[kPacketSize];
  WatertightRay wr[kPacketSize];
  alignas(32) Real tmax[kPacketSize];
#if RTMINI_FMA_BOX_TEST
  // The FMA box test's constants with ray r in lane r (fma_box_test_by_child), and whether every
  // ray of the packet has the same direction octant (then the near planes are the packet's).
  struct Lanes {
    alignas(32) Real inv[3][kPacketSize];
    alignas(32) Real org_inv[3][kPacketSize];
    alignas(32) Real tmin[kPacketSize];
    alignas(32) Real slack[kPacketSize];
    alignas(32) Real negative[3][kPacketSize];  // -0 where WideRay::neg_* (sign bit), else +0
  } lanes;
  bool one_octant;
#endif
};

// A node's box tests for a packet: byte k of per_child = the rays that hit child k; bit k of
// children = some ray hits child k.
struct PacketBoxHits {
  std::uint64_t per_child = 0;
  int children = 0;
};

#if RTMINI_FMA_BOX_TEST
// Rays of a packet from which its node's box tests go child by child rather than ray by ray:
// eight children's tests of all eight lanes cost less than one test per ray from about this many
// rays (packets of one direction octant; kMinMixedRaysByChild where blends pick each lane's near
// planes). Both measured on the dragon's shadow and AO rays, and kept for closest hit (diffuse
// and primary rays; from one ray on was faster on a quiet machine but slower under load, when
// the eight lanes' arithmetic competes for the core: results/bvh/raw_cpu9/explore.txt).
inline constexpr int kMinRaysByChild = 3;
inline constexpr int kMinMixedRaysByChild = 4;

// Stores the 8x8 matrix m (m[k] = row k) transposed: out[r][k] = lane r of m[k] (shuffles only,
// so the values keep their bits).
inline void store_transposed(const __m256 m[8], Real (*out)[8]) {
  __m256 t[8], u[8];
  for (int i = 0; i < 8; i += 2) {
    t[i] = _mm256_unpacklo_ps(m[i], m[i + 1]);      // rows i, i+1 interleaved, lanes 0 1 4 5
    t[i + 1] = _mm256_unpackhi_ps(m[i], m[i + 1]);  // lanes 2 3 6 7
  }
  for (int i = 0; i < 8; i += 4) {
    u[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44);
    u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xee);
    u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44);
    u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xee);
  }
  for (int i = 0; i < 4; ++i) {
    _mm256_store_ps(out[i], _mm256_permute2f128_ps(u[i], u[i + 4], 0x20));
    _mm256_store_ps(out[i + 4], _mm256_permute2f128_ps(u[i], u[i + 4], 0x31));
  }
}

// The FMA box test of one node for the rays `rays` of a packet at once, child by child, ray r in
// lane r: byte k of the result = the rays that hit child k. Lane r runs fma_box_test's operations
// for ray r in the same order on the same planes (each ray's near plane of an axis by the sign of
// its direction: the packet's when its rays share their octant, kOneOctant, else lane by lane),
// so each ray finds the children its own test finds. No transpose; one child's rays per vector
// instead of one ray's children. With kEntries, tn[r][k] = ray r's entry distance to child k, the
// value fma_box_test stores for it (closest hit culls and orders children by them).
template <bool kOneOctant, bool kEntries>
inline PacketBoxHits fma_box_test_by_child(const WideNode& nd, const PacketRays& p, int rays,
                                           Real (*tn)[kWidth]) {
  const PacketRays::Lanes& l = p.lanes;
  const __m256 ix = _mm256_load_ps(l.inv[0]), iy = _mm256_load_ps(l.inv[1]),
               iz = _mm256_load_ps(l.inv[2]);
  const __m256 qx = _mm256_load_ps(l.org_inv[0]), qy = _mm256_load_ps(l.org_inv[1]),
               qz = _mm256_load_ps(l.org_inv[2]);
  const __m256 tmin = _mm256_load_ps(l.tmin), tmax = _mm256_load_ps(p.tmax);
  const __m256 slack = _mm256_load_ps(l.slack), widening = _mm256_set1_ps(kFmaBoxWidening);
  const __m256 sx = _mm256_load_ps(l.negative[0]), sy = _mm256_load_ps(l.negative[1]),
               sz = _mm256_load_ps(l.negative[2]);
  // One octant: the planes by the packet's signs; else lo and hi (the blends below pick).
  const WideRay& r = p.box[lowest_bit(rays)];
  const bool swap_x = kOneOctant && r.neg_x, swap_y = kOneOctant && r.neg_y,
             swap_z = kOneOctant && r.neg_z;
  const Real* near_x = swap_x ? nd.hi_x : nd.lo_x;
  const Real* near_y = swap_y ? nd.hi_y : nd.lo_y;
  const Real* near_z = swap_z ? nd.hi_z : nd.lo_z;
  const Real* far_x = swap_x ? nd.lo_x : nd.hi_x;
  const Real* far_y = swap_y ? nd.lo_y : nd.hi_y;
  const Real* far_z = swap_z ? nd.lo_z : nd.hi_z;
  PacketBoxHits out;
  __m256 entry[kWidth];  // entry[k]: the rays' entry distances to child k (kEntries)
  for (int k = 0; k < kWidth; ++k) {
    __m256 a = _mm256_fmsub_ps(_mm256_set1_ps(near_x[k]), ix, qx);
    __m256 b = _mm256_fmsub_ps(_mm256_set1_ps(near_y[k]), iy, qy);
    __m256 c = _mm256_fmsub_ps(_mm256_set1_ps(near_z[k]), iz, qz);
    __m256 d = _mm256_fmsub_ps(_mm256_set1_ps(far_x[k]), ix, qx);
    __m256 e = _mm256_fmsub_ps(_mm256_set1_ps(far_y[k]), iy, qy);
    __m256 f = _mm256_fmsub_ps(_mm256_set1_ps(far_z[k]), iz, qz);
    if constexpr (!kOneOctant) {
      // Lanes whose ray has WideRay::neg_* on an axis swap that axis's near and far planes.
      const __m256 a0 = a, b0 = b, c0 = c;
      a = _mm256_blendv_ps(a0, d, sx);
      d = _mm256_blendv_ps(d, a0, sx);
      b = _mm256_blendv_ps(b0, e, sy);
      e = _mm256_blendv_ps(e, b0, sy);
      c = _mm256_blendv_ps(c0, f, sz);
      f = _mm256_blendv_ps(f, c0, sz);
    }
    const __m256 near = _mm256_max_ps(_mm256_max_ps(a, b), _mm256_max_ps(c, tmin));
    const __m256 far = _mm256_fmadd_ps(_mm256_min_ps(_mm256_min_ps(d, e), _mm256_min_ps(f, tmax)),
                                       widening, slack);
    const int hit = _mm256_movemask_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ)) & rays;
    out.per_child |= std::uint64_t(hit) << (8 * k);
    out.children |= (hit != 0 ? 1 : 0) << k;
    if constexpr (kEntries) entry[k] = near;
  }
  if constexpr (kEntries) store_transposed(entry, tn);
  return out;
}
#endif

// A pending node and the rays that reached it.
struct PacketEntry {
  std::uint32_t node;
  int rays;
};

// A packet walk's pending nodes with their rays: at most kWidth - 1 siblings per level of a
// path, as the single-ray walk's stack.
struct PacketStack {
  PacketEntry entry[(kWidth - 1) * kStackSize];
  int size = 0;
  KOKKOS_FORCEINLINE_FUNCTION bool empty() const { return size == 0; }
  KOKKOS_FORCEINLINE_FUNCTION void push(const PacketEntry& e) { entry[size++] = e; }
  KOKKOS_FORCEINLINE_FUNCTION PacketEntry pop() { return entry[--size]; }
};

// The rays `rays` of a packet whose rays all share one origin (AO rays from one point, a pinhole
// camera's) against one leaf: its rows relative to that origin are computed once, not per ray
// (the same subtraction, so the same bits); returns the rays an any-hit test finished.
template <int kLanes, bool kAnyHit>
KOKKOS_FORCEINLINE_FUNCTION int shared_origin_leaf(const Real* rows, int count, int rays,
                                                   PacketRays& p, Hit* hits, bool* found) {
  RelativeRows rel;
  rel.fill<kLanes>(rows, p.rays[lowest_bit(rays)].org);
  int done = 0;
  for (; rays != 0; rays &= rays - 1) {
    const int r = lowest_bit(rays);
    const LeafLaneHits lanes = rel.test(count, p.wr[r], p.rays[r].tmin, p.tmax[r]);
    if (take_leaf_lanes<kLanes, kAnyHit, false>(rows, count, lanes, p.wr[r], p.rays[r], p.tmax[r],
                                                hits[r], found[r], nullptr))
      done |= 1 << r;
  }
  return done;
}

// Tests the leaf child `c` for each ray of `rays`; returns the rays an any-hit test finished.
template <class BvhT, bool kAnyHit, bool kSharedOrigin>
KOKKOS_FORCEINLINE_FUNCTION int packet_leaf(const BvhT& bvh, std::uint32_t c, int rays,
                                            PacketRays& p, Hit* hits, bool* found) {
  const TriangleLanes& block = bvh.leaves(leaf_first(c) >> 1);
  if constexpr (kSharedOrigin) {
    const int count = static_cast<int>(leaf_count(c));
    const Real* rows = leaf_rows(block, c);
    if (count <= kCompactLeafSize)
      return shared_origin_leaf<kCompactLeafSize, kAnyHit>(rows, count, rays, p, hits, found);
    return shared_origin_leaf<kMaxLeafSize, kAnyHit>(rows, count, rays, p, hits, found);
  }
  int done = 0;
  for (; rays != 0; rays &= rays - 1) {
    const int r = lowest_bit(rays);
    if (intersect_wide_leaf<kAnyHit, false>(block, c, p.wr[r], p.rays[r], p.tmax[r], hits[r],
                                            found[r], nullptr))
      done |= 1 << r;
  }
  return done;
}

// The box tests of one node for the rays `rays` of a packet: byte k of the result = the rays
// that hit child k; with kEntries, tn[r][k] = ray r's entry distance to child k (closest hit),
// else tn is one row of scratch. Child by child where the packet has enough rays for it
// (fma_box_test_by_child, kMinRaysByChild), else ray by ray, the "children ray r hits" bytes
// transposed.
template <bool kFma, bool kEntries>
KOKKOS_FORCEINLINE_FUNCTION PacketBoxHits packet_box_tests(const WideNode& nd, const PacketRays& p,
                                                           int rays, Real (*tn)[kWidth]) {
#if RTMINI_FMA_BOX_TEST
  if (kFma) {
    const int n = __builtin_popcount(rays);
    if (p.one_octant && n >= kMinRaysByChild)
      return fma_box_test_by_child<true, kEntries>(nd, p, rays, tn);
    if (!p.one_octant && n >= kMinMixedRaysByChild)
      return fma_box_test_by_child<false, kEntries>(nd, p, rays, tn);
  }
#endif
  std::uint64_t per_ray = 0;
  PacketBoxHits out;
  for (int m = rays; m != 0; m &= m - 1) {
    const int r = lowest_bit(m);
    const int h = box_test<kFma>(nd, p.box[r], p.rays[r].tmin, p.tmax[r], tn[kEntries ? r : 0]);
    per_ray |= std::uint64_t(h) << (8 * r);
    out.children |= h;
  }
  out.per_child = transpose_bytes(per_ray);
  return out;
}

// The closest-hit packet walk (any hits: occlude_packet_with below).
template <class BvhT, bool kFma, bool kSharedOrigin>
inline void traverse_packet_with(const BvhT& bvh, PacketRays& p, int live, Hit* hits, bool* found) {
  PacketStack stack;
  PacketEntry at{0u, live};
  while (true) {
    const WideNode& nd = bvh.wide(at.node);
    // Byte k of `per_child` = the rays that hit child k; tn[r][k] = ray r's entry distance.
    alignas(32) Real tn[kPacketSize][kWidth];
    const PacketBoxHits box = packet_box_tests<kFma, true>(nd, p, at.rays, tn);
    std::uint64_t per_child = box.per_child;
    const int any_child = box.children;
    const int leaves = leaf_lanes(nd);
    // Every leaf some ray will test, fetched before the first is tested: with eight rays per
    // leaf the later leaves' misses overlap the earlier leaves' tests.
    for (int m = any_child & leaves; m != 0; m &= m - 1) {
      const std::uint32_t c = nd.child[lowest_bit(m)];
      if (c != kEmptyLeaf) prefetch_leaf(bvh.leaves(leaf_first(c) >> 1), c);
    }
    int shrunk = 0;  // closest hit: rays whose tmax a leaf of this node moved
    for (int m = any_child & leaves; m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      const std::uint32_t c = nd.child[k];
      if (c == kEmptyLeaf) continue;
      const int rays = byte_of(per_child, k) & live;
      if (rays == 0) continue;
      const Real before[kPacketSize] = {p.tmax[0], p.tmax[1], p.tmax[2], p.tmax[3],
                                        p.tmax[4], p.tmax[5], p.tmax[6], p.tmax[7]};
      packet_leaf<BvhT, false, kSharedOrigin>(bvh, c, rays, p, hits, found);
      for (int m2 = rays; m2 != 0; m2 &= m2 - 1) {
        const int r = lowest_bit(m2);
        if (p.tmax[r] != before[r]) shrunk |= 1 << r;
      }
    }
    // Closest hit: a ray whose tmax moved drops the inner children now beyond it (as the
    // single-ray traversal does).
    if (shrunk != 0) {
      std::uint64_t per_ray = transpose_bytes(per_child);  // byte r = the children ray r hits
      for (int m = shrunk; m != 0; m &= m - 1) {
        const int r = lowest_bit(m);
        const int keep = lanes_not_after(tn[r], cull_limit<kFma>(p.tmax[r], p.box[r]));
        per_ray &= ~(std::uint64_t(~keep & 0xff) << (8 * r));
      }
      per_child = transpose_bytes(per_ray);
    }
    // Inner children that some live ray reached.
    int inner = 0;
    for (int m = any_child & ~leaves; m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      if ((byte_of(per_child, k) & live) != 0) inner |= 1 << k;
    }
    if (inner == 0) {
      do {
        if (stack.empty()) return;
        at = stack.pop();
        at.rays &= live;
      } while (at.rays == 0);
      continue;
    }
    const int k0 = lowest_bit(inner);
    inner &= inner - 1;
    if (inner == 0) {  // one child: no stack traffic
      at = {nd.child[k0], byte_of(per_child, k0) & live};
      continue;
    }
    // Children by the nearest entry over their rays, pushed far-to-near.
    PacketEntry ids[kWidth];
    Real ds[kWidth];
    int n = 0;
    for (int m = inner | (1 << k0); m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      const int rays = byte_of(per_child, k) & live;
      Real d = Real(3e38);
      for (int rm = rays; rm != 0; rm &= rm - 1) {
        const Real e = tn[lowest_bit(rm)][k];
        d = e < d ? e : d;
      }
      int j = n++;
      while (j > 0 && ds[j - 1] < d) {
        ds[j] = ds[j - 1];
        ids[j] = ids[j - 1];
        --j;
      }
      ds[j] = d;
      ids[j] = {nd.child[k], rays};
    }
    for (int j = 0; j < n - 1; ++j) {
      prefetch_node(bvh.wide(ids[j].node));
      stack.push(ids[j]);
    }
    at = ids[n - 1];
  }
}

// Leaf children a node's box tests found, and the rays that hit each.
struct PendingLeaves {
  std::uint32_t leaf[kWidth];
  int rays[kWidth];
  int count = 0;
};

// The any-hit packet walk. A node's leaves are tested one step later, after the next node's box
// tests: both were prefetched together, so the leaves' cache misses overlap the next node's
// instead of following them (the packet's leaf loads were its largest stall). Any blocker ends a
// ray whichever leaf it is found in, so testing leaves later changes no answer; a ray stays in
// the packet until its first blocker, and the walk stops when no ray is left.
template <class BvhT, bool kFma, bool kSharedOrigin>
inline void occlude_packet_with(const BvhT& bvh, PacketRays& p, int live, Hit* hits, bool* found) {
  PacketStack stack;
  PacketEntry at{0u, live};
  PendingLeaves pending;
  while (true) {
    // The next node's box tests: byte k of `per_child` = the rays that hit child k.
    at.rays &= live;
    PacketBoxHits box;
    alignas(32) Real tn[1][kWidth];  // scratch: any hit keeps no entry distances
    if (at.rays != 0) box = packet_box_tests<kFma, false>(bvh.wide(at.node), p, at.rays, tn);
    // The previous node's leaves, fetched while this node's boxes were tested.
    for (int j = 0; j < pending.count; ++j) {
      const int rays = pending.rays[j] & live;
      if (rays == 0) continue;
      live &= ~packet_leaf<BvhT, true, kSharedOrigin>(bvh, pending.leaf[j], rays, p, hits, found);
      if (live == 0) return;
    }
    pending.count = 0;
    if (box.children == 0) {
      if (stack.empty()) return;
      at = stack.pop();
      continue;
    }
    const WideNode& nd = bvh.wide(at.node);
    const std::uint64_t per_child = box.per_child;
    const int leaves = leaf_lanes(nd);
    int inner = 0;
    for (int m = box.children; m != 0; m &= m - 1) {
      const int k = lowest_bit(m);
      const int rays = byte_of(per_child, k) & live;
      if (rays == 0) continue;
      if (!(leaves >> k & 1)) {
        inner |= 1 << k;
        continue;
      }
      const std::uint32_t c = nd.child[k];
      if (c == kEmptyLeaf) continue;
      prefetch_leaf(bvh.leaves(leaf_first(c) >> 1), c);
      pending.leaf[pending.count] = c;
      pending.rays[pending.count++] = rays;
    }
    if (inner == 0) {  // the pending leaves are tested after the next entry's box tests
      at = stack.empty() ? PacketEntry{0u, 0} : stack.pop();
      continue;
    }
    // Lane order, as the single-ray any hit; the next node is fetched with the pending leaves.
    const int k0 = lowest_bit(inner);
    at = {nd.child[k0], byte_of(per_child, k0) & live};
    prefetch_node(bvh.wide(at.node));
    for (inner &= inner - 1; inner != 0; inner &= inner - 1) {
      const int k = lowest_bit(inner);
      prefetch_node(bvh.wide(nd.child[k]));
      stack.push({nd.child[k], byte_of(per_child, k) & live});
    }
  }
}

#if RTMINI_FMA_BOX_TEST
// PacketRays::lanes and one_octant from rays [0, n)'s WideRays (lanes from n on: ray 0's, whose
// tests are masked out).
inline void fill_packet_lanes(PacketRays& p, int n) {
  p.one_octant = true;
  for (int r = 0; r < kPacketSize; ++r) {
    const WideRay& b = p.box[r < n ? r : 0];
    for (int axis = 0; axis < 3; ++axis) {
      p.lanes.inv[axis][r] = b.inv[axis];
      p.lanes.org_inv[axis][r] = b.org_inv[axis];
    }
    p.lanes.tmin[r] = p.rays[r < n ? r : 0].tmin;
    p.lanes.slack[r] = b.slack;
    const bool negative[3] = {b.neg_x, b.neg_y, b.neg_z};
    for (int axis = 0; axis < 3; ++axis)
      p.lanes.negative[axis][r] = negative[axis] ? Real(-0.0) : Real(0);
    p.one_octant = p.one_octant && b.neg_x == p.box[0].neg_x && b.neg_y == p.box[0].neg_y &&
                   b.neg_z == p.box[0].neg_z;
  }
}
#endif

#if RTMINI_FMA_BOX_TEST
// A full packet's per-ray constants, eight rays at once: WideRay, WatertightRay, the FMA lanes
// and fma_box_test_pays, with the scalar constructors' operations lane by lane (IEEE division,
// products and comparisons give the same bits in a vector lane; the selects follow the scalar
// ternaries, NaNs included), so every ray's constants are the ones traverse_packet's ray-by-ray
// setup computes. Eight scalar divisions per ray and the dominant-axis selects were ~12 % of a
// packet trace of the dragon's diffuse rays (perf). Returns the mask of live rays; `fma` = every ray
// may take the FMA box test.
inline int fill_full_packet(PacketRays& p, const Ray* rays, Hit* hits, bool* found, bool& fma) {
  alignas(32) Real in[8][kPacketSize];  // org xyz, dir xyz, tmin, tmax: ray r in lane r
  for (int r = 0; r < kPacketSize; ++r) {
    const Ray& ray = rays[r];
    in[0][r] = ray.org.x, in[1][r] = ray.org.y, in[2][r] = ray.org.z;
    in[3][r] = ray.dir.x, in[4][r] = ray.dir.y, in[5][r] = ray.dir.z;
    in[6][r] = ray.tmin, in[7][r] = ray.tmax;
    hits[r] = Hit();
    hits[r].t = ray.tmax;
    found[r] = false;
  }
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 sign = _mm256_set1_ps(-0.0f), huge = _mm256_set1_ps(1e30f);
  const __m256 tmin = _mm256_load_ps(in[6]), tmax = _mm256_load_ps(in[7]);
  __m256 o[3], d[3], inv[3], oi[3], neg[3], abs_d[3];
  for (int k = 0; k < 3; ++k) {
    o[k] = _mm256_load_ps(in[k]);
    d[k] = _mm256_load_ps(in[3 + k]);
    // safe_reciprocal: +-1e30 (the sign of d) where d == 0, else 1 / d.
    const __m256 huge_signed = _mm256_or_ps(huge, _mm256_and_ps(d[k], sign));
    inv[k] = _mm256_blendv_ps(_mm256_div_ps(one, d[k]), huge_signed,
                              _mm256_cmp_ps(d[k], zero, _CMP_EQ_OQ));
    oi[k] = _mm256_mul_ps(o[k], inv[k]);
    neg[k] = _mm256_cmp_ps(inv[k], zero, _CMP_LT_OQ);
    abs_d[k] = _mm256_andnot_ps(sign, d[k]);
  }
  // WideRay::slack: max(|oi|) by the constructor's comparisons (_mm256_max_ps(a, b) = a > b ? a : b).
  const __m256 abs_oi[3] = {_mm256_andnot_ps(sign, oi[0]), _mm256_andnot_ps(sign, oi[1]),
                            _mm256_andnot_ps(sign, oi[2])};
  const __m256 m = _mm256_max_ps(abs_oi[2], _mm256_max_ps(abs_oi[0], abs_oi[1]));
  const __m256 slack = _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(WideRay::kFmaSlackPerOrgInv), m),
                                     _mm256_set1_ps(WideRay::kFmaSlackFloor));
  // fma_box_test_pays, lane by lane.
  const __m256 abs_inv[3] = {_mm256_andnot_ps(sign, inv[0]), _mm256_andnot_ps(sign, inv[1]),
                             _mm256_andnot_ps(sign, inv[2])};
  const __m256 hi = _mm256_max_ps(abs_inv[2], _mm256_max_ps(abs_inv[0], abs_inv[1]));
  const __m256 lo = _mm256_min_ps(abs_inv[2], _mm256_min_ps(abs_inv[0], abs_inv[1]));
  __m256 pays = _mm256_and_ps(_mm256_cmp_ps(tmin, zero, _CMP_GE_OQ),
                              _mm256_cmp_ps(tmax, huge, _CMP_LE_OQ));
  pays = _mm256_and_ps(pays, _mm256_cmp_ps(hi, _mm256_mul_ps(_mm256_set1_ps(1024.0f), lo), _CMP_LE_OQ));
  for (int k = 0; k < 3; ++k) pays = _mm256_and_ps(pays, _mm256_cmp_ps(abs_oi[k], huge, _CMP_LE_OQ));
  fma = _mm256_movemask_ps(pays) == 0xff;
  // WatertightRay: kz = the dominant axis (x over y only when strictly larger, as the scalar
  // ternaries), kx, ky the next two, swapped where d[kz] < 0; sz = 1 / d[kz].
  const __m256 x_over_y = _mm256_cmp_ps(abs_d[0], abs_d[1], _CMP_GT_OQ);
  const __m256 axy = _mm256_blendv_ps(abs_d[1], abs_d[0], x_over_y);
  const __m256 z_is_xy = _mm256_cmp_ps(axy, abs_d[2], _CMP_GT_OQ);  // kz is x or y
  const __m256 kz_x = _mm256_and_ps(z_is_xy, x_over_y);
  const __m256 kz_y = _mm256_andnot_ps(x_over_y, z_is_xy);
  // d[kz], d[next], d[after] with next = kz + 1 and after = kz + 2 (mod 3).
  const __m256 dz = _mm256_blendv_ps(_mm256_blendv_ps(d[2], d[1], kz_y), d[0], kz_x);
  const __m256 dn = _mm256_blendv_ps(_mm256_blendv_ps(d[0], d[2], kz_y), d[1], kz_x);
  const __m256 da = _mm256_blendv_ps(_mm256_blendv_ps(d[1], d[0], kz_y), d[2], kz_x);
  const __m256 flip = _mm256_cmp_ps(dz, zero, _CMP_LT_OQ);
  const __m256 sz = _mm256_div_ps(one, dz);
  const __m256 sx = _mm256_mul_ps(_mm256_blendv_ps(dn, da, flip), sz);
  const __m256 sy = _mm256_mul_ps(_mm256_blendv_ps(da, dn, flip), sz);
  alignas(32) Real out_sx[kPacketSize], out_sy[kPacketSize], out_sz[kPacketSize];
  _mm256_store_ps(out_sx, sx);
  _mm256_store_ps(out_sy, sy);
  _mm256_store_ps(out_sz, sz);
  const int mask_x = _mm256_movemask_ps(kz_x), mask_y = _mm256_movemask_ps(kz_y);
  const int mask_flip = _mm256_movemask_ps(flip);
  // The FMA lanes, as fill_packet_lanes stores them.
  PacketRays::Lanes& l = p.lanes;
  for (int k = 0; k < 3; ++k) {
    _mm256_store_ps(l.inv[k], inv[k]);
    _mm256_store_ps(l.org_inv[k], oi[k]);
    _mm256_store_ps(l.negative[k], _mm256_and_ps(neg[k], sign));
  }
  _mm256_store_ps(l.tmin, tmin);
  _mm256_store_ps(l.slack, slack);
  _mm256_store_ps(p.tmax, tmax);
  const int nx = _mm256_movemask_ps(neg[0]), ny = _mm256_movemask_ps(neg[1]),
            nz = _mm256_movemask_ps(neg[2]);
  p.one_octant = (nx == 0 || nx == 0xff) && (ny == 0 || ny == 0xff) && (nz == 0 || nz == 0xff);
  for (int r = 0; r < kPacketSize; ++r) {
    WideRay& b = p.box[r];
    b.inv = Vec3(l.inv[0][r], l.inv[1][r], l.inv[2][r]);
    b.org = Vec3(in[0][r], in[1][r], in[2][r]);
    b.org_inv = Vec3(l.org_inv[0][r], l.org_inv[1][r], l.org_inv[2][r]);
    b.slack = l.slack[r];
    b.neg_x = nx >> r & 1, b.neg_y = ny >> r & 1, b.neg_z = nz >> r & 1;
    WatertightRay& w = p.wr[r];
    w.org = b.org;
    w.kz = (mask_x >> r & 1) ? 0 : (mask_y >> r & 1) ? 1 : 2;
    const int next = w.kz == 2 ? 0 : w.kz + 1;
    const int after = next == 2 ? 0 : next + 1;
    const bool flipped = mask_flip >> r & 1;
    w.kx = flipped ? after : next;
    w.ky = flipped ? next : after;
    w.sx = out_sx[r], w.sy = out_sy[r], w.sz = out_sz[r];
  }
  // An empty segment hits nothing (nor does the single-ray traversal find anything there).
  return _mm256_movemask_ps(_mm256_cmp_ps(tmin, tmax, _CMP_LE_OQ));
}
#endif

// True when rays [0, n) have the same origin, bit for bit.
inline bool shares_origin(const Ray* rays, int n) {
  for (int r = 1; r < n; ++r)
    if (std::memcmp(&rays[r].org, &rays[0].org, sizeof(Vec3)) != 0) return false;
  return true;
}

// The packet walk for the kind of query and the rays' origins.
template <class BvhT, bool kAnyHit, bool kFma>
inline void traverse_packet_by(const BvhT& bvh, PacketRays& p, int live, Hit* hits, bool* found,
                               bool shared_origin) {
  if constexpr (kAnyHit) {
    if (shared_origin) return occlude_packet_with<BvhT, kFma, true>(bvh, p, live, hits, found);
    return occlude_packet_with<BvhT, kFma, false>(bvh, p, live, hits, found);
  } else {
    if (shared_origin) return traverse_packet_with<BvhT, kFma, true>(bvh, p, live, hits, found);
    return traverse_packet_with<BvhT, kFma, false>(bvh, p, live, hits, found);
  }
}

// A packet's per-ray constants ray by ray, for any n <= kPacketSize (the partial packet at the end
// of a batch, hosts without the FMA test; fill_full_packet's reference): WideRay, WatertightRay,
// tmax, and the FMA lanes where `fma` (every ray may take the FMA test). Returns the mask of live
// rays.
inline int fill_packet_ray_by_ray(PacketRays& p, const Ray* rays, int n, Hit* hits, bool* found,
                                  bool& fma) {
  int live = 0;
  fma = true;
  for (int r = 0; r < n; ++r) {
    hits[r] = Hit();
    hits[r].t = rays[r].tmax;
    found[r] = false;
    // Built in place: a temporary copied in went through the stack, a store-forwarding stall
    // per ray (~1/6 of the packet traversal's time on the dragon's shadow rays).
    ::new (&p.box[r]) WideRay(rays[r]);
    ::new (&p.wr[r]) WatertightRay(rays[r].org, rays[r].dir);
    p.tmax[r] = rays[r].tmax;
    // An empty segment hits nothing (nor does the single-ray traversal find anything there).
    if (rays[r].tmin <= rays[r].tmax) live |= 1 << r;
#if RTMINI_FMA_BOX_TEST
    fma = fma && fma_box_test_pays(rays[r], p.box[r]);
#endif
  }
  for (int r = n; r < kPacketSize; ++r) p.tmax[r] = Real(0);
#if RTMINI_FMA_BOX_TEST
  if (fma) fill_packet_lanes(p, n);
#else
  fma = false;
#endif
  return live;
}

// The packet traversal of rays [0, n) (n <= kPacketSize) with the FMA box test where every ray
// can take it (both tests are conservative; the choice is speed only).
template <class BvhT, bool kAnyHit>
inline void traverse_packet(const BvhT& bvh, const Ray* rays, int n, Hit* hits, bool* found) {
  PacketRays p;
  p.rays = rays;
  bool fma = false;
#if RTMINI_FMA_BOX_TEST
  // A full packet, the common case, is set up eight lanes at a time.
  const int live = n == kPacketSize ? fill_full_packet(p, rays, hits, found, fma)
                                    : fill_packet_ray_by_ray(p, rays, n, hits, found, fma);
#else
  const int live = fill_packet_ray_by_ray(p, rays, n, hits, found, fma);
#endif
  if (live == 0 || bvh.num_prims == 0) return;
  const bool shared = shares_origin(rays, n);
#if RTMINI_FMA_BOX_TEST
  if (fma) return traverse_packet_by<BvhT, kAnyHit, true>(bvh, p, live, hits, found, shared);
#endif
  traverse_packet_by<BvhT, kAnyHit, false>(bvh, p, live, hits, found, shared);
}
#else
inline constexpr bool kHavePacketTraversal = false;
#endif

template <class BvhT, bool kAnyHit, bool kStats>
KOKKOS_INLINE_FUNCTION bool traverse_any_layout(const BvhT& bvh, const Ray& ray, Hit& hit,
                                                TraversalStats* stats) {
  // Closest hits take the compressed wide layout where it was built (devices); any hits keep the
  // binary tree, which traced AO 1.3x faster on the H200 (results/gpu/README.md, issue 21).
  if constexpr (HasQuantizedWide<BvhT>::value && !kAnyHit) {
    if (bvh.qwide.extent(0) > 0)
      return traverse_quantized<BvhT, kAnyHit, kStats>(bvh, ray, hit, stats);
  }
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                           typename BvhT::memory_space>::accessible) {
    if (bvh.wide.extent(0) > 0) return traverse_wide<BvhT, kAnyHit, kStats>(bvh, ray, hit, stats);
  }
  return traverse<BvhT, kAnyHit, kStats>(bvh, ray, hit, stats);
}

}  // namespace detail

// Closest hit in [ray.tmin, ray.tmax]; hit.prim = -1 when nothing is hit.
template <class BvhT>
KOKKOS_INLINE_FUNCTION Hit closest_hit(const BvhT& bvh, const Ray& ray) {
  Hit hit;
  hit.t = ray.tmax;
  detail::traverse_any_layout<BvhT, false, false>(bvh, ray, hit, nullptr);
  return hit;
}

template <class BvhT>
KOKKOS_INLINE_FUNCTION Hit closest_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  Hit hit;
  hit.t = ray.tmax;
  detail::traverse_any_layout<BvhT, false, true>(bvh, ray, hit, &stats);
  return hit;
}

// True if anything blocks the segment [ray.tmin, ray.tmax].
template <class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray) {
  Hit hit;
  return detail::traverse_any_layout<BvhT, true, false>(bvh, ray, hit, nullptr);
}

template <class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  Hit hit;
  return detail::traverse_any_layout<BvhT, true, true>(bvh, ray, hit, &stats);
}

// Packets of coherent rays (host memory): rays [0, n), n <= kPacketSize, traced together. The
// answers equal closest_hit / any_hit of each ray bit for bit; they pay where the rays are
// coherent (a camera's rays, shadow rays toward one light: results/bvh/README.md). Without the
// host wide tree (or the vector extensions) each ray is traced alone.
template <class BvhT>
inline void closest_hit_packet(const BvhT& bvh, const Ray* rays, int n, Hit* hits) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                           typename BvhT::memory_space>::accessible) {
    // (the single-ray dispatch would take the compressed layout where it was built)
    const bool quantized = [&] {
      if constexpr (detail::HasQuantizedWide<BvhT>::value) return bvh.qwide.extent(0) > 0;
      return false;
    }();
    if (bvh.wide.extent(0) > 0 && !quantized) {
      bool found[kPacketSize];
      detail::traverse_packet<BvhT, false>(bvh, rays, n, hits, found);
      return;
    }
  }
#endif
  for (int r = 0; r < n; ++r) hits[r] = closest_hit(bvh, rays[r]);
}

// blocked[r] = any_hit(bvh, rays[r]) for rays [0, n), n <= kPacketSize, traced as one packet.
template <class BvhT>
inline void any_hit_packet(const BvhT& bvh, const Ray* rays, int n, bool* blocked) {
#if defined(__GNUC__) && !defined(__CUDACC__)
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                           typename BvhT::memory_space>::accessible) {
    if (bvh.wide.extent(0) > 0) {
      Hit hits[kPacketSize];
      detail::traverse_packet<BvhT, true>(bvh, rays, n, hits, blocked);
      return;
    }
  }
#endif
  for (int r = 0; r < n; ++r) blocked[r] = any_hit(bvh, rays[r]);
}

}  // namespace rtmini::bvh
