// The passes are a pure function of (inputs, parameters, seed).
#include <gtest/gtest.h>

#include <cstring>

#include "npr.hpp"
#include "npr_test_util.hpp"

namespace rtmini::npr {
namespace {

Image run(const NprConfig& c) {
  Image color, edge;
  test::disk_scene(200, 150, color, edge);
  NprInputs in;
  in.color = &color;
  in.edge = &edge;
  return apply_passes(in, c);
}

bool same_bytes(const Image& a, const Image& b) {
  return a.data.size() == b.data.size() &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

TEST(NprDeterminism, SameSeedSameBytes) {
  for (NprStyle style : {NprStyle::kSketch, NprStyle::kColorPencil}) {
    NprConfig c;
    c.style = style;
    c.seed = 42;
    EXPECT_TRUE(same_bytes(run(c), run(c))) << style_name(style);
  }
}

TEST(NprDeterminism, OtherSeedOtherStrokesAndPaper) {
  NprConfig c;
  c.seed = 42;
  const Image a = run(c);
  c.seed = 43;
  const Image b = run(c);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.data.size(); ++i) differ += a.data[i] != b.data[i];
  EXPECT_GT(differ, a.data.size() / 10);
}

}  // namespace
}  // namespace rtmini::npr
