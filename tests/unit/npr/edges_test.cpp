// Lines from the ray stencil: ink ramp, resolution-independent width, full black, jitter.
#include <gtest/gtest.h>

#include <cmath>

#include "npr.hpp"
#include "npr_test_util.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::npr {
namespace {

TEST(NprEdges, InkRampsWithTheStencilFraction) {
  // Without growth, a pixel's line ink is its own stencil fraction mapped linearly
  // from edge_threshold (white) to edge_full (full darkness).
  NprConfig c;
  c.edge_darkness = 0.8f;
  c.edge_threshold = 0.1f;
  c.edge_full = 0.5f;
  c.line_width = 0.f;
  Image color(9, 4, 3), edge(9, 4, 1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 9; ++x) {
      for (int ch = 0; ch < 3; ++ch) color.at(x, y, ch) = 0.25f * (y + 1);
      edge.at(x, y, 0) = x / 8.f;  // 0, 1/8, ..., 1: the possible 8-ray fractions
    }
  const Image out = edge_pass(color, edge, c);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 9; ++x) {
      const float e = x / 8.f;
      const float ink = e >= c.edge_threshold ? std::fmin(1.f, (e - 0.1f) / 0.4f) : 0.f;
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(out.at(x, y, ch), color.at(x, y, ch) * (1.f - c.edge_darkness * ink), 1e-6f)
            << x << "," << y;
    }
}

// Pixels per row with line ink >= 0.5 for a one-pixel-wide stencil line.
double drawn_width(int size, const NprConfig& c) {
  Image edge(size, 8, 1);
  for (int y = 0; y < 8; ++y) edge.at(size / 2, y, 0) = 0.5f;
  const Image ink = line_ink(edge, c);
  double n = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < size; ++x) n += ink.at(x, y, 0) >= 0.5f;
  return n / 8.0;
}

TEST(NprEdges, LineWidthIsInPixelsAtAnyResolution) {
  NprConfig c;
  for (float w : {0.f, 1.5f, 4.f}) {
    c.line_width = w;
    const double small = drawn_width(64, c), large = drawn_width(512, c);
    EXPECT_EQ(small, large) << "width " << w;
    EXPECT_NEAR(small, 1.0 + 2.0 * std::floor(0.5 * w + 0.5), 0.01) << "width " << w;
  }
}

TEST(NprEdges, LinesReachFullBlackAndAreAntiAliased) {
  Image color, edge;
  test::disk_scene(120, 90, color, edge);
  NprConfig c;
  const Image ink = line_ink(edge, c);
  int full = 0, partial = 0;
  for (float v : ink.data) {
    full += v >= 1.f;
    partial += v > 0.f && v < 1.f;
  }
  EXPECT_GT(full, 100);
  EXPECT_GT(partial, 50);
  for (float& v : color.data) v = 1.f;
  const Image out = edge_pass(color, edge, c);
  float darkest = 1.f;
  for (float v : out.data) darkest = std::fmin(darkest, v);
  EXPECT_EQ(darkest, 0.f);
}

TEST(NprEdges, JitterMovesLinesButKeepsThem) {
  Image color, edge;
  test::disk_scene(160, 120, color, edge);
  NprConfig c;
  const Image straight = line_ink(edge, c);
  c.line_jitter = 1.5f;
  const Image wobbly = line_ink(edge, c);
  double a = 0, b = 0, moved = 0;
  for (std::size_t i = 0; i < straight.data.size(); ++i) {
    a += straight.data[i];
    b += wobbly.data[i];
    moved += std::fabs(straight.data[i] - wobbly.data[i]);
  }
  EXPECT_GT(moved, 0.2 * a);
  EXPECT_NEAR(b, a, 0.3 * a);
}

TEST(NprEdges, ApplyPassesUsesTheEdgeLayerOnlyWhenEnabled) {
  NprConfig c;
  c.pass_hatch = c.pass_paper = false;
  Image color(4, 4, 3), edge(4, 4, 1);
  for (float& v : color.data) v = 1.f;
  for (float& v : edge.data) v = 0.5f;
  NprInputs in;
  in.color = &color;
  in.edge = &edge;
  Image out = apply_passes(in, c);
  for (float v : out.data) EXPECT_FLOAT_EQ(v, 1.f - c.edge_darkness);
  c.pass_edges = false;
  out = apply_passes(in, c);
  for (float v : out.data) EXPECT_EQ(v, 1.f);
}

TEST(NprEdges, MismatchedAovSizeIsBadInput) {
  NprConfig c;
  Image color(4, 4, 3), edge(5, 4, 1);
  NprInputs in;
  in.color = &color;
  in.edge = &edge;
  EXPECT_THROW(apply_passes(in, c), InputError);
  in.color = nullptr;
  EXPECT_THROW(apply_passes(in, c), InputError);
}

TEST(NprConfigCheck, RejectsOutOfRangeParameters) {
  auto bad = [](auto mutate) {
    NprConfig c;
    mutate(c);
    EXPECT_THROW(validate(c), InputError);
  };
  bad([](NprConfig& c) { c.levels = 0; });
  bad([](NprConfig& c) { c.levels = kMaxLevels + 1; });
  bad([](NprConfig& c) { c.terminate_chance = 0.f; });
  bad([](NprConfig& c) { c.deviation_chance = 1.5f; });
  bad([](NprConfig& c) { c.min_stroke_length = 0; });
  bad([](NprConfig& c) { c.cell_size = 0; });
  bad([](NprConfig& c) { c.angles = {0.f}; });
  bad([](NprConfig& c) { c.paper_levels = 1; });
  bad([](NprConfig& c) { c.paper_octaves = 9; });
  bad([](NprConfig& c) { c.edge_darkness = -0.1f; });
  bad([](NprConfig& c) { c.edge_full = c.edge_threshold; });
  bad([](NprConfig& c) { c.line_width = -1.f; });
  bad([](NprConfig& c) { c.stroke_width = 0.f; });
  bad([](NprConfig& c) { c.white_percentile = 0.f; });
  bad([](NprConfig& c) { c.exposure = 0.f; });
  EXPECT_THROW(parse_style("watercolour"), InputError);
  EXPECT_EQ(parse_style(style_name(NprStyle::kColorPencil)), NprStyle::kColorPencil);
}

}  // namespace
}  // namespace rtmini::npr
