#pragma once
// A binary BVH node in 32 bytes for GPU any-hit traversal (issue 21): BvhNode's two child boxes
// with every plane as a 16-bit step count on one grid for the whole tree, instead of a float, so
// a node visit loads two 16-byte words instead of four (the binary kernel is bound by L1/TEX
// traffic, results/gpu/README.md). The child references are BvhNode's, so the compact copy
// (built by gpu_compact.hpp) shares the tree's triangles and node numbering.
//
// A decoded plane is origin + q * step with step a power of two: the product of a 16-bit integer
// and a power of two is exact, so the one rounding of the sum is the same with or without a fused
// multiply-add, on the host and on the device. The builder quantises lower planes down and upper
// planes up and checks each decoded plane against the exact box, so every decoded box encloses
// its child and traversal stays conservative with the ordinary slab test.
#include <cstdint>

#include "rtmini/geometry/aabb.hpp"

namespace rtmini::bvh {

inline constexpr std::uint32_t kCompactGridMax = 65535;  // the largest step count of a plane

struct alignas(32) CompactBvhNode {
  // Step counts of lo x, lo y, lo z, hi x, hi y, hi z, each for child 0 then child 1 (the order
  // of BvhNode's fields).
  std::uint16_t q[12];
  std::uint32_t child[2];  // as BvhNode::child
};
static_assert(sizeof(CompactBvhNode) == 32, "two 16-byte words");

// The tree's grid: plane q of axis k lies at origin[k] + q * step[k] (step a power of two).
struct CompactGrid {
  Real origin[3] = {0, 0, 0};
  Real step[3] = {1, 1, 1};
};

// A step count below 2^16 as a float made from its bits (2^23 + q, less 2^23: exact), rather
// than by an integer conversion, which GPUs issue at a fraction of the FMA rate.
KOKKOS_FORCEINLINE_FUNCTION Real grid_count(std::uint32_t q) {
  return Real(compat::bit_cast<float>(0x4b000000u | q) - 8388608.0f);
}

KOKKOS_FORCEINLINE_FUNCTION Real grid_plane(const CompactGrid& g, int axis, std::uint32_t q) {
  return g.origin[axis] + grid_count(q) * g.step[axis];
}

}  // namespace rtmini::bvh
