// Scene-file settings: every [settings] key is read, and bad values are
// InputErrors that point at the offending line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "render_settings.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::sketch::test {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& text) {
  const std::string path = write_temp("sketch_settings.toml", text);
  try {
    RenderSettings s;
    apply_scene_settings(read_scene_file(path), s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SketchSettings, ReadsEveryKey) {
  const std::string path =
      write_temp("sketch_ok.toml",
                 "ambient = [0.1, 0.2, 0.3]\n[settings]\nwidth = 33\nheight = 22\nspp = 5\n"
                 "soft_shadows = false\nshadow_samples = 9\nbounces = 4\nglossy_samples = 3\n"
                 "indirect = true\nedge_thickness = 2.5\ncrease_angle = 45\n"
                 "depth_threshold = 0.2\nstencil_samples = 8\nsphere_subdivisions = 2\n"
                 "smooth = false\nbackground = [0.5, 0.5, 1]\nseed = 42\nbvh = \"lbvh\"\n"
                 "aov = [\"depth\", \"edge\"]\nstyle = \"color-pencil\"\nchunk_pixels = 7\n");
  RenderSettings s;
  apply_scene_settings(read_scene_file(path), s);
  EXPECT_EQ(s.width, 33);
  EXPECT_EQ(s.height, 22);
  EXPECT_EQ(s.spp, 5);
  EXPECT_FALSE(s.soft_shadows);
  EXPECT_EQ(s.shadow_samples, 9);
  EXPECT_EQ(s.bounces, 4);
  EXPECT_EQ(s.glossy_samples, 3);
  EXPECT_TRUE(s.indirect);
  EXPECT_DOUBLE_EQ(s.edge_thickness, 2.5);
  EXPECT_DOUBLE_EQ(s.crease_angle_deg, 45);
  EXPECT_DOUBLE_EQ(s.depth_threshold, 0.2);
  EXPECT_EQ(s.stencil_samples, 8);
  EXPECT_EQ(s.sphere_subdivisions, 2);
  EXPECT_FALSE(s.smooth);
  EXPECT_FLOAT_EQ(s.background.z, 1.f);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.bvh, bvh::BuildQuality::kLbvh);
  EXPECT_EQ(s.aov.size(), 2u);
  EXPECT_EQ(s.style, "color_pencil");
  EXPECT_EQ(s.chunk_pixels, 7);
  EXPECT_FLOAT_EQ(s.ambient.y, 0.2f);
}

TEST(SketchSettings, BadValuesNameFileAndLine) {
  EXPECT_NE(error_of("[settings]\nwidth = 10\nfoo = 1\n")
                .find("sketch_settings.toml:3: unknown key 'foo'"),
            std::string::npos);
  EXPECT_NE(error_of("[settings]\nwidth = 0\n").find(":2: 'width' in [settings] must be >= 1"),
            std::string::npos);
  EXPECT_NE(error_of("[settings]\n\nshadow_samples = -4\n").find(":3: 'shadow_samples'"),
            std::string::npos);
  EXPECT_NE(error_of("[settings]\nspp = 2.5\n").find(":2: 'spp' in [settings] must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of("[settings]\naov = [\"depth\", \"colour\"]\n").find(":2: 'aov'"),
            std::string::npos);
  EXPECT_NE(error_of("[settings]\nstyle = \"oil\"\n").find(":2: 'style'"), std::string::npos);
}

}  // namespace
}  // namespace rtmini::sketch::test
