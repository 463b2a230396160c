// NPR outputs on synthetic inputs against committed references (tests/reference/npr).
// Set RTMINI_NPR_UPDATE_REFERENCE=1 to rewrite them after an intended change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "../optional_features.hpp"
#include "npr.hpp"
#include "npr_test_util.hpp"
#include "rtmini/io/srgb.hpp"

namespace rtmini::npr {
namespace {

struct Case {
  const char* name;
  NprStyle style;
  bool hatch, edges, paper;
};

// Fraction of 8-bit sRGB samples that differ by more than one code. References are
// 8-bit PNGs, so a bit-exact float comparison is not possible; one code of slack
// absorbs the round trip, and the fraction bounds pixels that changed stroke state.
double mismatch(const Image& out, const Image& ref) {
  if (out.width != ref.width || out.height != ref.height) return 1.0;
  std::size_t bad = 0;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const int a = srgb_encode_8bit(out.at(x, y, c));
        const int b = srgb_encode_8bit(ref.at(x, y, c));
        bad += std::abs(a - b) > 1;
      }
  return double(bad) / (3.0 * out.width * out.height);
}

void check(const Case& k) {
  Image color, edge;
  if (std::string(k.name).find("gradient") != std::string::npos) {
    color = test::gradient_image(320, 96);
    edge = Image(320, 96, 1);
  } else {
    test::disk_scene(240, 180, color, edge);
  }
  NprConfig c;
  c.style = k.style;
  c.pass_hatch = k.hatch;
  c.pass_edges = k.edges;
  c.pass_paper = k.paper;
  c.seed = 2024;
  NprInputs in;
  in.color = &color;
  in.edge = &edge;
  RTMINI_REQUIRE_PNG();  // the references are 8-bit PNGs
  const Image out = apply_passes(in, c);
  const std::string path = std::string(RTMINI_NPR_REFERENCE_DIR) + "/" + k.name + ".png";
  const char* update = std::getenv("RTMINI_NPR_UPDATE_REFERENCE");
  if (update != nullptr && std::string(update) == "1") {
    write_image(path, out);
    GTEST_SKIP() << "wrote " << path;
  }
  const Image ref = read_image(path);
  EXPECT_LT(mismatch(out, ref), 1e-3) << k.name;
}

TEST(NprReference, GradientHatching) {
  check({"gradient_hatch", NprStyle::kSketch, true, false, false});
}
TEST(NprReference, GradientAllPasses) {
  check({"gradient_all", NprStyle::kSketch, true, true, true});
}
TEST(NprReference, DiskEdgesOnly) { check({"disk_edges", NprStyle::kNone, false, true, false}); }
TEST(NprReference, DiskSketch) { check({"disk_sketch", NprStyle::kSketch, true, true, true}); }
TEST(NprReference, DiskColorPencil) {
  check({"disk_color_pencil", NprStyle::kColorPencil, true, true, true});
}
TEST(NprReference, DiskPaperOnly) { check({"disk_paper", NprStyle::kNone, false, false, true}); }

}  // namespace
}  // namespace rtmini::npr
