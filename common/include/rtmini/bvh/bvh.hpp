#pragma once
// The BVH shared by every kernel: a binary tree whose nodes store both
// children's boxes (one node fetch tests two boxes), leaves of up to 8
// triangles stored contiguously in leaf order. Built by build_lbvh.hpp
// (Karras 2012, on any Kokkos backend) or build_sah.hpp (binned SAH, host).
#include <cstdint>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/bvh/compact_node.hpp"
#include "rtmini/bvh/gpu_wide.hpp"
#include "rtmini/geometry/aabb.hpp"
#include "rtmini/geometry/triangle.hpp"

namespace rtmini::bvh {

inline constexpr int kMaxLeafSize = 8;
inline constexpr int kStackSize = 64;  // builders guarantee depth <= kStackSize
inline constexpr std::uint32_t kLeafBit = 0x80000000u;
// A child slot with nothing in it (only in one-triangle trees): all bits set
// (no real leaf has first = 2^28 - 1 with 8 triangles), and an empty box.
inline constexpr std::uint32_t kEmptyLeaf = 0xffffffffu;

// Child reference: an internal node index, or kLeafBit | first << 3 | (count - 1).
KOKKOS_INLINE_FUNCTION constexpr std::uint32_t make_leaf(std::uint32_t first, std::uint32_t count) {
  return kLeafBit | (first << 3) | (count - 1u);
}
KOKKOS_INLINE_FUNCTION constexpr bool is_leaf(std::uint32_t c) { return (c & kLeafBit) != 0u; }
KOKKOS_INLINE_FUNCTION constexpr std::uint32_t leaf_first(std::uint32_t c) {
  return (c & ~kLeafBit) >> 3;
}
KOKKOS_INLINE_FUNCTION constexpr std::uint32_t leaf_count(std::uint32_t c) { return (c & 7u) + 1u; }

struct alignas(16) BvhNode {
  Real lo_x[2], lo_y[2], lo_z[2];
  Real hi_x[2], hi_y[2], hi_z[2];
  std::uint32_t child[2];

  KOKKOS_INLINE_FUNCTION void set_child(int k, const Aabb& box, std::uint32_t ref) {
    lo_x[k] = box.lo.x;
    lo_y[k] = box.lo.y;
    lo_z[k] = box.lo.z;
    hi_x[k] = box.hi.x;
    hi_y[k] = box.hi.y;
    hi_z[k] = box.hi.z;
    child[k] = ref;
  }
  KOKKOS_INLINE_FUNCTION Aabb box(int k) const {
    Aabb b;
    b.lo = Vec3(lo_x[k], lo_y[k], lo_z[k]);
    b.hi = Vec3(hi_x[k], hi_y[k], hi_z[k]);
    return b;
  }
};

// Device-resident BVH. tris and prim are in leaf order; prim maps a leaf slot
// back to the caller's triangle index, which is what queries report.
// 8-wide node for CPU traversal (see wide.hpp): the eight children's boxes as
// structure-of-arrays lanes so one visit tests eight boxes with SIMD (AVX: one 256-bit op per
// plane; 8 was 10 % faster than 4 on the dragon AO workload, 10.4 instead of 15.8 node visits per
// ray).
inline constexpr int kWidth = 8;
struct alignas(64) WideNode {
  Real lo_x[kWidth], lo_y[kWidth], lo_z[kWidth];
  Real hi_x[kWidth], hi_y[kWidth], hi_z[kWidth];
  // Same encoding as BvhNode, but a leaf's `first` counts halves of Bvh::leaves' blocks
  // (TriangleLanes, below); kEmptyLeaf = unused lane.
  std::uint32_t child[kWidth];
};

// The triangles of one wide-BVH leaf as structure-of-arrays lanes, so one SIMD pass runs the
// watertight test on all of them (traverse.hpp). Lanes at and past the leaf's count are unused.
// A leaf of at most kCompactLeafSize triangles is stored compact, in one half of a block: the
// same nine rows and prim ids, four lanes per row (rows of 16 bytes, 160 bytes in all), so its
// test touches three cache lines instead of five (the leaves' first use was a quarter of the
// traversal's time, results/bvh/README.md). A leaf reference's `first` counts half blocks; a
// full leaf starts at an even one.
inline constexpr int kCompactLeafSize = kMaxLeafSize / 2;
struct alignas(64) TriangleLanes {
  Real ax[kMaxLeafSize], ay[kMaxLeafSize], az[kMaxLeafSize];
  Real bx[kMaxLeafSize], by[kMaxLeafSize], bz[kMaxLeafSize];
  Real cx[kMaxLeafSize], cy[kMaxLeafSize], cz[kMaxLeafSize];
  int prim[kMaxLeafSize];
};

template <class MemorySpace>
struct Bvh {
  using memory_space = MemorySpace;
  Kokkos::View<BvhNode*, MemorySpace> nodes;
  // 8-wide copy of the same tree for host (CPU) traversal; empty on devices.
  Kokkos::View<WideNode*, MemorySpace> wide;
  Kokkos::View<TriangleLanes*, MemorySpace> leaves;  // the wide tree's leaves
  // Compressed 8-wide copy for GPU traversal (gpu_wide.hpp, built by gpu_collapse.hpp): on
  // devices always, on the host only when asked; its triangles and ids in its own leaf order.
  Kokkos::View<QuantizedWideNode*, MemorySpace> qwide;
  Kokkos::View<Triangle*, MemorySpace> qwide_tris;
  Kokkos::View<int*, MemorySpace> qwide_prim;
  // The binary nodes in 32 bytes (compact_node.hpp, built by gpu_compact.hpp) for the device
  // any-hit kernels that trace them; empty unless asked for.
  Kokkos::View<CompactBvhNode*, MemorySpace> compact;
  CompactGrid grid;
  Kokkos::View<Triangle*, MemorySpace> tris;
  Kokkos::View<int*, MemorySpace> prim;
  // Where a builder made nodes, tris and prim one allocation (build_lbvh, scratch_arena.hpp: one
  // cudaMalloc instead of three), that allocation: those Views do not own their memory, so keep
  // the Bvh (not only a copy of one of them) while they are used. Empty otherwise.
  Kokkos::View<unsigned char*, MemorySpace> storage;
  Aabb bounds;
  int num_prims = 0;
  BuildQuality quality = BuildQuality::kLbvh;
};

}  // namespace rtmini::bvh
