// Reading a saved render's colour and AOV layers for the standalone post-process.
#include "post_inputs.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "rtmini/io/error.hpp"

namespace rtmini::npr {
namespace {

[[maybe_unused]] Image ramp(int w, int h, int channels, float scale) {  // unused without OpenEXR
  Image img(w, h, channels);
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = scale * float(i % 97);
  return img;
}

TEST(NprPostInputs, ExrLayersBecomeInputs) {
#ifndef RTMINI_HAVE_EXR
  GTEST_SKIP() << "built without OpenEXR";
#else
  const std::string path = ::testing::TempDir() + "npr_post_inputs.exr";
  const Image color = ramp(16, 8, 3, 0.01f), edge = ramp(16, 8, 1, 0.005f);
  const Image depth = ramp(16, 8, 1, 2.f), normal = ramp(16, 8, 3, -0.01f);
  write_exr_layers(path, {{"", color}, {"edge", edge}, {"depth.Z", depth}, {"normal", normal}});
  const PostImages li = read_post_images(path);
  std::remove(path.c_str());
  const NprInputs in = li.inputs();
  ASSERT_NE(in.edge, nullptr);
  ASSERT_NE(in.depth, nullptr);
  ASSERT_NE(in.normal, nullptr);
  EXPECT_EQ(in.object, nullptr);
  EXPECT_EQ(in.color->data, color.data);
  EXPECT_EQ(in.edge->data, edge.data);
  EXPECT_EQ(in.depth->data, depth.data);
  EXPECT_EQ(in.normal->data, normal.data);
#endif
}

TEST(NprPostInputs, ExrWithoutColourIsBadInput) {
#ifndef RTMINI_HAVE_EXR
  GTEST_SKIP() << "built without OpenEXR";
#else
  const std::string path = ::testing::TempDir() + "npr_post_nocolour.exr";
  write_exr_layers(path, {{"depth.Z", ramp(4, 4, 1, 1.f)}});
  EXPECT_THROW(read_post_images(path), InputError);
  std::remove(path.c_str());
#endif
}

}  // namespace
}  // namespace rtmini::npr
