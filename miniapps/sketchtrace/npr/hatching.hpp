#pragma once
// Pencil-stroke bitmaps (hand-drawn seed §4, after Lake et al., NPAR 2000):
// strokes are Markov chains that start at stratified points in a grid of
// cells, walk in their level's direction, deviate sideways by one pixel with
// the deviation chance and stop with the terminate chance once they are
// min_stroke_length long. Level k's bitmap is every stroke of levels <= k, so
// a darker level always contains all lighter strokes. Every random draw is
// Rng(seed, stroke id, step): the bitmaps are identical on any backend.
#include <cstdint>
#include <vector>

#include "npr.hpp"
#include "rtmini/kokkos_compat.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/sampling/rng.hpp"

namespace rtmini::npr {

// Plain-data copy of the hatching parameters that kernels capture by value.
struct HatchParams {
  std::uint64_t seed = 0;
  int levels = 0;
  int size = 0;  // bitmap side in pixels
  int cell_size = 0;
  int strokes_per_cell = 0;
  int min_length = 0;
  int max_length = 0;
  float deviation = 0.f;
  float terminate = 0.f;
  float dir_x[kMaxLevels] = {};
  float dir_y[kMaxLevels] = {};

  KOKKOS_INLINE_FUNCTION int cells_per_side() const { return (size + cell_size - 1) / cell_size; }
  KOKKOS_INLINE_FUNCTION std::int64_t strokes_per_level() const {
    return std::int64_t(cells_per_side()) * cells_per_side() * strokes_per_cell;
  }
};

HatchParams make_hatch_params(const NprConfig& config);

// Walks stroke `index` (0 .. strokes_per_level-1) of `level`, calling
// visit(x, y, deviated) for each pixel it covers (wrapped onto the torus) and
// returning its length in steps. Mean length: min_length + (1 - p) / p for
// terminate chance p (a geometric tail after the minimum), capped at max_length.
template <class Visit>
KOKKOS_INLINE_FUNCTION int walk_stroke(const HatchParams& p, int level, std::int64_t index,
                                       Visit&& visit) {
  const std::uint64_t id = std::uint64_t(level) * std::uint64_t(p.strokes_per_level()) + index;
  const int cell = static_cast<int>(index / p.strokes_per_cell);
  const int j = static_cast<int>(index % p.strokes_per_cell);
  const int cx = cell % p.cells_per_side(), cy = cell / p.cells_per_side();
  // Start: one stratum (band across the cell) per stroke of this cell.
  float u, v;
  Rng(p.seed, id, 0u).uniform2(2u, u, v);
  float x = (float(cx) + u) * float(p.cell_size);
  float y = (float(cy) + (float(j) + v) / float(p.strokes_per_cell)) * float(p.cell_size);
  const float dx = p.dir_x[level], dy = p.dir_y[level];
  bool deviated = false;
  int length = 0;
  while (length < p.max_length) {
    int px = static_cast<int>(math::floor(x + 0.5f)) % p.size;
    int py = static_cast<int>(math::floor(y + 0.5f)) % p.size;
    px += px < 0 ? p.size : 0;
    py += py < 0 ? p.size : 0;
    visit(px, py, deviated);
    ++length;
    const auto r = Rng(p.seed, id, static_cast<std::uint32_t>(length)).block(0u);
    if (length >= p.min_length && Rng::to_unit(r.v[2]) < p.terminate) break;
    deviated = Rng::to_unit(r.v[0]) < p.deviation;
    if (deviated) {
      const float side = Rng::to_unit(r.v[1]) < 0.5f ? -1.f : 1.f;
      x -= side * dy;
      y += side * dx;
    }
    x += dx;
    y += dy;
  }
  return length;
}

// Stroke coverage as bits: bit k of mask(y, x) is set when a level-k stroke covers it.
struct HatchBitmaps {
  Kokkos::View<std::uint32_t**, Kokkos::LayoutRight, Kokkos::DefaultExecutionSpace::memory_space>
      mask;
  int size = 0;
  int levels = 0;
};

// Level k's bitmap: dark where any stroke of levels 0..k lies (level < 0 = white).
KOKKOS_INLINE_FUNCTION bool hatch_dark(std::uint32_t mask, int level) {
  return level >= 0 && (mask & ((2u << level) - 1u)) != 0u;
}

// Bitmap offset of the size x size region (rx, ry) of a large image, so tiles
// do not repeat visibly.
KOKKOS_INLINE_FUNCTION void region_offset(std::uint64_t seed, int size, int rx, int ry, int& ox,
                                          int& oy) {
  const std::uint64_t h =
      hash_term(seed, (std::uint64_t(std::uint32_t(rx)) << 32) | std::uint32_t(ry));
  ox = static_cast<int>((h & 0xffffffffu) % std::uint64_t(size));
  oy = static_cast<int>((h >> 32) % std::uint64_t(size));
}

HatchBitmaps build_hatch_bitmaps(const HatchParams& params);

// Level k's bitmap on the host, row-major, 1 = stroke (for tests and pictures).
std::vector<std::uint8_t> level_bitmap(const HatchBitmaps& bitmaps, int level);

}  // namespace rtmini::npr
