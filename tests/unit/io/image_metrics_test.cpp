// compare_images: the error metrics of the speed/accuracy study against hand-computed values.
#include "rtmini/report/image_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "rtmini/io/error.hpp"

namespace rtmini {
namespace {

Image constant(int w, int h, float v) {
  Image im(w, h, 3);
  for (float& x : im.data) x = v;
  return im;
}

TEST(ImageMetrics, IdenticalImagesHaveZeroErrorAndUnitSsim) {
  Image a(16, 12, 3);
  for (std::size_t i = 0; i < a.data.size(); ++i) a.data[i] = static_cast<float>(i % 7) / 7.f;
  const ImageErrors e = compare_images(a, a, "same");
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.rel_mse, 0.0);
  EXPECT_TRUE(std::isinf(e.psnr));
  EXPECT_NEAR(e.ssim, 1.0, 1e-12);
}

TEST(ImageMetrics, ConstantOffsetMatchesClosedForm) {
  const Image ref = constant(9, 9, 0.5f), img = constant(9, 9, 0.6f);
  const ImageErrors e = compare_images(img, ref, "offset");
  EXPECT_NEAR(e.rmse, 0.1, 1e-6);
  EXPECT_NEAR(e.rel_mse, 0.01 / (0.25 + 0.01), 1e-6);
  EXPECT_NEAR(e.psnr, 20.0, 1e-4);  // peak 1, MSE 0.01
  EXPECT_LT(e.ssim, 1.0);
  EXPECT_GT(e.ssim, 0.9);  // a small luminance shift keeps the structure
}

TEST(ImageMetrics, NoiseLowersSsimMoreThanShift) {
  Image ref(32, 32, 3), noisy(32, 32, 3), shifted(32, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = 0.25f + 0.5f * static_cast<float>(x) / 31.f;
        ref.at(x, y, c) = v;
        shifted.at(x, y, c) = v + 0.05f;
        noisy.at(x, y, c) = v + (((x * 7 + y * 13) % 5) - 2) * 0.05f;
      }
  EXPECT_LT(compare_images(noisy, ref, "n").ssim, compare_images(shifted, ref, "s").ssim);
}

TEST(ImageMetrics, SizeMismatchIsAnInputErrorNamingTheFile) {
  try {
    compare_images(constant(4, 4, 0), constant(4, 5, 0), "ref.exr");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ref.exr"), std::string::npos);
  }
}

}  // namespace
}  // namespace rtmini
