#include "hatching.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rtmini/io/srgb.hpp"

namespace rtmini::npr {

HatchParams make_hatch_params(const NprConfig& config) {
  HatchParams p;
  // Decorrelated from the paper noise, which uses the same run seed.
  p.seed = mix64(config.seed ^ 0x6861746368ULL);
  p.levels = config.levels;
  p.size = config.bitmap_size;
  p.cell_size = config.cell_size;
  p.min_length = config.min_stroke_length;
  p.max_length = config.max_stroke_length;
  p.deviation = config.deviation_chance;
  p.terminate = config.terminate_chance;
  p.width = config.stroke_width;
  p.bend = static_cast<float>(config.stroke_bend * math::kPi / 180.0);
  const int cells = p.cells();
  p.cell_stride = std::max(1, static_cast<int>(0.618034 * cells));
  while (std::gcd(p.cell_stride, cells) != 1) ++p.cell_stride;
  const std::vector<float> angles = effective_angles(config);
  for (int k = 0; k < p.levels; ++k) {
    const double a = angles[k] * math::kPi / 180.0;
    // Image rows grow downwards, so a counter-clockwise angle has a negative y step.
    p.dir_x[k] = static_cast<float>(std::cos(a));
    p.dir_y[k] = static_cast<float>(-std::sin(a));
  }
  return p;
}

std::vector<double> level_ink_targets(const NprConfig& config) {
  std::vector<double> target(static_cast<std::size_t>(config.levels));
  const double pencil = srgb_encode(static_cast<double>(config.pencil_tone));
  for (int k = 0; k < config.levels; ++k) {
    if (config.thresholds.empty()) {
      target[k] = 0.95 * double(k + 1) / double(config.levels);
    } else {
      // Displayed tone 1 - ink * (1 - pencil) = threshold.
      const double ink = (1.0 - config.thresholds[k]) / std::max(1e-6, 1.0 - pencil);
      target[k] = std::min(1.0, std::max(0.0, ink));
    }
  }
  return target;
}

namespace {

// Splats batches first .. first+count-1 of `level` into ink(level). Batch
// `round` takes the (round % kBatchesPerGrid)-th slice of the scattered cell order.
void add_stroke_batches(const HatchParams& p, const InkView& ink, int level, int first, int count) {
  const int per_batch = (p.cells() + kBatchesPerGrid - 1) / kBatchesPerGrid;
  // Strokes overlap, so ink is combined with an atomic max (order-independent).
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::hatch_strokes",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, per_batch * count),
      KOKKOS_LAMBDA(int i) {
        const int round = first + i / per_batch;
        const int j = (round % kBatchesPerGrid) * per_batch + i % per_batch;
        if (j >= p.cells()) return;
        const int cell = static_cast<int>(std::int64_t(j) * p.cell_stride % p.cells());
        const int length = walk_stroke(p, level, round, cell, [](float, float, int) {});
        const std::uint64_t id = (std::uint64_t(level) << 48) ^ (std::uint64_t(round) << 24) ^
                                 std::uint64_t(cell) ^ 0x5eedULL;
        const float intensity = 0.85f + 0.15f * Rng(p.seed, id, 0u).uniform(0u);
        walk_stroke(p, level, round, cell, [&](float x, float y, int step) {
          const float r = 0.5f * p.width * stroke_pressure(step, length);
          const int x0 = static_cast<int>(math::floor(x - r - 0.5f));
          const int y0 = static_cast<int>(math::floor(y - r - 0.5f));
          const int x1 = static_cast<int>(math::floor(x + r + 0.5f));
          const int y1 = static_cast<int>(math::floor(y + r + 0.5f));
          for (int py = y0; py <= y1; ++py)
            for (int px = x0; px <= x1; ++px) {
              const float ddx = float(px) + 0.5f - x, ddy = float(py) + 0.5f - y;
              const float c = disc_coverage(math::sqrt(ddx * ddx + ddy * ddy), r) * intensity;
              if (c <= 0.f) continue;
              const int wx = ((px % p.size) + p.size) % p.size;
              const int wy = ((py % p.size) + p.size) % p.size;
              Kokkos::atomic_fetch_max(&ink(level, wy, wx),
                                       static_cast<std::uint32_t>(c * float(kInkScale) + 0.5f));
            }
        });
      });
}

double mean_ink(const InkView& ink, int level, int size) {
  std::uint64_t sum = 0;
  Kokkos::parallel_reduce(
      "rtmini::sketchtrace::npr::hatch_coverage",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, size * size),
      KOKKOS_LAMBDA(int i, std::uint64_t& acc) { acc += ink(level, i / size, i % size); }, sum);
  return double(sum) / (double(kInkScale) * double(size) * double(size));
}

}  // namespace

ToneArtMap build_tone_art_map(const NprConfig& config) {
  const HatchParams p = make_hatch_params(config);
  ToneArtMap tam;
  tam.size = p.size;
  tam.levels = p.levels;
  tam.target = level_ink_targets(config);
  tam.ink = InkView("rtmini::sketchtrace::npr::tam", p.levels, p.size, p.size);
  // Enough rounds to cover any target: each round is one stroke per cell.
  const int max_rounds = 1024 * kBatchesPerGrid;
  int round = 0;
  // Fraction of the uncovered area one batch inks; the first guess is high so
  // that the first step adds a single batch.
  double gain = 0.5;
  for (int k = 0; k < p.levels; ++k) {
    if (k > 0) {
      const auto dst = Kokkos::subview(tam.ink, k, Kokkos::ALL, Kokkos::ALL);
      const auto src = Kokkos::subview(tam.ink, k - 1, Kokkos::ALL, Kokkos::ALL);
      Kokkos::deep_copy(dst, src);
    }
    double covered = mean_ink(tam.ink, k, p.size);
    int added = 0;
    // Each step adds most of the batches that a model of independent layers
    // predicts (1 - c grows by the factor measured in the previous step), then
    // measures again: few launches, and the last steps add single batches.
    while (covered < tam.target[k] && round < max_rounds) {
      const double need = std::log((1.0 - tam.target[k]) / (1.0 - covered)) /
                          std::log(1.0 - std::min(0.9, std::max(1e-3, gain)));
      const int n = std::max(1, std::min(max_rounds - round, static_cast<int>(0.7 * need)));
      add_stroke_batches(p, tam.ink, k, round, n);
      round += n;
      added += n;
      const double now = mean_ink(tam.ink, k, p.size);
      if (now > covered) gain = 1.0 - std::pow((1.0 - now) / (1.0 - covered), 1.0 / n);
      covered = now;
    }
    tam.coverage.push_back(covered);
    tam.batches.push_back(added);
  }
  Kokkos::fence();
  return tam;
}

std::vector<float> level_ink(const ToneArtMap& tam, int level) {
  const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tam.ink);
  std::vector<float> out(static_cast<std::size_t>(tam.size) * tam.size);
  for (int y = 0; y < tam.size; ++y)
    for (int x = 0; x < tam.size; ++x)
      out[static_cast<std::size_t>(y) * tam.size + x] = float(host(level, y, x)) / float(kInkScale);
  return out;
}

}  // namespace rtmini::npr
