// Edge compositing: anti-aliased darkening proportional to the stencil fraction.
#include <gtest/gtest.h>

#include "npr.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::npr {
namespace {

TEST(NprEdges, DarknessProportionalToEdgeFraction) {
  NprConfig c;
  c.edge_darkness = 0.8f;
  c.edge_threshold = 0.1f;
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
      const float expect = e >= c.edge_threshold ? 1.f - c.edge_darkness * e : 1.f;
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_FLOAT_EQ(out.at(x, y, ch), color.at(x, y, ch) * expect) << x << "," << y;
    }
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
  for (float v : out.data) EXPECT_FLOAT_EQ(v, 1.f - 0.5f * c.edge_darkness);
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
  EXPECT_THROW(parse_style("watercolour"), InputError);
  EXPECT_EQ(parse_style(style_name(NprStyle::kColorPencil)), NprStyle::kColorPencil);
}

}  // namespace
}  // namespace rtmini::npr
