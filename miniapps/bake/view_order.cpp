#include "view_order.hpp"

#include <Kokkos_Core.hpp>
#include <algorithm>
#include <cmath>
#include <utility>

#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {

ViewOrder coherent_view_order(int n, int stored) {
  const int bands = std::max(1, static_cast<int>(std::lround(std::sqrt(n / 2.0))));
  std::vector<std::pair<double, int>> key(static_cast<std::size_t>(stored));
  for (int i = 0; i < stored; ++i) {
    const Vec3 p = fibonacci_point(i, n);
    const int band = std::min(bands - 1, static_cast<int>((1.0 - p.z) * 0.5 * bands));
    const double phi = std::atan2(double(p.y), double(p.x));
    key[i] = {band * 10.0 + (band % 2 == 0 ? phi : -phi) / 4.0, i};
  }
  std::sort(key.begin(), key.end());
  ViewOrder o;
  o.order.resize(key.size());
  o.slot.resize(key.size());
  for (int s = 0; s < stored; ++s) {
    o.order[s] = key[s].second;
    o.slot[key[s].second] = s;
  }
  return o;
}

namespace {
// Every vertex with more than one colour: entry `to_of[i]` of its block takes entry i. On the
// host threads, a piece of vertices at a time with one scratch block each.
void permute_blocks(const std::vector<int>& to_of, const std::vector<std::int64_t>& offset,
                    std::vector<Vec3f>& colors) {
  constexpr std::int64_t kPiece = 1024;
  const std::int64_t nv = static_cast<std::int64_t>(offset.size()) - 1;
  const std::int64_t n = static_cast<std::int64_t>(to_of.size());
  using Host = Kokkos::DefaultHostExecutionSpace;
  Kokkos::parallel_for(
      "rtmini::bake::permute_colour_blocks",
      Kokkos::RangePolicy<Host, Kokkos::IndexType<std::int64_t>>(0, (nv + kPiece - 1) / kPiece),
      [&](std::int64_t piece) {
        std::vector<Vec3f> block(to_of.size());
        for (std::int64_t v = piece * kPiece; v < std::min(nv, (piece + 1) * kPiece); ++v) {
          if (offset[v + 1] - offset[v] != n) continue;  // one colour: nothing moves
          Vec3f* c = colors.data() + offset[v];
          for (std::int64_t i = 0; i < n; ++i) block[to_of[i]] = c[i];
          std::copy(block.begin(), block.end(), c);
        }
      });
  Host().fence();
}
}  // namespace

void to_viewpoint_order(const ViewOrder& o, const std::vector<std::int64_t>& offset,
                        std::vector<Vec3f>& colors) {
  permute_blocks(o.order, offset, colors);  // slot s holds viewpoint order[s]
}

void to_storage_order(const ViewOrder& o, const std::vector<std::int64_t>& offset,
                      std::vector<Vec3f>& colors) {
  permute_blocks(o.slot, offset, colors);  // viewpoint j goes to slot[j]
}

}  // namespace rtmini::bake
