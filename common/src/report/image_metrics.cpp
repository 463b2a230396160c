#include "rtmini/report/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rtmini/io/error.hpp"

namespace rtmini {

namespace {

// Rec. 709 luma weights on the stored (linear) values: SSIM compares structure in luminance.
double luminance(const Image& im, int x, int y) {
  return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

// Mean SSIM over 8x8 windows with stride 4 (uniform weights); c1, c2 as in Wang et al.
// with dynamic range `peak`. Images smaller than a window use one window of their size.
double mean_ssim(const Image& a, const Image& b, double peak) {
  const int win_x = std::min(8, a.width), win_y = std::min(8, a.height);
  const double c1 = (0.01 * peak) * (0.01 * peak), c2 = (0.03 * peak) * (0.03 * peak);
  double total = 0;
  long windows = 0;
  for (int y0 = 0; y0 + win_y <= a.height; y0 += 4) {
    for (int x0 = 0; x0 + win_x <= a.width; x0 += 4) {
      double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
      for (int y = y0; y < y0 + win_y; ++y)
        for (int x = x0; x < x0 + win_x; ++x) {
          const double la = luminance(a, x, y), lb = luminance(b, x, y);
          sa += la;
          sb += lb;
          saa += la * la;
          sbb += lb * lb;
          sab += la * lb;
        }
      const double n = static_cast<double>(win_x) * win_y;
      const double ma = sa / n, mb = sb / n;
      // E[x^2] - E[x]^2 can round below zero on a flat window; a variance is never negative.
      const double va = std::max(0.0, saa / n - ma * ma), vb = std::max(0.0, sbb / n - mb * mb);
      const double cov = sab / n - ma * mb;
      total += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++windows;
    }
  }
  return windows > 0 ? total / static_cast<double>(windows) : 1.0;
}

}  // namespace

ImageErrors compare_images(const Image& image, const Image& reference, const std::string& what) {
  if (image.width != reference.width || image.height != reference.height || image.channels < 3 ||
      reference.channels < 3)
    throw InputError(what + ": reference is " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height) + "x" + std::to_string(reference.channels) +
                     ", the image " + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + "x" + std::to_string(image.channels) +
                     " (need equal sizes and RGB)");
  // rel: squared error relative to the reference's value (+1e-2 keeps black pixels from
  // dominating); peak: the dynamic range for PSNR and SSIM, at least 1 (display range) but as
  // high as the brightest reference value for linear HDR images.
  double se = 0, rel = 0, peak = 1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double r = reference.at(x, y, c);
        const double d = static_cast<double>(image.at(x, y, c)) - r;
        se += d * d;
        rel += d * d / (r * r + 1e-2);
        peak = std::max(peak, r);
      }
  const double n = 3.0 * image.width * image.height;
  ImageErrors e;
  const double mse = n > 0 ? se / n : 0;
  e.rmse = std::sqrt(mse);
  e.rel_mse = n > 0 ? rel / n : 0;
  e.psnr = mse > 0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
  e.ssim = mean_ssim(image, reference, peak);
  return e;
}

}  // namespace rtmini
