// Tonal art map (nesting, calibration, anti-aliasing, stroke statistics) and
// the tone mapping that reads it (hand-drawn seed §4, Praun et al. 2001).
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
  c.bitmap_size = 128;
  c.seed = 7;
  return c;
}

double mean(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += x;
  return s / double(v.size());
}

TEST(NprHatching, DarkerLevelsContainEveryLighterStroke) {
  const NprConfig c = small_config();
  const ToneArtMap tam = build_tone_art_map(c);
  ASSERT_EQ(tam.levels, c.levels);
  std::vector<float> lighter = level_ink(tam, 0);
  for (int k = 1; k < tam.levels; ++k) {
    const std::vector<float> darker = level_ink(tam, k);
    std::size_t violations = 0;
    for (std::size_t i = 0; i < darker.size(); ++i) violations += darker[i] < lighter[i];
    EXPECT_EQ(violations, 0u) << "level " << k << " lost ink of level " << k - 1;
    EXPECT_GT(mean(darker), mean(lighter) + 0.05) << "level " << k << " adds too few strokes";
    lighter = darker;
  }
}

TEST(NprHatching, LevelInkMatchesItsTarget) {
  // Calibration measured from the generated bitmaps themselves, for the default
  // targets and for explicit level tones.
  for (int variant = 0; variant < 2; ++variant) {
    NprConfig c = small_config();
    if (variant == 1) {
      c.levels = 4;
      c.thresholds = {0.9f, 0.6f, 0.4f, 0.2f};
    }
    const ToneArtMap tam = build_tone_art_map(c);
    const std::vector<double> target = level_ink_targets(c);
    for (int k = 0; k < tam.levels; ++k) {
      const double measured = mean(level_ink(tam, k));
      EXPECT_NEAR(measured, tam.coverage[k], 1e-6) << "level " << k;
      EXPECT_NEAR(measured, target[k], 0.02) << "variant " << variant << " level " << k;
    }
  }
}

TEST(NprHatching, StrokesAreAntiAliased) {
  const ToneArtMap tam = build_tone_art_map(small_config());
  const std::vector<float> ink = level_ink(tam, 0);
  std::size_t partial = 0, inked = 0;
  for (float v : ink) {
    inked += v > 0.f;
    partial += v > 0.f && v < 0.8f;
  }
  ASSERT_GT(inked, 0u);
  // Stroke edges and tapered ends are grey, not a hard 0/1 mask.
  EXPECT_GT(double(partial) / double(inked), 0.2);
}

TEST(NprHatching, MeanStrokeLengthMatchesMarkovChain) {
  NprConfig c = small_config();
  c.bitmap_size = 256;
  c.min_stroke_length = 6;
  c.terminate_chance = 0.1f;
  c.deviation_chance = 0.2f;
  c.stroke_bend = 0.f;
  c.angles = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
  const HatchParams p = make_hatch_params(c);
  double sum = 0, sum2 = 0, steps = 0, deviations = 0, count = 0;
  int shortest = 1 << 30;
  for (int round = 0; round < 20; ++round)
    for (int cell = 0; cell < p.cells(); ++cell) {
      float py = 0;
      int devs = 0;
      const int len = walk_stroke(p, round % p.levels, round, cell, [&](float, float y, int step) {
        // Axis-aligned strokes: a deviation is a one-pixel move in y.
        if (step > 0 && std::fabs(y - py) > 0.5f) {
          EXPECT_NEAR(std::fabs(y - py), 1.f, 1e-4f);
          ++devs;
        }
        py = y;
      });
      sum += len;
      sum2 += double(len) * len;
      steps += len - 1;  // the first point follows no step
      deviations += devs;
      count += 1;
      shortest = std::min(shortest, len);
    }
  const double m = sum / count;
  // Geometric tail after the minimum: mean = m + (1 - p) / p, variance (1 - p) / p^2.
  const double expect = c.min_stroke_length + (1.0 - c.terminate_chance) / c.terminate_chance;
  const double sigma = std::sqrt((1.0 - c.terminate_chance) / std::pow(c.terminate_chance, 2));
  EXPECT_NEAR(m, expect, 5 * sigma / std::sqrt(count));
  EXPECT_NEAR(sum2 / count - m * m, sigma * sigma, 0.1 * sigma * sigma);
  EXPECT_EQ(shortest, c.min_stroke_length);
  EXPECT_NEAR(deviations / steps, c.deviation_chance, 5 * std::sqrt(0.2 * 0.8 / steps));
}

TEST(NprHatching, StrokesBendSlightly) {
  NprConfig c = small_config();
  c.deviation_chance = 0.f;
  c.stroke_bend = 1.f;
  const HatchParams p = make_hatch_params(c);
  int bent = 0;
  for (int cell = 0; cell < 100; ++cell) {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0, xl = 0, yl = 0;
    const int len = walk_stroke(p, 0, 0, cell, [&](float x, float y, int step) {
      if (step == 0) x0 = x, y0 = y;
      if (step == 1) x1 = x, y1 = y;
      xl = x, yl = y;
    });
    if (len < 3) continue;
    // Turn between the first step and the chord: at most bend * length.
    const float a0 = std::atan2(y1 - y0, x1 - x0), a1 = std::atan2(yl - y0, xl - x0);
    const float turn = std::fabs(std::remainder(a1 - a0, 2.f * float(math::kPi)));
    EXPECT_LE(turn, p.bend * len);
    bent += turn > 1e-3f;
  }
  EXPECT_GT(bent, 50);
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
      if (k > 0) {
        EXPECT_LT(t[k], t[k - 1]);
      }
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

TEST(NprTone, BrightestPixelsStayPaperWhite) {
  // The white percentile of a ramp maps to tone 1: every pixel at or above it is untouched paper.
  NprConfig c = small_config();
  c.white_percentile = 0.9f;
  const Image in = test::gradient_image(200, 64);
  const Image out = tone_pass(in, c);
  const float white = exposure_white(in, c);
  EXPECT_NEAR(white, 0.9f, 0.01f);
  int inked_bright = 0, inked_dark = 0;
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const bool inked = out.at(x, y, 0) < 1.f;
      if (in.at(x, y, 0) >= white) inked_bright += inked;
      if (in.at(x, y, 0) < 0.5f * white) inked_dark += inked;
    }
  EXPECT_EQ(inked_bright, 0);
  EXPECT_GT(inked_dark, 0);
}

TEST(NprTone, BlurredDrawingReproducesTheTone) {
  // A ramp drawn with hatching only: at the stroke spacing its tone follows the ramp.
  NprConfig c = small_config();
  c.pass_edges = c.pass_paper = false;
  const Image in = test::gradient_image(400, 120);
  NprInputs inputs;
  inputs.color = &in;
  const Image out = apply_passes(inputs, c);
  const QualityStats q = measure_quality(inputs, out, c);
  ASSERT_TRUE(q.has_tone);
  EXPECT_FALSE(q.has_lines);
  EXPECT_GT(q.tone_correlation, 0.95);
  EXPECT_LT(q.tone_mean_abs_error, 0.05);
  // Without calibration (all of the ink at the darkest level) the same measure fails.
  NprConfig flat = c;
  flat.exposure = 0.25f;
  const QualityStats dark = measure_quality(inputs, apply_passes(inputs, flat), c);
  EXPECT_GT(dark.tone_mean_abs_error, 0.1);
}

TEST(NprTone, ColorPencilKeepsTheHue) {
  NprConfig c = small_config();
  c.style = NprStyle::kColorPencil;
  c.white_percentile = 1.f;
  // Red at half brightness, then a bright grey that sets the white point.
  Image img(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool red = y < 60;
      img.at(x, y, 0) = red ? 0.45f : 1.f;
      img.at(x, y, 1) = red ? 0.05f : 1.f;
      img.at(x, y, 2) = red ? 0.025f : 1.f;
    }
  const Image out = tone_pass(img, c);
  int strokes = 0;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 64; ++x) {
      const float r = out.at(x, y, 0), g = out.at(x, y, 1), b = out.at(x, y, 2);
      if (r >= 0.999f && g >= 0.999f && b >= 0.999f) continue;
      ++strokes;
      // The pigment is the pixel's colour at full brightness: red stays the strongest
      // channel and the green/blue ratio of the input is kept.
      ASSERT_GT(r, g);
      ASSERT_GE(g, b);
    }
  EXPECT_GT(strokes, 60 * 64 / 2);
}

TEST(NprTone, ObjectsGetTheirOwnHatching) {
  // Two objects of one flat tone: with per-object directions the halves differ.
  NprConfig c = small_config();
  c.white_percentile = 1.f;  // the one white pixel sets the exposure
  Image img(128, 64, 3), object(128, 64, 1);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x) {
      for (int ch = 0; ch < 3; ++ch) img.at(x, y, ch) = x == 0 && y == 0 ? 1.f : 0.2f;
      object.at(x, y, 0) = x < 64 ? 1.f : 2.f;
    }
  const Image out = tone_pass(img, c, &object);
  const Image same = tone_pass(img, c, nullptr);
  std::size_t differ = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 64; x < 128; ++x) differ += out.at(x, y, 0) != same.at(x, y, 0);
  EXPECT_GT(differ, 64u * 64u / 4);
}

}  // namespace
}  // namespace rtmini::npr
