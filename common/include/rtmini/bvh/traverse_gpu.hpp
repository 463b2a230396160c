#pragma once
// Traversal of the compressed 8-wide BVH (gpu_wide.hpp), written for GPU threads: a node is
// loaded as six 16-byte words, its eight child boxes are decoded and tested with fully unrolled
// code (no dynamically indexed arrays, so nothing lands in local memory), and the stack holds
// node groups (Ylitie et al. 2017): one entry is a visited node's remaining inner hits, taken in
// octant order, so one push serves up to seven siblings. The top stack entries live in
// registers; deeper ones spill to a local array, which only unusually deep paths touch.
// Leaf triangles are tested as soon as their node is visited; results equal brute force exactly
// (same watertight test, same tie-break). On devices closest hits take this path and any hits
// the binary tree, which measured faster for AO (results/gpu/README.md, issue 21).
#include <type_traits>
#include <utility>

#include "rtmini/bvh/bvh.hpp"

#if defined(__CUDACC__)
#define RTMINI_UNROLL _Pragma("unroll")
#elif defined(__GNUC__) && !defined(__clang__)
#define RTMINI_UNROLL _Pragma("GCC unroll 8")
#else
#define RTMINI_UNROLL
#endif

namespace rtmini::bvh::detail {

KOKKOS_FORCEINLINE_FUNCTION int lowest_bit(std::uint32_t m) {  // m != 0
#if defined(__CUDA_ARCH__)
  return __ffs(static_cast<int>(m)) - 1;
#else
  return __builtin_ctz(m);
#endif
}
KOKKOS_FORCEINLINE_FUNCTION int lowest_bit(std::uint64_t m) {  // m != 0
#if defined(__CUDA_ARCH__)
  return __ffsll(static_cast<long long>(m)) - 1;
#else
  return __builtin_ctzll(m);
#endif
}
KOKKOS_FORCEINLINE_FUNCTION int popcount(std::uint32_t m) {
#if defined(__CUDA_ARCH__)
  return __popc(m);
#else
  return __builtin_popcount(m);
#endif
}

// Whether a BVH-shaped type carries the compressed wide layout (views of it may not).
template <class T, class = void>
struct HasQuantizedWide : std::false_type {};
template <class T>
struct HasQuantizedWide<T, std::void_t<decltype(std::declval<const T&>().qwide)>> : std::true_type {
};

// A node as words, loaded with 16-byte loads on the GPU.
struct NodeWords {
  std::uint32_t w[kQuantizedWords];
  KOKKOS_FORCEINLINE_FUNCTION std::uint32_t byte(int word, int k) const {
    return (w[word + (k >> 2)] >> ((k & 3) * 8)) & 0xffu;
  }
};

template <class NodeView>
KOKKOS_FORCEINLINE_FUNCTION NodeWords load_node(const NodeView& nodes, std::uint32_t i) {
  NodeWords n;
#if defined(__CUDA_ARCH__)
  const uint4* src = reinterpret_cast<const uint4*>(&nodes(i));
  RTMINI_UNROLL
  for (int j = 0; j < kQuantizedWords / 4; ++j) {
    const uint4 v = __ldg(src + j);
    n.w[4 * j] = v.x;
    n.w[4 * j + 1] = v.y;
    n.w[4 * j + 2] = v.z;
    n.w[4 * j + 3] = v.w;
  }
#else
  memcpy(n.w, &nodes(i), sizeof n.w);
#endif
  return n;
}

// Pending node groups (base | inner mask << 32 | remaining hits in octant order << 40): the top
// four in scalar registers, deeper ones in `deep`, an array the caller owns (local memory on the
// GPU, touched only by paths more than four groups deep). Scalars, not an array member: an
// aggregate with a dynamically indexed part would be placed in local memory whole.
struct GroupStack {
  std::uint64_t s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int depth = 0;

  KOKKOS_FORCEINLINE_FUNCTION bool empty() const { return depth == 0; }
  KOKKOS_FORCEINLINE_FUNCTION void push(std::uint64_t g, std::uint64_t* deep) {
    if (depth >= 4) deep[depth - 4] = s3;
    s3 = s2;
    s2 = s1;
    s1 = s0;
    s0 = g;
    ++depth;
  }
  KOKKOS_FORCEINLINE_FUNCTION std::uint64_t pop(const std::uint64_t* deep) {
    const std::uint64_t g = s0;
    s0 = s1;
    s1 = s2;
    s2 = s3;
    if (--depth >= 4) s3 = deep[depth - 4];
    return g;
  }
};

KOKKOS_FORCEINLINE_FUNCTION std::uint32_t group_hits(std::uint64_t g) {
  return static_cast<std::uint32_t>(g >> 40);
}

// The ray's origin along its permuted axes, once per ray.
KOKKOS_FORCEINLINE_FUNCTION Real axis(const Vec3& v, int k) {
  return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}
struct PermutedOrigin {
  Real x, y, z;
  KOKKOS_INLINE_FUNCTION explicit PermutedOrigin(const WatertightRay& r)
      : x(axis(r.org, r.kx)), y(axis(r.org, r.ky)), z(axis(r.org, r.kz)) {}
};

static_assert(sizeof(Triangle) == 9 * sizeof(Real), "a triangle is nine packed coordinates");

// intersect_triangle for a triangle in memory: the permuted coordinates are loaded by index
// from the triangle itself (one cached load each) rather than from a small indexed array, which
// the GPU would keep in local memory. Every value and operation is intersect_triangle's, so the
// results are its own bit for bit.
KOKKOS_FORCEINLINE_FUNCTION bool intersect_stored_triangle(const WatertightRay& r,
                                                           const PermutedOrigin& o,
                                                           const Triangle& tri, Real tmin,
                                                           Real tmax, Real& t_out, Real& u_out,
                                                           Real& v_out) {
  const Real* a = &tri.a.x;
  const Real* b = &tri.b.x;
  const Real* c = &tri.c.x;
  const Real Ax = a[r.kx] - o.x, Ay = a[r.ky] - o.y, Az = a[r.kz] - o.z;
  const Real Bx = b[r.kx] - o.x, By = b[r.ky] - o.y, Bz = b[r.kz] - o.z;
  const Real Cx = c[r.kx] - o.x, Cy = c[r.ky] - o.y, Cz = c[r.kz] - o.z;
  return intersect_permuted(r, Ax, Ay, Az, Bx, By, Bz, Cx, Cy, Cz, tmin, tmax, t_out, u_out, v_out);
}

// One axis of a node's slab test in the form of Ylitie et al.: a plane's ray distance is one
// fused multiply-add per child, t(q) = f(q) * scale + offset with f(q) = 1 + q / 256 made from
// the byte's bits (exact, no integer conversion), scale = 256 * 2^e / d (exact: a power of two
// times the reciprocal) and offset = ((origin - o) / d) - scale. That rounds differently from
// (origin + q * 2^e - o) / d, so near planes move down and far planes up by a margin that bounds
// every rounding involved (the decoded plane, the offset, the fused sum; about 4 ulps of the
// magnitudes, taken as 32): boxes stay conservative, never missing a hit.
struct SlabPlanes {
  Real scale, near_offset, far_offset;
  KOKKOS_FORCEINLINE_FUNCTION Real near(std::uint32_t q) const {
    return Real(compat::bit_cast<float>(0x3f800000u | q << 15)) * scale + near_offset;
  }
  KOKKOS_FORCEINLINE_FUNCTION Real far(std::uint32_t q) const {
    return Real(compat::bit_cast<float>(0x3f800000u | q << 15)) * scale + far_offset;
  }
};

KOKKOS_FORCEINLINE_FUNCTION SlabPlanes slab_planes(std::uint32_t origin_bits,
                                                   std::uint32_t biased_exponent, Real o,
                                                   Real inv) {
  const Real origin = compat::bit_cast<float>(origin_bits);
  const Real step = grid_step(biased_exponent);
  const Real d = origin - o;
  const Real scale = Real(256) * step * inv;
  const Real offset = d * inv - scale;
  constexpr Real kMaxMargin = sizeof(Real) == 4 ? Real(3e38) : Real(1e300);
  constexpr Real kRelative = sizeof(Real) == 4 ? Real(1.0 / (1 << 19)) : Real(1e-14);
  Real margin =
      ((math::fabs(d) + math::fabs(origin) + Real(256) * step) * math::fabs(inv)) * kRelative +
      Real(1e-30);
  margin = margin < kMaxMargin ? margin : kMaxMargin;
  return {scale, offset - margin, offset + margin};
}

// `stack` holds the pending node groups (GroupStack: registers, or the shared-memory ring of an
// any-hit variant, any_hit_gpu.hpp); either spills to a local array past its own entries.
template <class BvhT, bool kAnyHit, bool kStats, class Stats, class Stack = GroupStack>
KOKKOS_INLINE_FUNCTION bool traverse_quantized(const BvhT& bvh, const Ray& ray, Hit& hit,
                                               Stats* stats, Stack stack = Stack{}) {
  const WatertightRay wr(ray.org, ray.dir);
  const PermutedOrigin po(wr);
  const Vec3 inv(safe_reciprocal(ray.dir.x), safe_reciprocal(ray.dir.y),
                 safe_reciprocal(ray.dir.z));
  const bool neg_x = inv.x < 0, neg_y = inv.y < 0, neg_z = inv.z < 0;
  const std::uint32_t octant = (neg_x ? 1u : 0u) | (neg_y ? 2u : 0u) | (neg_z ? 4u : 0u);
  const Real widen = slab_widening();
  Real tmax = ray.tmax;
  std::uint64_t deep[kStackSize];
  std::uint64_t group = 0;
  std::uint32_t node = 0;
  bool found = false;
  while (true) {
    const NodeWords n = load_node(bvh.qwide, node);
    if (kStats) ++stats->nodes;
    const SlabPlanes x = slab_planes(n.w[0], n.byte(qword::kExponents, 0), ray.org.x, inv.x);
    const SlabPlanes y = slab_planes(n.w[1], n.byte(qword::kExponents, 1), ray.org.y, inv.y);
    const SlabPlanes z = slab_planes(n.w[2], n.byte(qword::kExponents, 2), ray.org.z, inv.z);
    const std::uint32_t inner_mask = n.byte(qword::kExponents, 3);
    // The near and far planes of each axis by the ray's direction; plane p of slots 0-3 is word
    // kPlanes + 2p, of slots 4-7 the word after it.
    constexpr int P = qword::kPlanes;
    const std::uint32_t nx0 = (neg_x ? n.w[P + 6] : n.w[P]),
                        nx1 = (neg_x ? n.w[P + 7] : n.w[P + 1]);
    const std::uint32_t fx0 = (neg_x ? n.w[P] : n.w[P + 6]),
                        fx1 = (neg_x ? n.w[P + 1] : n.w[P + 7]);
    const std::uint32_t ny0 = (neg_y ? n.w[P + 8] : n.w[P + 2]),
                        ny1 = (neg_y ? n.w[P + 9] : n.w[P + 3]);
    const std::uint32_t fy0 = (neg_y ? n.w[P + 2] : n.w[P + 8]),
                        fy1 = (neg_y ? n.w[P + 3] : n.w[P + 9]);
    const std::uint32_t nz0 = (neg_z ? n.w[P + 10] : n.w[P + 4]),
                        nz1 = (neg_z ? n.w[P + 11] : n.w[P + 5]);
    const std::uint32_t fz0 = (neg_z ? n.w[P + 4] : n.w[P + 10]),
                        fz1 = (neg_z ? n.w[P + 5] : n.w[P + 11]);
    const std::uint32_t counts0 = n.w[qword::kTriCount], counts1 = n.w[qword::kTriCount + 1];
    const std::uint32_t offsets0 = n.w[qword::kTriOffset], offsets1 = n.w[qword::kTriOffset + 1];
    std::uint32_t inner_hits = 0;
    std::uint64_t tri_hits = 0;
    RTMINI_UNROLL
    for (int k = 0; k < kQuantizedWidth; ++k) {
      const int shift = (k & 3) * 8;
      const auto slot_byte = [&](std::uint32_t w0, std::uint32_t w1) {
        return ((k < 4 ? w0 : w1) >> shift) & 0xffu;
      };
      Real near = x.near(slot_byte(nx0, nx1));
      const Real b = y.near(slot_byte(ny0, ny1)), c = z.near(slot_byte(nz0, nz1));
      Real far = x.far(slot_byte(fx0, fx1));
      const Real e = y.far(slot_byte(fy0, fy1)), f = z.far(slot_byte(fz0, fz1));
      near = b > near ? b : near;
      near = c > near ? c : near;
      near = ray.tmin > near ? ray.tmin : near;
      far = e < far ? e : far;
      far = f < far ? f : far;
      far = far * widen;
      const Real lim = tmax * widen;
      far = lim < far ? lim : far;
      const bool box_hit = near <= far;
      const std::uint32_t count = slot_byte(counts0, counts1);
      if (inner_mask >> k & 1u) {
        inner_hits |= (box_hit ? 1u : 0u) << (std::uint32_t(k) ^ octant);
      } else if (box_hit && count > 0) {
        tri_hits |= ((std::uint64_t(1) << count) - 1u) << slot_byte(offsets0, offsets1);
      }
    }
    // Leaf triangles now: a closer hit shrinks tmax before the inner children are taken.
    const std::uint32_t tri_base = n.w[qword::kTriBase];
    for (std::uint64_t m = tri_hits; m != 0; m &= m - 1) {
      const std::uint32_t i = tri_base + static_cast<std::uint32_t>(lowest_bit(m));
      if (kStats) ++stats->tests;
      Real t, u, v;
      if (!intersect_stored_triangle(wr, po, bvh.qwide_tris(i), ray.tmin, tmax, t, u, v)) continue;
      const int id = bvh.qwide_prim(i);
      if (kAnyHit || t < tmax || id < hit.prim || !found) {
        tmax = t;
        hit.t = t;
        hit.u = u;
        hit.v = v;
        hit.prim = id;
        found = true;
      }
      if (kAnyHit) return true;
    }
    if (inner_hits != 0) {
      if (group_hits(group) != 0) stack.push(group, deep);
      group = std::uint64_t(n.w[qword::kChildBase]) | std::uint64_t(inner_mask) << 32 |
              std::uint64_t(inner_hits) << 40;
    }
    if (group_hits(group) == 0) {
      if (stack.empty()) break;
      group = stack.pop(deep);
    }
    const int b = lowest_bit(group_hits(group));
    group &= ~(std::uint64_t(1) << (40 + b));
    const std::uint32_t k = static_cast<std::uint32_t>(b) ^ octant;
    const std::uint32_t mask = static_cast<std::uint32_t>(group >> 32) & 0xffu;
    node = static_cast<std::uint32_t>(group) +
           static_cast<std::uint32_t>(popcount(mask & ((1u << k) - 1u)));
  }
  return found;
}

}  // namespace rtmini::bvh::detail
