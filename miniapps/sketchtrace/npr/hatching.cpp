#include "hatching.hpp"

namespace rtmini::npr {

HatchParams make_hatch_params(const NprConfig& config) {
  HatchParams p;
  // Decorrelated from the paper noise, which uses the same run seed.
  p.seed = mix64(config.seed ^ 0x6861746368ULL);
  p.levels = config.levels;
  p.size = config.bitmap_size;
  p.cell_size = config.cell_size;
  p.strokes_per_cell = config.strokes_per_cell;
  p.min_length = config.min_stroke_length;
  p.max_length = config.max_stroke_length;
  p.deviation = config.deviation_chance;
  p.terminate = config.terminate_chance;
  const std::vector<float> angles = effective_angles(config);
  for (int k = 0; k < p.levels; ++k) {
    const double a = angles[k] * math::kPi / 180.0;
    // Image rows grow downwards, so a counter-clockwise angle has a negative y step.
    p.dir_x[k] = static_cast<float>(std::cos(a));
    p.dir_y[k] = static_cast<float>(-std::sin(a));
  }
  return p;
}

HatchBitmaps build_hatch_bitmaps(const HatchParams& params) {
  HatchBitmaps out;
  out.size = params.size;
  out.levels = params.levels;
  out.mask = decltype(out.mask)("rtmini::sketchtrace::npr::hatch_mask", params.size, params.size);
  const auto mask = out.mask;
  const HatchParams p = params;
  const std::int64_t per_level = p.strokes_per_level();
  // Strokes overlap, so coverage bits are or-ed atomically (order-independent).
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::hatch_strokes",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace, Kokkos::IndexType<std::int64_t>>(
          0, per_level * p.levels),
      KOKKOS_LAMBDA(std::int64_t s) {
        const int level = static_cast<int>(s / per_level);
        const std::uint32_t bit = 1u << level;
        walk_stroke(p, level, s % per_level,
                    [&](int x, int y, bool) { Kokkos::atomic_fetch_or(&mask(y, x), bit); });
      });
  Kokkos::fence();
  return out;
}

std::vector<std::uint8_t> level_bitmap(const HatchBitmaps& bitmaps, int level) {
  const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bitmaps.mask);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(bitmaps.size) * bitmaps.size);
  for (int y = 0; y < bitmaps.size; ++y)
    for (int x = 0; x < bitmaps.size; ++x)
      out[static_cast<std::size_t>(y) * bitmaps.size + x] = hatch_dark(host(y, x), level) ? 1 : 0;
  return out;
}

}  // namespace rtmini::npr
