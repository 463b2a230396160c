#pragma once
// Tonal art map (Praun et al., "Real-Time Hatching", SIGGRAPH 2001) built from
// the hand-drawn seed's Markov-chain pencil strokes (§4, after Lake et al. 2000).
// A stroke starts at a stratified point of a cell grid, walks in its level's
// direction with a slight per-stroke bend, moves one pixel sideways with the
// deviation chance and stops with the terminate chance once it is
// min_stroke_length long. It is splatted anti-aliased, with a width that tapers
// at both ends (pen pressure) and a per-stroke intensity. Level k starts as a
// copy of level k-1 (nested: a darker level contains every lighter stroke) and
// receives batches of strokes until its measured mean ink reaches its target,
// so the tone of every level is calibrated from the bitmap itself.
// Every random draw is Rng(seed, stroke id, step) and ink is combined with an
// integer atomic max, so the map is identical on any backend and thread count.
#include <cstdint>
#include <vector>

#include "npr.hpp"
#include "rtmini/kokkos_compat.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/sampling/rng.hpp"

namespace rtmini::npr {

// Ink is stored as an integer in [0, kInkScale] so that the atomic max and the
// coverage sums are exact (order-independent).
inline constexpr std::uint32_t kInkScale = 65535u;
// A level's cell grid is split into this many batches (slices of a scattered
// cell order), the unit in which strokes are added while calibrating.
inline constexpr int kBatchesPerGrid = 16;

// Plain-data copy of the hatching parameters that kernels capture by value.
struct HatchParams {
  std::uint64_t seed = 0;
  int levels = 0;
  int size = 0;  // bitmap side in pixels
  int cell_size = 0;
  int min_length = 0;
  int max_length = 0;
  float deviation = 0.f;
  float terminate = 0.f;
  float width = 1.f;  // stroke width at full pressure, pixels
  float bend = 0.f;   // largest turn per step, radians
  float dir_x[kMaxLevels] = {};
  float dir_y[kMaxLevels] = {};
  // Batches take cells in the order j -> (j * cell_stride) mod cells, a stride
  // near the golden ratio of the cell count and coprime with it, so the cells of
  // one batch are scattered over the bitmap rather than lined up in columns.
  int cell_stride = 1;

  KOKKOS_INLINE_FUNCTION int cells_per_side() const { return (size + cell_size - 1) / cell_size; }
  KOKKOS_INLINE_FUNCTION int cells() const { return cells_per_side() * cells_per_side(); }
};

HatchParams make_hatch_params(const NprConfig& config);

// Walks stroke `round` of cell `cell` at `level`, calling visit(x, y, step) at
// each sub-pixel centre (unwrapped, the caller wraps) and returning its length
// in steps. Mean length: min_length + (1 - p) / p for terminate chance p (a
// geometric tail after the minimum), capped at max_length.
template <class Visit>
KOKKOS_INLINE_FUNCTION int walk_stroke(const HatchParams& p, int level, int round, int cell,
                                       Visit&& visit) {
  const std::uint64_t id =
      (std::uint64_t(level) << 48) ^ (std::uint64_t(round) << 24) ^ std::uint64_t(cell);
  const int cx = cell % p.cells_per_side(), cy = cell / p.cells_per_side();
  const auto r0 = Rng(p.seed, id, 0u).block(0u);
  float x = (float(cx) + Rng::to_unit(r0.v[0])) * float(p.cell_size);
  float y = (float(cy) + Rng::to_unit(r0.v[1])) * float(p.cell_size);
  // A constant turn per step bends the stroke into a slight arc.
  const float turn = p.bend * (2.f * Rng::to_unit(r0.v[2]) - 1.f);
  float dx = p.dir_x[level], dy = p.dir_y[level];
  const float ct = math::cos(turn), st = math::sin(turn);
  int length = 0;
  while (length < p.max_length) {
    visit(x, y, length);
    ++length;
    const auto r = Rng(p.seed, id, static_cast<std::uint32_t>(length)).block(0u);
    if (length >= p.min_length && Rng::to_unit(r.v[2]) < p.terminate) break;
    if (Rng::to_unit(r.v[0]) < p.deviation) {
      const float side = Rng::to_unit(r.v[1]) < 0.5f ? -1.f : 1.f;
      x -= side * dy;
      y += side * dx;
    }
    x += dx;
    y += dy;
    const float ndx = ct * dx - st * dy;
    dy = st * dx + ct * dy;
    dx = ndx;
  }
  return length;
}

// Pen pressure along a stroke of `length` steps: tapers over the first and last
// steps so that ends are thin and light, as a pencil lifts.
KOKKOS_INLINE_FUNCTION float stroke_pressure(int step, int length) {
  const float taper = 3.f;
  const float a = (float(step) + 1.f) / taper, b = float(length - step) / taper;
  return math::clamp(compat::kmin(a, b), 0.35f, 1.f);
}

// Anti-aliased coverage of a pixel centre at distance d from a pen tip of radius r.
KOKKOS_INLINE_FUNCTION float disc_coverage(float d, float r) {
  return math::clamp(r + 0.5f - d, 0.f, 1.f);
}

using InkView = Kokkos::View<std::uint32_t***, Kokkos::LayoutRight,
                             Kokkos::DefaultExecutionSpace::memory_space>;

// ink(level, y, x) in [0, kInkScale]; coverage[k] = measured mean ink of level k in [0, 1].
struct ToneArtMap {
  InkView ink;
  int size = 0;
  int levels = 0;
  std::vector<double> target;    // requested mean ink per level
  std::vector<double> coverage;  // measured mean ink per level (non-decreasing)
  std::vector<int> batches;      // stroke batches added per level
};

// Target mean ink of each level, darkest last (from config.thresholds or the default spacing).
std::vector<double> level_ink_targets(const NprConfig& config);

ToneArtMap build_tone_art_map(const NprConfig& config);

// Level k's ink on the host, row-major, in [0, 1] (for tests and pictures).
std::vector<float> level_ink(const ToneArtMap& tam, int level);

// Bitmap offset of an object's hatching, so that objects hatched in the same
// direction do not continue each other's strokes.
KOKKOS_INLINE_FUNCTION void object_offset(std::uint64_t seed, int size, int object, int& ox,
                                          int& oy) {
  const std::uint64_t h = hash_term(seed, std::uint64_t(std::uint32_t(object)));
  ox = static_cast<int>((h & 0xffffffffu) % std::uint64_t(size));
  oy = static_cast<int>((h >> 32) % std::uint64_t(size));
}

}  // namespace rtmini::npr
