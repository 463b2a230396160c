#pragma once
// Compressed 8-wide BVH node for GPU traversal (after Ylitie, Karras, Laine, "Efficient Incoherent
// Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017): eight child boxes quantised to
// 8 bits per plane against a per-node grid, so one node is 96 bytes (three 32-byte sectors)
// instead of the 8 x 24 bytes of float boxes. Inner children are stored consecutively from
// child_base in slot order; the triangles of the leaf children consecutively from tri_base, a
// leaf's own range given by its offset and count. Slots are assigned by octant at build time
// (gpu_collapse.hpp), so a ray visiting slots in the order i ^ octant(ray) meets near children
// first without sorting.
//
// Quantisation is conservative by construction: a decoded plane is origin + q * 2^e in Real
// arithmetic (the product is exact, so a fused multiply-add rounds the same), and the builder
// checks each decoded plane against the exact child box, moving q outward until it encloses it.
// Traversal evaluates planes in a cheaper form and widens them by a bound on its own rounding
// (traverse_gpu.hpp), so the tested box still encloses the decoded one.
#include <cstdint>

#include "rtmini/geometry/aabb.hpp"

namespace rtmini::bvh {

inline constexpr int kQuantizedWidth = 8;
inline constexpr int kQuantizedWords = 24;  // 96 bytes

struct alignas(32) QuantizedWideNode {
  float origin[3];                           // the grid's corner: at or below every child box
  std::uint8_t exponent[3];                  // grid step 2^(exponent - 127) per axis
  std::uint8_t inner_mask;                   // bit k: slot k is an inner node
  std::uint32_t child_base;                  // node index of the first inner child
  std::uint32_t tri_base;                    // first triangle of the leaf children
  std::uint8_t tri_offset[kQuantizedWidth];  // leaf slot: its first triangle - tri_base
  std::uint8_t tri_count[kQuantizedWidth];   // leaf slot: its triangles; 0 = inner or unused
  // Planes lo x, lo y, lo z, hi x, hi y, hi z, one byte per slot each.
  std::uint8_t q[6][kQuantizedWidth];
  std::uint32_t unused[2];
};
static_assert(sizeof(QuantizedWideNode) == kQuantizedWords * 4, "three 32-byte sectors");

// Word indices of the fields above, for traversal code that loads a node as 24 words.
namespace qword {
inline constexpr int kExponents = 3;  // exponent bytes 0-2, inner_mask byte 3
inline constexpr int kChildBase = 4;
inline constexpr int kTriBase = 5;
inline constexpr int kTriOffset = 6;  // two words
inline constexpr int kTriCount = 8;   // two words
inline constexpr int kPlanes = 10;    // two words per plane
}  // namespace qword

// 2^(biased - 127) as a float, built from its bits (exact, no libm).
KOKKOS_INLINE_FUNCTION float grid_step(std::uint32_t biased) {
  return compat::bit_cast<float>(biased << 23);
}

// The decoded plane, as the builder checks it.
KOKKOS_INLINE_FUNCTION Real decode_plane(Real origin, Real step, std::uint32_t q) {
  return origin + Real(q) * step;
}

}  // namespace rtmini::bvh
