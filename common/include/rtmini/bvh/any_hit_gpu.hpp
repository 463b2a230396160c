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
//  - kDefaultBounded / kStoredBounded / kCompactBounded / kWideBounded: the same traversals
//    launched with launch bounds that make the compiler fit more threads per SM (at most 40
//    registers for the binary kernels, 64 for the wide one, which lost on occupancy: 72
//    registers, 38 % warps active).
//  - kShared8 / kShared16 / kWideShared: kStored's (the wide kernel's) loop with the newest 8 or
//    16 stack entries in shared memory (team scratch, one ring per thread, SharedRing below)
//    instead of local memory or registers; deeper entries spill to the local array.
//  - kCompact / kCompactBounded / kCompactShared16: kStored's loop (or kShared16's) over the
//    32-byte copy of the nodes (compact_node.hpp: planes as 16-bit counts on one grid per tree,
//    half of BvhNode's bytes per visit); the binary default where the tree has no such copy.
//  - kSpeculative / kSpeculativeShared16 / kSpeculativeCompact: Aila & Laine's while-while loop
//    with postponed leaves and speculative node fetches (SpeculativeAnyHitRay) over BvhNode with a
//    local stack, with kShared16's ring, or over the 32-byte nodes.
//
// Every binary variant answers exactly what brute force answers (same watertight test,
// tests/unit/core); those on BvhNode visit the same nodes as detail::traverse (near child first,
// far child pushed), the compact ones the nodes whose enclosing decoded boxes the ray meets.
#include <algorithm>
#include <string>
#include <type_traits>

#include "rtmini/bvh/traverse.hpp"
#include "rtmini/parallel/ray_loop.hpp"

namespace rtmini::bvh {

enum class AnyHitKernel {
  kDefault,
  kWide,
  kStored,
  kShort8,
  kShort16,
  kDefaultBounded,
  kStoredBounded,
  kCompactBounded,
  kWideBounded,
  kShared8,
  kShared16,
  kWideShared,
  kCompact,
  kCompactShared16,
  kSpeculative,
  kSpeculativeShared16,
  kSpeculativeCompact
};

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
    case AnyHitKernel::kDefaultBounded:
      return "default_lb";
    case AnyHitKernel::kStoredBounded:
      return "stored_lb";
    case AnyHitKernel::kCompactBounded:
      return "compact_lb";
    case AnyHitKernel::kWideBounded:
      return "wide_lb";
    case AnyHitKernel::kShared8:
      return "shared8";
    case AnyHitKernel::kShared16:
      return "shared16";
    case AnyHitKernel::kWideShared:
      return "wide_shared";
    case AnyHitKernel::kCompact:
      return "compact";
    case AnyHitKernel::kCompactShared16:
      return "compact_shared16";
    case AnyHitKernel::kSpeculative:
      return "speculative";
    case AnyHitKernel::kSpeculativeShared16:
      return "speculative_shared16";
    case AnyHitKernel::kSpeculativeCompact:
      return "speculative_compact";
  }
  return "?";
}

inline constexpr AnyHitKernel kAnyHitKernels[] = {AnyHitKernel::kDefault,
                                                  AnyHitKernel::kWide,
                                                  AnyHitKernel::kStored,
                                                  AnyHitKernel::kShort8,
                                                  AnyHitKernel::kShort16,
                                                  AnyHitKernel::kDefaultBounded,
                                                  AnyHitKernel::kStoredBounded,
                                                  AnyHitKernel::kCompactBounded,
                                                  AnyHitKernel::kWideBounded,
                                                  AnyHitKernel::kShared8,
                                                  AnyHitKernel::kShared16,
                                                  AnyHitKernel::kWideShared,
                                                  AnyHitKernel::kCompact,
                                                  AnyHitKernel::kCompactShared16,
                                                  AnyHitKernel::kSpeculative,
                                                  AnyHitKernel::kSpeculativeShared16,
                                                  AnyHitKernel::kSpeculativeCompact};

// False when `name` is none of the kernels' names.
inline bool parse_any_hit_kernel(const std::string& name, AnyHitKernel& out) {
  for (AnyHitKernel k : kAnyHitKernels)
    if (name == to_string(k)) {
      out = k;
      return true;
    }
  return false;
}

// The kernels' names, comma separated (for messages).
inline std::string any_hit_kernel_names() {
  std::string s;
  for (AnyHitKernel k : kAnyHitKernels) s += (s.empty() ? "" : ", ") + std::string(to_string(k));
  return s;
}

// Stack entries kept in registers by a kernel (0: the whole stack is the local array).
constexpr int register_stack_entries(AnyHitKernel k) {
  return k == AnyHitKernel::kShort8 ? 8 : (k == AnyHitKernel::kShort16 ? 16 : 0);
}

// Stack entries per thread kept in shared memory (0: none; the kernel runs as a RangePolicy).
constexpr int shared_stack_entries(AnyHitKernel k) {
  switch (k) {
    case AnyHitKernel::kShared8:
    case AnyHitKernel::kWideShared:
      return 8;
    case AnyHitKernel::kShared16:
    case AnyHitKernel::kCompactShared16:
    case AnyHitKernel::kSpeculativeShared16:
      return 16;
    default:
      return 0;
  }
}

// Whether a kernel traces the compressed 8-wide layout (where the tree has it).
constexpr bool traces_wide(AnyHitKernel k) {
  return k == AnyHitKernel::kWide || k == AnyHitKernel::kWideBounded ||
         k == AnyHitKernel::kWideShared;
}

// Whether a kernel traces the 32-byte binary nodes (bvh.compact, gpu_compact.hpp).
constexpr bool traces_compact_nodes(AnyHitKernel k) {
  return k == AnyHitKernel::kCompact || k == AnyHitKernel::kCompactBounded ||
         k == AnyHitKernel::kCompactShared16 || k == AnyHitKernel::kSpeculativeCompact;
}

// Whether a kernel postpones leaves and fetches nodes speculatively (SpeculativeAnyHitRay).
constexpr bool speculates(AnyHitKernel k) {
  return k == AnyHitKernel::kSpeculative || k == AnyHitKernel::kSpeculativeShared16 ||
         k == AnyHitKernel::kSpeculativeCompact;
}

// Whether a kernel is today's traversal (any_hit of traverse.hpp), whatever its launch.
constexpr bool traces_default(AnyHitKernel k) {
  return k == AnyHitKernel::kDefault || k == AnyHitKernel::kDefaultBounded;
}

// Launch bounds: threads per block and the blocks per SM the compiler must fit (0: none). With
// 65,536 registers per SM, 6 blocks of 256 threads leave 42 registers a thread (the allocation
// rounds to 40), 4 blocks leave 64.
inline constexpr unsigned kBoundedBlockThreads = 256;
constexpr unsigned launch_min_blocks(AnyHitKernel k) {
  switch (k) {
    case AnyHitKernel::kDefaultBounded:
    case AnyHitKernel::kStoredBounded:
    case AnyHitKernel::kCompactBounded:
      return 6;
    case AnyHitKernel::kWideBounded:
      return 4;
    default:
      return 0;
  }
}

namespace detail {

// A binary node fetched whole as 16-byte words (one request per 16 bytes instead of one per
// field) through the read-only cache on CUDA.
template <class T, class NodeView>
KOKKOS_FORCEINLINE_FUNCTION T load_words(const NodeView& nodes, std::uint32_t i) {
#if defined(__CUDA_ARCH__)
  static_assert(sizeof(T) % 16 == 0, "a node is a whole number of 16-byte words");
  T n;
  const uint4* src = reinterpret_cast<const uint4*>(&nodes(i));
  uint4* dst = reinterpret_cast<uint4*>(&n);
  RTMINI_UNROLL
  for (int j = 0; j < int(sizeof(T) / 16); ++j) dst[j] = __ldg(src + j);
  return n;
#else
  return nodes(i);
#endif
}

template <class NodeView>
KOKKOS_FORCEINLINE_FUNCTION BvhNode load_binary_node(const NodeView& nodes, std::uint32_t i) {
  return load_words<BvhNode>(nodes, i);
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

// Pending entries: the newest N (a power of two) in a ring in shared memory, older ones in `deep`
// (the caller's local array). Entry j of a team's thread r sits at ring + j * stride with stride
// the team size, so the 32 lanes of a warp always touch 32 consecutive words, whatever depth each
// is at: no bank conflicts. Entry d lives in slot d mod N while the ray is no deeper than d + N;
// a push past N entries moves the oldest to `deep`, a pop back to N or more brings it back.
template <int N, class T>
struct SharedRing {
  static_assert(N > 0 && (N & (N - 1)) == 0, "the ring's length is a power of two");
  T* ring;
  int stride;
  int depth = 0;

  KOKKOS_FORCEINLINE_FUNCTION SharedRing(T* r, int s) : ring(r), stride(s) {}
  KOKKOS_FORCEINLINE_FUNCTION bool empty() const { return depth == 0; }
  KOKKOS_FORCEINLINE_FUNCTION void push(T v, T* deep) {
    T& slot = ring[(depth & (N - 1)) * stride];
    if (depth >= N) deep[depth - N] = slot;
    slot = v;
    ++depth;
  }
  KOKKOS_FORCEINLINE_FUNCTION T pop(const T* deep) {
    T& slot = ring[(--depth & (N - 1)) * stride];
    const T v = slot;
    if (depth >= N) slot = deep[depth - N];
    return v;
  }
};

// A binary node's two child boxes and references, from either layout.
struct BinaryChildren {
  Vec3 lo0, hi0, lo1, hi1;
  std::uint32_t c0, c1;
};

template <class NodeView>
KOKKOS_FORCEINLINE_FUNCTION BinaryChildren binary_children(const NodeView& nodes, std::uint32_t i) {
  const BvhNode nd = load_binary_node(nodes, i);
  return {Vec3(nd.lo_x[0], nd.lo_y[0], nd.lo_z[0]),
          Vec3(nd.hi_x[0], nd.hi_y[0], nd.hi_z[0]),
          Vec3(nd.lo_x[1], nd.lo_y[1], nd.lo_z[1]),
          Vec3(nd.hi_x[1], nd.hi_y[1], nd.hi_z[1]),
          nd.child[0],
          nd.child[1]};
}

// The decoded boxes of a 32-byte node: plane p is the 16-bit half (p & 1) of word p / 2.
template <class NodeView>
KOKKOS_FORCEINLINE_FUNCTION BinaryChildren compact_children(const NodeView& nodes,
                                                            const CompactGrid& g, std::uint32_t i) {
  struct alignas(16) Words {  // stored to as 16-byte words
    std::uint32_t w[8];
  };
  static_assert(sizeof(Words) == sizeof(CompactBvhNode), "a compact node is eight words");
#if defined(__CUDA_ARCH__)
  const Words n = load_words<Words>(nodes, i);
#else
  Words n;
  memcpy(n.w, &nodes(i), sizeof n.w);
#endif
  const auto lo_half = [&](int w) { return n.w[w] & 0xffffu; };
  const auto hi_half = [&](int w) { return n.w[w] >> 16; };
  return {Vec3(grid_plane(g, 0, lo_half(0)), grid_plane(g, 1, lo_half(1)),
               grid_plane(g, 2, lo_half(2))),
          Vec3(grid_plane(g, 0, lo_half(3)), grid_plane(g, 1, lo_half(4)),
               grid_plane(g, 2, lo_half(5))),
          Vec3(grid_plane(g, 0, hi_half(0)), grid_plane(g, 1, hi_half(1)),
               grid_plane(g, 2, hi_half(2))),
          Vec3(grid_plane(g, 0, hi_half(3)), grid_plane(g, 1, hi_half(4)),
               grid_plane(g, 2, hi_half(5))),
          n.w[6],
          n.w[7]};
}

// What one node visit left the ray at.
enum class AnyHitStep { kGoing, kBlocked, kClear };

// One ray's any-hit traversal of the binary tree (kCompact: its 32-byte copy) as a state
// advanced one node per step(), its pending far children in `stack` (ShortStack or SharedRing).
template <class Stack, bool kCompact>
struct BinaryAnyHitRay {
  WatertightRay wr;
  PermutedOrigin po;
  RaySlab rs;
  Real tmin, tmax;
  std::uint32_t node = 0;
  Stack stack;

  KOKKOS_INLINE_FUNCTION BinaryAnyHitRay(const Ray& ray, const Stack& s)
      : wr(ray.org, ray.dir),
        po(wr),
        rs(ray.org, ray.dir),
        tmin(ray.tmin),
        tmax(ray.tmax),
        stack(s) {}

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

  template <class BvhT>
  KOKKOS_FORCEINLINE_FUNCTION BinaryChildren children(const BvhT& bvh, std::uint32_t i) const {
    if constexpr (kCompact)
      return compact_children(bvh.compact, bvh.grid, i);
    else
      return binary_children(bvh.nodes, i);
  }

  template <class BvhT, bool kStats>
  KOKKOS_INLINE_FUNCTION AnyHitStep step(const BvhT& bvh, std::uint32_t* deep,
                                         TraversalStats* stats) {
    const BinaryChildren nd = children(bvh, node);
    if (kStats) ++stats->nodes;
    Real t0, t1;
    bool h0 = slab_test(rs, nd.lo0, nd.hi0, tmin, tmax, t0);
    bool h1 = slab_test(rs, nd.lo1, nd.hi1, tmin, tmax, t1);
    const std::uint32_t c0 = nd.c0, c1 = nd.c1;
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
template <bool kCompact, bool kStats, class BvhT, class Stack>
KOKKOS_INLINE_FUNCTION bool any_hit_binary(const BvhT& bvh, const Ray& ray, const Stack& stack,
                                           TraversalStats* stats) {
  if (bvh.num_prims == 0) return false;
  BinaryAnyHitRay<Stack, kCompact> r(ray, stack);
  std::uint32_t deep[kStackSize];
  AnyHitStep s;
  do {
    s = r.template step<BvhT, kStats>(bvh, deep, stats);
  } while (s == AnyHitStep::kGoing);
  return s == AnyHitStep::kBlocked;
}

// Aila & Laine's (2009) while-while traversal with speculative node fetches, for any hit on the
// binary tree: a lane that meets a leaf keeps it pending and goes on visiting nodes until every
// converged lane of its warp holds a leaf (compat::warp_all) or it meets a second one; then the
// pending leaves are tested. Node visits and triangle tests thus run with more lanes of a warp
// at once (9.75 of 32 active for the default, results/gpu/README.md). The vote only decides when
// leaves are tested, never which: every hit leaf is tested before the ray ends, so the answer
// is brute force's on any warp width (the host's lane is its own warp: no speculation). Vote
// stands in for the warp in tests (NeverAllVote: as far as a lane can speculate).
struct WarpVote {
  KOKKOS_FORCEINLINE_FUNCTION static bool all(bool p) { return compat::warp_all(p); }
};
struct NeverAllVote {
  KOKKOS_FORCEINLINE_FUNCTION static bool all(bool) { return false; }
};

template <class Stack, bool kCompact, class Vote = WarpVote>
struct SpeculativeAnyHitRay : BinaryAnyHitRay<Stack, kCompact> {
  static constexpr std::uint32_t kDone = 0x7fffffffu;  // no node left: an inner index past any tree
  static constexpr std::uint32_t kNoLeaf = 0u;         // no pending leaf: the root, never a leaf

  using BinaryAnyHitRay<Stack, kCompact>::BinaryAnyHitRay;

  KOKKOS_FORCEINLINE_FUNCTION std::uint32_t pop_or_done(const std::uint32_t* deep) {
    return this->stack.empty() ? kDone : this->stack.pop(deep);
  }

  // Visits inner node i: the child to take next (near one first, the far one pushed), a leaf
  // included, or the next pending entry, or kDone.
  template <class BvhT, bool kStats>
  KOKKOS_FORCEINLINE_FUNCTION std::uint32_t visit(const BvhT& bvh, std::uint32_t i,
                                                  std::uint32_t* deep, TraversalStats* stats) {
    const BinaryChildren nd = this->children(bvh, i);
    if (kStats) ++stats->nodes;
    Real t0, t1;
    const bool h0 = slab_test(this->rs, nd.lo0, nd.hi0, this->tmin, this->tmax, t0);
    const bool h1 = slab_test(this->rs, nd.lo1, nd.hi1, this->tmin, this->tmax, t1);
    if (h0 && h1) {
      const bool first0 = t0 <= t1;
      this->stack.push(first0 ? nd.c1 : nd.c0, deep);
      return first0 ? nd.c0 : nd.c1;
    }
    if (h0 || h1) return h0 ? nd.c0 : nd.c1;
    return pop_or_done(deep);
  }

  template <class BvhT, bool kStats>
  KOKKOS_INLINE_FUNCTION bool blocked(const BvhT& bvh, std::uint32_t* deep, TraversalStats* stats) {
    std::uint32_t ref = 0, leaf = kNoLeaf;
    while (true) {
      while (ref != kDone && !is_leaf(ref)) {
        ref = visit<BvhT, kStats>(bvh, ref, deep, stats);
        if (is_leaf(ref) && leaf == kNoLeaf) {
          leaf = ref;
          ref = pop_or_done(deep);
        }
        if (Vote::all(leaf != kNoLeaf)) break;
      }
      // The pending leaf, then `ref` while it is one (kDone is not).
      while (leaf != kNoLeaf || is_leaf(ref)) {
        std::uint32_t l = leaf;
        if (leaf != kNoLeaf) {
          leaf = kNoLeaf;
        } else {
          l = ref;
          ref = pop_or_done(deep);
        }
        if (this->template leaf_blocks<BvhT, kStats>(bvh, l, stats)) return true;
      }
      if (ref == kDone) return false;
    }
  }
};

template <bool kCompact, bool kStats, class BvhT, class Stack, class Vote = WarpVote>
KOKKOS_INLINE_FUNCTION bool any_hit_speculative(const BvhT& bvh, const Ray& ray, const Stack& stack,
                                                TraversalStats* stats) {
  if (bvh.num_prims == 0) return false;
  SpeculativeAnyHitRay<Stack, kCompact, Vote> r(ray, stack);
  std::uint32_t deep[kStackSize];
  return r.template blocked<BvhT, kStats>(bvh, deep, stats);
}

// Whether a BVH-shaped type carries the 32-byte node copy (views of it may not).
template <class T, class = void>
struct HasCompactBinary : std::false_type {};
template <class T>
struct HasCompactBinary<T, std::void_t<decltype(std::declval<const T&>().compact)>>
    : std::true_type {};

template <bool kStats, class BvhT>
KOKKOS_FORCEINLINE_FUNCTION bool default_any_hit(const BvhT& bvh, const Ray& ray,
                                                 TraversalStats* stats) {
  if constexpr (kStats)
    return any_hit(bvh, ray, *stats);
  else
    return any_hit(bvh, ray);
}

// Any hit through kernel K's traversal with `stack` for its pending entries (a SharedRing for
// the shared-memory kernels; ShortStack or GroupStack otherwise).
template <AnyHitKernel K, bool kStats, class BvhT, class Stack>
KOKKOS_INLINE_FUNCTION bool kernel_any_hit(const BvhT& bvh, const Ray& ray, const Stack& stack,
                                           TraversalStats* stats) {
  if constexpr (traces_default(K)) {
    return default_any_hit<kStats>(bvh, ray, stats);
  } else if constexpr (traces_wide(K)) {
    if constexpr (HasQuantizedWide<BvhT>::value) {
      if (bvh.qwide.extent(0) > 0) {
        Hit hit;
        return traverse_quantized<BvhT, true, kStats, TraversalStats, Stack>(bvh, ray, hit, stats,
                                                                             stack);
      }
    }
    return default_any_hit<kStats>(bvh, ray, stats);
  } else if constexpr (traces_compact_nodes(K)) {
    if constexpr (HasCompactBinary<BvhT>::value) {
      if (bvh.compact.extent(0) > 0) {
        if constexpr (speculates(K))
          return any_hit_speculative<true, kStats>(bvh, ray, stack, stats);
        else
          return any_hit_binary<true, kStats>(bvh, ray, stack, stats);
      }
    }
    return default_any_hit<kStats>(bvh, ray, stats);
  } else if constexpr (speculates(K)) {
    return any_hit_speculative<false, kStats>(bvh, ray, stack, stats);
  } else {
    return any_hit_binary<false, kStats>(bvh, ray, stack, stats);
  }
}

// The stack of a kernel without shared memory: node groups in registers for the wide traversal,
// the newest register_stack_entries(K) far children in registers for the binary ones.
template <AnyHitKernel K>
using RegisterStack =
    std::conditional_t<traces_wide(K), GroupStack, ShortStack<register_stack_entries(K)>>;

// A shared-memory kernel's stack entry: a node group (wide) or a far child (binary).
template <AnyHitKernel K>
using StackEntry = std::conditional_t<traces_wide(K), std::uint64_t, std::uint32_t>;

}  // namespace detail

// Any hit through the kernel K (those with a shared-memory stack run only through any_hit_all).
template <AnyHitKernel K, class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray) {
  static_assert(shared_stack_entries(K) == 0, "shared-memory stacks need any_hit_all's teams");
  return detail::kernel_any_hit<K, false>(bvh, ray, detail::RegisterStack<K>{}, nullptr);
}

template <AnyHitKernel K, class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  static_assert(shared_stack_entries(K) == 0, "shared-memory stacks need any_hit_all's teams");
  return detail::kernel_any_hit<K, true>(bvh, ray, detail::RegisterStack<K>{}, &stats);
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

// One thread per ray in teams of `team_size()` consecutive rays, each thread's stack ring in the
// team's scratch (shared memory on GPUs).
template <AnyHitKernel K, class ExecSpace, class BvhT, class RayOf, class Store>
struct AnyHitEachRayInTeam {
  using Member = typename Kokkos::TeamPolicy<ExecSpace>::member_type;
  using Entry = StackEntry<K>;
  static constexpr int kEntries = shared_stack_entries(K);
  BvhT bvh;
  RayOf ray_of;
  Store store;
  std::int64_t n;

  KOKKOS_INLINE_FUNCTION static std::size_t scratch_bytes(int team_size) {
    return sizeof(Entry) * std::size_t(kEntries) * std::size_t(team_size);
  }
  KOKKOS_INLINE_FUNCTION void operator()(const Member& team) const {
    const int size = team.team_size(), rank = team.team_rank();
    Entry* ring = static_cast<Entry*>(team.team_shmem().get_shmem(scratch_bytes(size)));
    const std::int64_t i = std::int64_t(team.league_rank()) * size + rank;
    if (i >= n) return;
    const SharedRing<kEntries, Entry> stack(ring + rank, size);
    store(i, kernel_any_hit<K, false>(bvh, ray_of(i), stack, nullptr));
  }
};

inline constexpr int kSharedStackTeam = 128;  // threads per team of the shared-memory kernels

}  // namespace detail

// Any hit of rays 0..n-1 with the kernel K, one thread per ray: ray_of(i) is ray i,
// store(i, blocked) records its answer.
template <AnyHitKernel K, class ExecSpace, class BvhT, class RayOf, class Store>
void any_hit_all(const ExecSpace& space, const BvhT& bvh, std::int64_t n, const RayOf& ray_of,
                 const Store& store) {
  constexpr const char* kLabel = "rtmini::bvh::any_hit_all";
  if constexpr (shared_stack_entries(K) > 0) {
    using Functor = detail::AnyHitEachRayInTeam<K, ExecSpace, BvhT, RayOf, Store>;
    const Functor f{bvh, ray_of, store, n};
    const int most = Kokkos::TeamPolicy<ExecSpace>(space, 1, Kokkos::AUTO)
                         .team_size_max(f, Kokkos::ParallelForTag());
    const int team = std::min(detail::kSharedStackTeam, most);
    const int league = static_cast<int>((n + team - 1) / team);
    if (league == 0) return;
    Kokkos::parallel_for(kLabel,
                         Kokkos::TeamPolicy<ExecSpace>(space, league, team)
                             .set_scratch_size(0, Kokkos::PerTeam(Functor::scratch_bytes(team))),
                         f);
  } else if constexpr (launch_min_blocks(K) > 0) {
    using Bounds = Kokkos::LaunchBounds<kBoundedBlockThreads, launch_min_blocks(K)>;
    Kokkos::parallel_for(kLabel, Kokkos::RangePolicy<ExecSpace, Bounds>(space, 0, n),
                         detail::AnyHitEachRay<K, BvhT, RayOf, Store>{bvh, ray_of, store});
  } else {
    Kokkos::parallel_for(kLabel, RayLoopPolicy<ExecSpace>(space, 0, n),
                         detail::AnyHitEachRay<K, BvhT, RayOf, Store>{bvh, ray_of, store});
  }
}

}  // namespace rtmini::bvh
