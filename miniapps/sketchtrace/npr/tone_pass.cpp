#include <algorithm>
#include <cmath>

#include "hatching.hpp"
#include "passes.hpp"
#include "rtmini/io/srgb.hpp"

namespace rtmini::npr {
namespace detail {

// A colour pencil's stroke is its hue at this fraction of full (displayed)
// brightness: dark enough that mid tones need partial coverage, so the strokes
// and the paper between them stay visible instead of a flat fill.
inline constexpr float kPigmentShade = 0.6f;

struct ToneParams {
  int levels = 0;
  int size = 0;
  float coverage[kMaxLevels] = {};  // measured mean ink per level
  float pencil = 0.f;               // displayed tone of a graphite stroke
  float inv_white = 1.f;
  bool color = false;
  bool object_directions = false;
  std::uint64_t seed = 0;
};

// Bilinear, toroidal lookup of level k's ink at bitmap position (u, v).
KOKKOS_INLINE_FUNCTION float sample_ink(const InkView& ink, int level, int size, float u, float v) {
  const float fu = math::floor(u), fv = math::floor(v);
  const float tu = u - fu, tv = v - fv;
  const int x0 = ((static_cast<int>(fu) % size) + size) % size, x1 = (x0 + 1) % size;
  const int y0 = ((static_cast<int>(fv) % size) + size) % size, y1 = (y0 + 1) % size;
  const float a = float(ink(level, y0, x0)), b = float(ink(level, y0, x1));
  const float c = float(ink(level, y1, x0)), d = float(ink(level, y1, x1));
  return ((1.f - tv) * ((1.f - tu) * a + tu * b) + tv * ((1.f - tu) * c + tu * d)) /
         float(kInkScale);
}

// Ink at a pixel whose required mean ink is `want`: the two levels whose
// measured coverages bracket it are blended (Praun et al. 2001), so the local
// mean ink equals `want`; past the darkest level the gaps fill in.
template <class Lookup>
KOKKOS_INLINE_FUNCTION float tam_ink(const ToneParams& p, float want, Lookup&& lookup) {
  // Below half an 8-bit code of tone the pixel is the brightest: pure paper (seed's rule).
  if (want <= 0.5f / 255.f) return 0.f;
  int k = 0;
  while (k < p.levels && p.coverage[k] < want) ++k;
  if (k == p.levels) {
    const float last = lookup(p.levels - 1), top = p.coverage[p.levels - 1];
    const float t = top < 1.f ? math::clamp((want - top) / (1.f - top), 0.f, 1.f) : 1.f;
    return last + t * (1.f - last);
  }
  const float lo = k > 0 ? p.coverage[k - 1] : 0.f, hi = p.coverage[k];
  const float t = hi > lo ? (want - lo) / (hi - lo) : 1.f;
  const float a = k > 0 ? lookup(k - 1) : 0.f;
  return a + t * (lookup(k) - a);
}

// Hatching angle of an object: the golden angle sequence spreads ids evenly over [0, pi).
KOKKOS_INLINE_FUNCTION float object_angle(int object) {
  if (object <= 0) return 0.f;
  const float golden = 2.39996323f;
  const float a = float(object) * golden;
  return a - math::floor(a / float(math::kPi)) * float(math::kPi);
}

void run_tone(const DeviceImage& rgb, const DeviceImage& object, const NprConfig& config,
              float white) {
  if (config.style == NprStyle::kNone) return;
  const ToneArtMap tam = build_tone_art_map(config);
  ToneParams tp;
  tp.levels = tam.levels;
  tp.size = tam.size;
  for (int k = 0; k < tp.levels; ++k) tp.coverage[k] = static_cast<float>(tam.coverage[k]);
  tp.pencil = srgb_encode(config.pencil_tone);
  tp.inv_white = 1.f / white;
  tp.color = config.style == NprStyle::kColorPencil;
  tp.object_directions = config.object_directions && object.extent(0) > 0;
  tp.seed = mix64(config.seed ^ 0x726567696f6eULL);
  const InkView ink = tam.ink;
  const int w = static_cast<int>(rgb.extent(1));
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::tone",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, static_cast<int>(rgb.extent(0)) * w),
      KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        const float r = compat::kmax(rgb(y, x, 0), 0.f), g = compat::kmax(rgb(y, x, 1), 0.f),
                    b = compat::kmax(rgb(y, x, 2), 0.f);
        const float tone = render_tone(r, g, b, tp.inv_white);
        // Pigment (displayed colour of a stroke): graphite grey, or the pixel's
        // hue at full brightness, shaded, for colour pencil.
        float pig[3] = {tp.pencil, tp.pencil, tp.pencil};
        if (tp.color) {
          const float m = compat::kmax(r, compat::kmax(g, b));
          const float lin[3] = {r, g, b};
          if (m > 0.f)
            for (int c = 0; c < 3; ++c) pig[c] = kPigmentShade * srgb_encode(lin[c] / m);
        }
        const float pig_lum = 0.2126f * pig[0] + 0.7152f * pig[1] + 0.0722f * pig[2];
        // Mean displayed tone 1 - ink * (1 - pigment) = tone: the ink needed. A
        // light pigment that cannot reach the tone with the darkest level's ink is
        // darkened instead (same hue), so strokes stay visible.
        float want = (1.f - tone) / compat::kmax(1e-4f, 1.f - pig_lum);
        const float top = tp.coverage[tp.levels - 1];
        if (want > top && tp.color && top > 0.f) {
          const float lum = compat::kmax(0.f, 1.f - (1.f - tone) / top);
          const float s = pig_lum > 0.f ? lum / pig_lum : 0.f;
          for (int c = 0; c < 3; ++c) pig[c] = math::clamp(pig[c] * s, 0.f, 1.f);
          want = top;
        }
        // Turned bitmap coordinates: per-object hatching direction.
        const int id = tp.object_directions ? static_cast<int>(object(y, x, 0)) : 0;
        const float a = object_angle(id);
        const float ca = math::cos(a), sa = math::sin(a);
        const float px = float(x) + 0.5f, py = float(y) + 0.5f;
        // One offset per object and no per-region offsets: a region seam would
        // cut strokes along a straight line.
        int ox, oy;
        object_offset(tp.seed, tp.size, id, ox, oy);
        const float u = ca * px - sa * py + float(ox), v = sa * px + ca * py + float(oy);
        const float k = tam_ink(tp, math::clamp(want, 0.f, 1.f),
                                [&](int level) { return sample_ink(ink, level, tp.size, u, v); });
        for (int c = 0; c < 3; ++c) rgb(y, x, c) = srgb_decode(1.f - k * (1.f - pig[c]));
      });
}

}  // namespace detail

float exposure_white(const Image& color, const NprConfig& config) {
  const std::size_t n = static_cast<std::size_t>(color.width) * color.height;
  if (n == 0) return 1.f;
  std::vector<float> lum(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int x = static_cast<int>(i % color.width), y = static_cast<int>(i / color.width);
    const float r = color.at(x, y, 0);
    const float g = color.channels >= 3 ? color.at(x, y, 1) : r;
    const float b = color.channels >= 3 ? color.at(x, y, 2) : r;
    lum[i] = std::max(0.f, 0.2126f * r + 0.7152f * g + 0.0722f * b);
  }
  const std::size_t q = std::min(
      n - 1, static_cast<std::size_t>(double(config.white_percentile) * double(n - 1) + 0.5));
  std::nth_element(lum.begin(), lum.begin() + static_cast<std::ptrdiff_t>(q), lum.end());
  const float white = lum[q] / config.exposure;
  return white > 0.f && std::isfinite(white) ? white : 1.f;
}

Image tone_pass(const Image& color, const NprConfig& config, const Image* object) {
  validate(config);
  const DeviceImage rgb = upload_image(color, 3, "rtmini::sketchtrace::npr::rgb");
  const DeviceImage obj = object ? upload_image(*object, 1, "rtmini::sketchtrace::npr::object")
                                 : DeviceImage("rtmini::sketchtrace::npr::no_object", 0, 0, 1);
  detail::run_tone(rgb, obj, config, exposure_white(color, config));
  return download_image(rgb);
}

}  // namespace rtmini::npr
