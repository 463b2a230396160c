#pragma once
// The order a loop with a progress line visits its items in. The ETA of such a loop divides the
// work left by the rate measured so far; when the loop runs through its items in storage order,
// that rate is the rate of the first region only (the sky rows of a frame, the cheap end of a
// mesh) and the ETA is off by the ratio of the regions' costs (bake render: -30 to -44 % on the
// Cornell box, results/progress/). Visited in a spread order, every stretch of consecutive
// positions (what one dispatch of TimedChunks runs) is a fair sample of the whole range, so the
// rate measured so far holds for the rest: the ETA is then off by the load changes only.
#include <cstdint>
#include <numeric>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

// Maps positions [0, total) to items [0, total): whole blocks of `block` consecutive items (which
// keeps neighbours together: rays through neighbouring pixels or points share BVH nodes in the
// cache), the blocks in golden-ratio stride order b -> b * stride mod blocks, stride coprime
// with the block count (a permutation; by the three-distance theorem any run of consecutive
// positions lands nearly evenly over the range). The total % block items after the last whole
// block stay at the end, in order. The default order is the identity.
struct SpreadOrder {
  std::int64_t block = 1, blocks = 0, stride = 1;

  SpreadOrder() = default;
  SpreadOrder(std::int64_t total, std::int64_t block_items)
      : block(block_items > 0 ? block_items : 1), blocks(total > 0 ? total / block : 0) {
    if (blocks < 3) return;  // one or two blocks: nothing to spread
    stride = static_cast<std::int64_t>(0.6180339887498949 * static_cast<double>(blocks) + 0.5);
    while (std::gcd(stride, blocks) != 1) ++stride;
  }

  // The item visited at position `pos`.
  KOKKOS_INLINE_FUNCTION std::int64_t item(std::int64_t pos) const {
    const std::int64_t b = pos / block;
    if (b >= blocks) return pos;
    return (b * stride % blocks) * block + pos % block;
  }
};

}  // namespace rtmini
