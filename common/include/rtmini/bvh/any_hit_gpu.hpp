#pragma once
// Any-hit traversal of the binary BVH written for GPU threads (issue 21), as variants the
// benchmark chooses at run time so one device run measures them against today's kernel:
//
//  - kStored: today's loop, but the node is fetched as 16-byte words and each triangle's
//    permuted coordinates are loaded by index from the triangle itself (intersect_stored_triangle)
//    instead of from the small indexed arrays of intersect_triangle, which the GPU keeps in local
//    memory. The 64-entry stack stays a local array.
//  - kShort8 / kShort16: as kStored with the top 8 or 16 stack entries in registers (a shift
//    register: push and pop move every entry, with constant indices only, so nothing of it is
//    placed in local memory); deeper entries spill to the local array, which only paths with more
//    pending siblings than that touch. Always correct: no entry is dropped, no restart needed.
//  (Persistent threads fetching rays from a global counter, with eager or lazy ray replacement
//    after Aila & Laine 2009, were tried too: on the H200 their kernels did not finish within
//    60 s, bench and unit tests alike (results/gpu/README.md, 2026-11-24), so they were removed
//    rather than kept unvalidated.)
//  - kWide: the compressed 8-wide traversal that closest hits use on devices (traverse_gpu.hpp),
//    for any hits too (the in-run reference of results/gpu/README.md's 0.76x; the binary
//    default where the tree has no compressed copy, as on the host).
//
// Every variant visits the same nodes as detail::traverse (near child first, far child pushed)
// and answers exactly what brute force answers (same watertight test, tests/unit/core).
#include <algorithm>
#include <string>

#include "rtmini/bvh/traverse.hpp"

namespace rtmini::bvh {

enum class AnyHitKernel { kDefault, kWide, kStored, kShort8, kShort16 };

inline const char* to_string(AnyHitKernel k) {
  switch (k) {
    case AnyHitKernel::kDefault:
      return "default";
    case AnyHitKernel::kWide:
      return "wide";
    case AnyHitKernel::kStored:
      return "stored";
    case AnyHitKernel::kShort8:
      return "short8";
    case AnyHitKernel::kShort16:
      return "short16";
  }
  return "?";
}

inline constexpr AnyHitKernel kAnyHitKernels[] = {AnyHitKernel::kDefault, AnyHitKernel::kWide,
                                                  AnyHitKernel::kStored, AnyHitKernel::kShort8,
                                                  AnyHitKernel::kShort16};

// False when `name` is none of the kernels' names.
inline bool parse_any_hit_kernel(const std::string& name, AnyHitKernel& out) {
  for (AnyHitKernel k : kAnyHitKernels)
    if (name == to_string(k)) {
      out = k;
      return true;
    }
  return false;
}

// Stack entries kept in registers by a kernel (0: the whole stack is the local array).
constexpr int register_stack_entries(AnyHitKernel k) {
  return k == AnyHitKernel::kShort8 ? 8 : (k == AnyHitKernel::kShort16 ? 16 : 0);
}

namespace detail {

// A binary node fetched whole as 16-byte words (one request per 16 bytes instead of one per
// field) through the read-only cache on CUDA.
template <class NodeView>
KOKKOS_FORCEINLINE_FUNCTION BvhNode load_binary_node(const NodeView& nodes, std::uint32_t i) {
#if defined(__CUDA_ARCH__)
  static_assert(sizeof(BvhNode) % 16 == 0, "BvhNode is a whole number of 16-byte words");
  BvhNode n;
  const uint4* src = reinterpret_cast<const uint4*>(&nodes(i));
  uint4* dst = reinterpret_cast<uint4*>(&n);
  RTMINI_UNROLL
  for (int j = 0; j < int(sizeof(BvhNode) / 16); ++j) dst[j] = __ldg(src + j);
  return n;
#else
  return nodes(i);
#endif
}

// Pending far children: the newest N in registers, older ones in `deep` (the caller's local
// array of kStackSize entries). N = 0 keeps everything in `deep`.
template <int N>
struct ShortStack {
  std::uint32_t top[N > 0 ? N : 1] = {};  // zeroed: the shifts copy unused entries too
  int depth = 0;

  KOKKOS_FORCEINLINE_FUNCTION bool empty() const { return depth == 0; }
  KOKKOS_FORCEINLINE_FUNCTION void push(std::uint32_t v, std::uint32_t* deep) {
    if constexpr (N == 0) {
      deep[depth++] = v;
    } else {
      if (depth >= N) deep[depth - N] = top[N - 1];
      RTMINI_UNROLL
      for (int j = N - 1; j > 0; --j) top[j] = top[j - 1];
      top[0] = v;
      ++depth;
    }
  }
  KOKKOS_FORCEINLINE_FUNCTION std::uint32_t pop(const std::uint32_t* deep) {
    if constexpr (N == 0) {
      return deep[--depth];
    } else {
      const std::uint32_t v = top[0];
      RTMINI_UNROLL
      for (int j = 0; j < N - 1; ++j) top[j] = top[j + 1];
      if (--depth >= N) top[N - 1] = deep[depth - N];
      return v;
    }
  }
};

// What one node visit left the ray at.
enum class AnyHitStep { kGoing, kBlocked, kClear };

// One ray's any-hit traversal as a state advanced one node per step() (a driver could also
// replace ended rays between steps; see the note on persistent threads at the top).
template <int N>
struct BinaryAnyHitRay {
  WatertightRay wr;
  PermutedOrigin po;
  RaySlab rs;
  Real tmin, tmax;
  std::uint32_t node = 0;
  ShortStack<N> stack;

  KOKKOS_INLINE_FUNCTION explicit BinaryAnyHitRay(const Ray& ray)
      : wr(ray.org, ray.dir), po(wr), rs(ray.org, ray.dir), tmin(ray.tmin), tmax(ray.tmax) {}

  // Whether a triangle of a hit leaf blocks the ray.
  template <class BvhT, bool kStats>
  KOKKOS_FORCEINLINE_FUNCTION bool leaf_blocks(const BvhT& bvh, std::uint32_t c,
                                               TraversalStats* stats) const {
    if (c == kEmptyLeaf) return false;
    const std::uint32_t first = leaf_first(c), end = first + leaf_count(c);
    for (std::uint32_t i = first; i < end; ++i) {
      if (kStats) ++stats->tests;
      Real t, u, v;
      if (intersect_stored_triangle(wr, po, bvh.tris(i), tmin, tmax, t, u, v)) return true;
    }
    return false;
  }

  template <class BvhT, bool kStats>
  KOKKOS_INLINE_FUNCTION AnyHitStep step(const BvhT& bvh, std::uint32_t* deep,
                                         TraversalStats* stats) {
    const BvhNode nd = load_binary_node(bvh.nodes, node);
    if (kStats) ++stats->nodes;
    Real t0, t1;
    bool h0 = slab_test(rs, Vec3(nd.lo_x[0], nd.lo_y[0], nd.lo_z[0]),
                        Vec3(nd.hi_x[0], nd.hi_y[0], nd.hi_z[0]), tmin, tmax, t0);
    bool h1 = slab_test(rs, Vec3(nd.lo_x[1], nd.lo_y[1], nd.lo_z[1]),
                        Vec3(nd.hi_x[1], nd.hi_y[1], nd.hi_z[1]), tmin, tmax, t1);
    const std::uint32_t c0 = nd.child[0], c1 = nd.child[1];
    if (h0 && is_leaf(c0)) {
      if (leaf_blocks<BvhT, kStats>(bvh, c0, stats)) return AnyHitStep::kBlocked;
      h0 = false;
    }
    if (h1 && is_leaf(c1)) {
      if (leaf_blocks<BvhT, kStats>(bvh, c1, stats)) return AnyHitStep::kBlocked;
      h1 = false;
    }
    if (h0 && h1) {
      const bool first0 = t0 <= t1;
      stack.push(first0 ? c1 : c0, deep);
      node = first0 ? c0 : c1;
    } else if (h0 || h1) {
      node = h0 ? c0 : c1;
    } else {
      if (stack.empty()) return AnyHitStep::kClear;
      node = stack.pop(deep);
    }
    return AnyHitStep::kGoing;
  }
};

// Any hit through one of the binary-tree kernels, one ray to its end.
template <int N, bool kStats, class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit_binary(const BvhT& bvh, const Ray& ray, TraversalStats* stats) {
  if (bvh.num_prims == 0) return false;
  BinaryAnyHitRay<N> r(ray);
  std::uint32_t deep[kStackSize];
  AnyHitStep s;
  do {
    s = r.template step<BvhT, kStats>(bvh, deep, stats);
  } while (s == AnyHitStep::kGoing);
  return s == AnyHitStep::kBlocked;
}

}  // namespace detail

// Any hit through the kernel K.
template <AnyHitKernel K, class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray) {
  if constexpr (K == AnyHitKernel::kWide && detail::HasQuantizedWide<BvhT>::value) {
    if (bvh.qwide.extent(0) == 0) return any_hit(bvh, ray);
    Hit hit;
    return detail::traverse_quantized<BvhT, true, false, TraversalStats>(bvh, ray, hit, nullptr);
  } else if constexpr (K == AnyHitKernel::kDefault || K == AnyHitKernel::kWide) {
    return any_hit(bvh, ray);
  } else {
    return detail::any_hit_binary<register_stack_entries(K), false>(bvh, ray, nullptr);
  }
}

template <AnyHitKernel K, class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  if constexpr (K == AnyHitKernel::kWide && detail::HasQuantizedWide<BvhT>::value) {
    if (bvh.qwide.extent(0) == 0) return any_hit(bvh, ray, stats);
    Hit hit;
    return detail::traverse_quantized<BvhT, true, true, TraversalStats>(bvh, ray, hit, &stats);
  } else if constexpr (K == AnyHitKernel::kDefault || K == AnyHitKernel::kWide) {
    return any_hit(bvh, ray, stats);
  } else {
    return detail::any_hit_binary<register_stack_entries(K), true>(bvh, ray, &stats);
  }
}

namespace detail {

// The drivers as functors rather than lambdas: nvcc's extended lambdas may not sit in a function
// template instantiated with a caller's local or unnamed-namespace types (the bench's, the tests').
template <AnyHitKernel K, class BvhT, class RayOf, class Store>
struct AnyHitEachRay {
  BvhT bvh;
  RayOf ray_of;
  Store store;
  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t i) const {
    store(i, any_hit<K>(bvh, ray_of(i)));
  }
};

}  // namespace detail

// Any hit of rays 0..n-1 with the kernel K, one thread per ray: ray_of(i) is ray i,
// store(i, blocked) records its answer.
template <AnyHitKernel K, class ExecSpace, class BvhT, class RayOf, class Store>
void any_hit_all(const ExecSpace& space, const BvhT& bvh, std::int64_t n, const RayOf& ray_of,
                 const Store& store) {
  Kokkos::parallel_for("rtmini::bvh::any_hit_all", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
                       detail::AnyHitEachRay<K, BvhT, RayOf, Store>{bvh, ray_of, store});
}

}  // namespace rtmini::bvh
