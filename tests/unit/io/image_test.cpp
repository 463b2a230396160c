#include "rtmini/io/image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "../optional_features.hpp"
#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/srgb.hpp"

namespace rtmini {
namespace {

// Linear values that are exact decodes of 8-bit codes, so 8-bit formats round-trip exactly.
Image make_8bit_exact_image(int w, int h, int c, unsigned seed) {
  std::mt19937 rng(seed);
  Image img(w, h, c);
  for (float& v : img.data) v = srgb_decode_8bit(static_cast<std::uint8_t>(rng() & 255u));
  return img;
}

TEST(Srgb, EncodeDecodeAreInverseOnCodes) {
  for (int code = 0; code < 256; ++code)
    EXPECT_EQ(srgb_encode_8bit(srgb_decode_8bit(static_cast<std::uint8_t>(code))), code);
  EXPECT_EQ(srgb_encode_8bit(-1.f), 0);
  EXPECT_EQ(srgb_encode_8bit(5.f), 255);
  EXPECT_EQ(srgb_encode_8bit(std::nanf("")), 0);
  EXPECT_NEAR(srgb_encode(0.5), 0.735356983, 1e-6);  // IEC 61966-2-1 curve
}

TEST(Image, PpmRoundTrip) {
  test::TempDir dir;
  const Image img = make_8bit_exact_image(7, 5, 3, 1);
  write_image(dir.file("a.ppm"), img);
  EXPECT_EQ(test::count_files(dir.path()), 1);
  const std::string bytes = test::read_file(dir.file("a.ppm"));
  EXPECT_EQ(bytes.substr(0, 11), "P6\n7 5\n255\n");
  EXPECT_EQ(bytes.size(), 11u + 7 * 5 * 3);
  const Image back = read_image(dir.file("a.ppm"));
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  ASSERT_EQ(back.channels, 3);
  EXPECT_EQ(back.data, img.data);
}

TEST(Image, PpmP3AndSixteenBit) {
  test::TempDir dir;
  test::write_file(dir.file("p3.ppm"), "P3\n# comment\n2 1\n255\n255 0 0   0 255 255\n");
  const Image a = read_ppm(dir.file("p3.ppm"));
  EXPECT_EQ(a.at(0, 0, 0), 1.f);
  EXPECT_EQ(a.at(0, 0, 1), 0.f);
  EXPECT_EQ(a.at(1, 0, 2), 1.f);
  // 16-bit P6: big-endian samples, maxval 65535.
  std::string p6 = "P6\n1 1\n65535\n";
  p6 += std::string("\xff\xff\x00\x00\x80\x00", 6);
  test::write_file(dir.file("p16.ppm"), p6);
  const Image b = read_ppm(dir.file("p16.ppm"));
  EXPECT_EQ(b.at(0, 0, 0), 1.f);
  EXPECT_EQ(b.at(0, 0, 1), 0.f);
  EXPECT_NEAR(b.at(0, 0, 2), srgb_decode(32768.f / 65535.f), 1e-7);
}

TEST(Image, PpmWritesGreyAsRgb) {
  test::TempDir dir;
  const Image grey = make_8bit_exact_image(3, 2, 1, 2);
  write_ppm(dir.file("g.ppm"), grey);
  const Image back = read_ppm(dir.file("g.ppm"));
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(back.at(x, y, c), grey.at(x, y, 0));
}

TEST(Image, PngRoundTripRgbAndRgba) {
  RTMINI_REQUIRE_PNG();
  test::TempDir dir;
  const Image rgb = make_8bit_exact_image(9, 4, 3, 3);
  write_image(dir.file("a.png"), rgb);
  EXPECT_EQ(read_image(dir.file("a.png")).data, rgb.data);

  Image rgba = make_8bit_exact_image(4, 3, 4, 4);
  for (std::size_t i = 3; i < rgba.data.size(); i += 4)
    rgba.data[i] = static_cast<float>(i % 256) / 255.f;
  write_png(dir.file("b.PNG"), rgba);
  const Image back = read_png(dir.file("b.PNG"));
  ASSERT_EQ(back.channels, 4);
  EXPECT_EQ(back.data, rgba.data);
  EXPECT_EQ(test::count_files(dir.path()), 2);
}

TEST(Image, ExrRoundTripHalfAndFloat) {
  RTMINI_REQUIRE_EXR();
  test::TempDir dir;
  Image img(6, 3, 3);
  for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = 0.001f * i * i + 1e-3f;
  img.data[4] = 1234.5f;  // HDR values stay linear
  write_image(dir.file("h.exr"), img);
  const Image half = read_image(dir.file("h.exr"));
  ASSERT_EQ(half.channels, 3);
  for (std::size_t i = 0; i < img.data.size(); ++i)
    EXPECT_NEAR(half.data[i], img.data[i], img.data[i] * 1e-3f);
  write_exr(dir.file("f.exr"), img, ExrPixel::kFloat);
  EXPECT_EQ(read_exr(dir.file("f.exr")).data, img.data);
}

TEST(Image, ExrLayersRoundTrip) {
  RTMINI_REQUIRE_EXR();
  test::TempDir dir;
  Image beauty(4, 2, 3), normal(4, 2, 3), depth(4, 2, 1), cost(4, 2, 1);
  for (std::size_t i = 0; i < beauty.data.size(); ++i) {
    beauty.data[i] = 0.1f * i;
    normal.data[i] = -0.05f * i;
  }
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    depth.data[i] = 100.f + i;
    cost.data[i] = 3.f * i;
  }
  write_exr_layers(dir.file("aov.exr"),
                   {{"", beauty}, {"normal", normal}, {"depth.Z", depth}, {"cost", cost}});
  const auto layers = read_exr_layers(dir.file("aov.exr"));
  std::map<std::string, Image> by_name(layers.begin(), layers.end());
  ASSERT_EQ(by_name.size(), 4u);
  EXPECT_EQ(by_name.at("").data, beauty.data);
  EXPECT_EQ(by_name.at("normal").data, normal.data);
  EXPECT_EQ(by_name.at("depth.Z").data, depth.data);
  EXPECT_EQ(by_name.at("cost.Y").data, cost.data);
  EXPECT_EQ(read_exr(dir.file("aov.exr")).data, beauty.data);
}

TEST(Image, UnknownExtensionIsInputError) {
  test::TempDir dir;
  EXPECT_THROW(write_image(dir.file("x.tiff"), Image(1, 1, 3)), InputError);
  EXPECT_THROW(read_image(dir.file("x")), InputError);
  EXPECT_EQ(test::count_files(dir.path()), 0);
}

}  // namespace
}  // namespace rtmini
