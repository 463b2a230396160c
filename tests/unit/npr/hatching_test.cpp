// Stroke bitmaps: nesting, tone mapping, stroke statistics (hand-drawn seed §4).
#include "hatching.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "npr.hpp"
#include "npr_test_util.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::npr {
namespace {

NprConfig small_config() {
  NprConfig c;
  c.bitmap_size = 256;
  c.seed = 7;
  return c;
}

TEST(NprHatching, DarkerLevelsContainEveryLighterStroke) {
  const NprConfig c = small_config();
  const HatchBitmaps b = build_hatch_bitmaps(make_hatch_params(c));
  ASSERT_EQ(b.levels, c.levels);
  std::size_t previous = 0;
  std::vector<std::uint8_t> lighter = level_bitmap(b, 0);
  for (int k = 1; k < b.levels; ++k) {
    const std::vector<std::uint8_t> darker = level_bitmap(b, k);
    std::size_t violations = 0, dark = 0;
    for (std::size_t i = 0; i < darker.size(); ++i) {
      violations += lighter[i] && !darker[i];
      dark += darker[i];
    }
    EXPECT_EQ(violations, 0u) << "level " << k << " lost strokes of level " << k - 1;
    std::size_t lighter_dark = 0;
    for (auto v : lighter) lighter_dark += v;
    EXPECT_GT(dark, lighter_dark) << "level " << k << " adds no strokes";
    EXPECT_GT(dark, previous);
    previous = dark;
    lighter = darker;
  }
}

TEST(NprHatching, CoverageGrowsLikeIndependentLayers) {
  // Each level adds the same stroke density, so the white fraction of level k is
  // about (1 - c)^(k+1) for the single-level coverage c (strokes overlapping at random).
  const NprConfig c = small_config();
  const HatchBitmaps b = build_hatch_bitmaps(make_hatch_params(c));
  auto coverage = [&](int k) {
    const auto bits = level_bitmap(b, k);
    double s = 0;
    for (auto v : bits) s += v;
    return s / bits.size();
  };
  const double c0 = coverage(0);
  EXPECT_GT(c0, 0.05);
  EXPECT_LT(c0, 0.5);
  // Levels 0 and 1 share a direction, so they overlap more than independent layers;
  // compare with generous slack rather than the exact product.
  const double white4 = 1.0 - coverage(4);
  EXPECT_NEAR(white4, std::pow(1.0 - c0, 5), 0.12);
}

TEST(NprHatching, MeanStrokeLengthMatchesMarkovChain) {
  NprConfig c = small_config();
  c.min_stroke_length = 6;
  c.terminate_chance = 0.1f;
  c.cell_size = 8;  // ~20k strokes: the variance check below is then a 5-sigma bound
  c.strokes_per_cell = 4;
  c.deviation_chance = 0.2f;
  const HatchParams p = make_hatch_params(c);
  const std::int64_t n = p.strokes_per_level();
  double sum = 0, sum2 = 0, steps = 0, deviations = 0;
  int shortest = 1 << 30;
  for (int level = 0; level < p.levels; ++level)
    for (std::int64_t s = 0; s < n; ++s) {
      int devs = 0;
      const int len = walk_stroke(p, level, s, [&](int, int, bool d) { devs += d; });
      sum += len;
      sum2 += double(len) * len;
      steps += len - 1;  // the first pixel follows no step
      deviations += devs;
      shortest = std::min(shortest, len);
    }
  const double count = double(n) * p.levels;
  const double mean = sum / count;
  // Geometric tail after the minimum: mean = m + (1 - p) / p, variance (1 - p) / p^2.
  const double expect = c.min_stroke_length + (1.0 - c.terminate_chance) / c.terminate_chance;
  const double sigma = std::sqrt((1.0 - c.terminate_chance) / std::pow(c.terminate_chance, 2));
  EXPECT_NEAR(mean, expect, 5 * sigma / std::sqrt(count));
  EXPECT_NEAR(sum2 / count - mean * mean, sigma * sigma, 0.1 * sigma * sigma);
  EXPECT_EQ(shortest, c.min_stroke_length);
  const double rate = deviations / steps;
  EXPECT_NEAR(rate, c.deviation_chance, 5 * std::sqrt(0.2 * 0.8 / steps));
}

TEST(NprHatching, StrokesStartStratifiedInEveryCell) {
  NprConfig c = small_config();
  c.cell_size = 16;
  c.strokes_per_cell = 3;
  const HatchParams p = make_hatch_params(c);
  const int cps = p.cells_per_side();
  for (int level = 0; level < p.levels; ++level)
    for (std::int64_t s = 0; s < p.strokes_per_level(); ++s) {
      int x0 = -1, y0 = -1;
      walk_stroke(p, level, s, [&](int x, int y, bool) {
        if (x0 < 0) x0 = x, y0 = y;
      });
      const int cell = static_cast<int>(s / c.strokes_per_cell);
      const int j = static_cast<int>(s % c.strokes_per_cell);
      // The start lies in its cell and in its own band of it (offsets taken on the
      // torus: rounding may reach the next pixel row or column, wrapping at the border).
      const int cx = (cell % cps) * c.cell_size, cy = (cell / cps) * c.cell_size;
      const int rx = ((x0 - cx) % p.size + p.size) % p.size;
      const int ry = ((y0 - cy) % p.size + p.size) % p.size;
      ASSERT_LE(rx, c.cell_size) << "stroke " << s;
      const float band = float(c.cell_size) / c.strokes_per_cell;
      ASSERT_GE(ry, std::floor(j * band)) << "stroke " << s;
      ASSERT_LE(ry, std::ceil((j + 1) * band)) << "stroke " << s;
    }
}

TEST(NprHatching, AxisAlignedStrokesDeviateByOnePixel) {
  NprConfig c = small_config();
  c.levels = 1;
  c.angles = {0.f};
  c.deviation_chance = 0.3f;
  const HatchParams p = make_hatch_params(c);
  for (std::int64_t s = 0; s < 200; ++s) {
    int px = -1, py = -1;
    walk_stroke(p, 0, s, [&](int x, int y, bool deviated) {
      if (px >= 0) {
        EXPECT_EQ((x - px + p.size) % p.size, 1);
        const int dy = ((y - py) % p.size + p.size + 1) % p.size - 1;  // -1, 0, 1
        EXPECT_EQ(std::abs(dy), deviated ? 1 : 0);
      }
      px = x;
      py = y;
    });
  }
}

TEST(NprTone, ThresholdsDefaultStrictlyDecreasing) {
  for (int levels = 1; levels <= kMaxLevels; ++levels) {
    NprConfig c;
    c.levels = levels;
    const auto t = effective_thresholds(c);
    ASSERT_EQ(static_cast<int>(t.size()), levels);
    for (int k = 0; k < levels; ++k) {
      EXPECT_GT(t[k], 0.f);
      EXPECT_LT(t[k], 1.f);
      if (k > 0) EXPECT_LT(t[k], t[k - 1]);
    }
    EXPECT_NO_THROW(validate(c));
  }
  NprConfig bad;
  bad.levels = 3;
  bad.thresholds = {0.8f, 0.9f, 0.2f};
  EXPECT_THROW(validate(bad), InputError);
  bad.thresholds = {0.8f, 0.5f};
  EXPECT_THROW(validate(bad), InputError);
}

TEST(NprTone, BrightestLevelStaysWhite) {
  NprConfig c = small_config();
  c.thresholds = {0.9f, 0.7f, 0.5f, 0.3f, 0.1f};
  // Tone = sRGB-encoded luminance; every pixel at or above 0.9 must stay paper-white.
  Image img(64, 64, 3);
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.80f;  // encodes to ~0.906
  Image out = tone_pass(img, c);
  for (float v : out.data) ASSERT_EQ(v, 1.f);
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.76f;  // ~0.886: level 0
  out = tone_pass(img, c);
  int dark = 0;
  for (float v : out.data) dark += v < 1.f;
  EXPECT_GT(dark, 0);
}

TEST(NprTone, DarknessFollowsToneMonotonically) {
  // Ink fraction averaged per tone band of a gradient never decreases with darker input.
  NprConfig c = small_config();
  const Image in = test::gradient_image(600, 200);
  const Image out = tone_pass(in, c);
  const auto t = effective_thresholds(c);
  std::vector<double> ink(c.levels + 1, 0.0), n(c.levels + 1, 0.0);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const float v = out.at(x, y, 0);
      ASSERT_TRUE(v == 1.f || v == c.pencil_tone);
      const float lum = in.at(x, y, 0);
      const float tone =
          lum <= 0.0031308f ? 12.92f * lum : 1.055f * std::pow(lum, 1 / 2.4f) - 0.055f;
      int k = 0;
      while (k < c.levels && tone < t[k]) ++k;
      ink[k] += v < 1.f;
      n[k] += 1;
    }
  EXPECT_EQ(ink[0], 0.0);  // brightest band white
  for (int k = 1; k <= c.levels; ++k) {
    ASSERT_GT(n[k], 0);
    EXPECT_GT(ink[k] / n[k], ink[k - 1] / n[k - 1]) << "band " << k;
  }
}

TEST(NprTone, ColorPencilStrokesCarryThePixelColour) {
  NprConfig c = small_config();
  c.style = NprStyle::kColorPencil;
  Image img(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      img.at(x, y, 0) = 0.9f;
      img.at(x, y, 1) = 0.1f;
      img.at(x, y, 2) = 0.05f;
    }
  const Image out = tone_pass(img, c);
  int strokes = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool white = out.at(x, y, 0) == 1.f && out.at(x, y, 1) == 1.f && out.at(x, y, 2) == 1.f;
      if (white) continue;
      ++strokes;
      for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(out.at(x, y, ch), img.at(x, y, ch));
    }
  EXPECT_GT(strokes, 64 * 64 / 4);
}

TEST(NprHatching, RegionsOfLargeImagesUseDifferentOffsets) {
  std::set<std::pair<int, int>> offsets;
  for (int ry = 0; ry < 4; ++ry)
    for (int rx = 0; rx < 4; ++rx) {
      int ox, oy;
      region_offset(99, 512, rx, ry, ox, oy);
      ASSERT_GE(ox, 0);
      ASSERT_LT(ox, 512);
      ASSERT_GE(oy, 0);
      ASSERT_LT(oy, 512);
      offsets.insert({ox, oy});
    }
  EXPECT_EQ(offsets.size(), 16u);
}

}  // namespace
}  // namespace rtmini::npr
