#include "hatching.hpp"
#include "passes.hpp"
#include "rtmini/io/srgb.hpp"

namespace rtmini::npr {
namespace detail {

struct ToneParams {
  int levels = 0;
  float threshold[kMaxLevels] = {};
  float pencil = 0.f;
  bool color = false;
};

// Number of thresholds above `tone`, minus one: -1 = white, levels-1 = darkest bitmap.
KOKKOS_INLINE_FUNCTION int tone_level(const ToneParams& p, float tone) {
  int k = 0;
  while (k < p.levels && tone < p.threshold[k]) ++k;
  return k - 1;
}

void run_tone(const DeviceImage& rgb, const NprConfig& config) {
  if (config.style == NprStyle::kNone) return;
  const HatchBitmaps bitmaps = build_hatch_bitmaps(make_hatch_params(config));
  ToneParams tp;
  tp.levels = config.levels;
  const std::vector<float> thresholds = effective_thresholds(config);
  for (int k = 0; k < tp.levels; ++k) tp.threshold[k] = thresholds[k];
  tp.pencil = config.pencil_tone;
  tp.color = config.style == NprStyle::kColorPencil;
  const auto mask = bitmaps.mask;
  const int size = bitmaps.size;
  const std::uint64_t region_seed = mix64(config.seed ^ 0x726567696f6eULL);
  const int w = static_cast<int>(rgb.extent(1));
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::tone",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, static_cast<int>(rgb.extent(0)) * w),
      KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        const float r = math::clamp(rgb(y, x, 0), 0.f, 1.f);
        const float g = math::clamp(rgb(y, x, 1), 0.f, 1.f);
        const float b = math::clamp(rgb(y, x, 2), 0.f, 1.f);
        // Sketch: tone is perceptual lightness (sRGB-encoded luminance). Colour pencil:
        // tone is the lightest channel, i.e. how much pigment the colour needs.
        const float lin = tp.color ? compat::kmin(r, compat::kmin(g, b))
                                   : 0.2126f * r + 0.7152f * g + 0.0722f * b;
        const int level = tone_level(tp, srgb_encode(lin));
        int ox, oy;
        region_offset(region_seed, size, x / size, y / size, ox, oy);
        const bool dark = hatch_dark(mask((y + oy) % size, (x + ox) % size), level);
        if (tp.color) {
          rgb(y, x, 0) = dark ? r : 1.f;
          rgb(y, x, 1) = dark ? g : 1.f;
          rgb(y, x, 2) = dark ? b : 1.f;
        } else {
          const float v = dark ? tp.pencil : 1.f;
          rgb(y, x, 0) = v;
          rgb(y, x, 1) = v;
          rgb(y, x, 2) = v;
        }
      });
}

}  // namespace detail

Image tone_pass(const Image& color, const NprConfig& config) {
  validate(config);
  const DeviceImage rgb = upload_image(color, 3, "rtmini::sketchtrace::npr::rgb");
  detail::run_tone(rgb, config);
  return download_image(rgb);
}

}  // namespace rtmini::npr
