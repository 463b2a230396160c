#pragma once
// Error of an image against a reference (the speed/accuracy measurements, issue 7):
// RMSE and relative MSE on linear RGB, PSNR against the reference's peak, and the
// structural similarity index (Wang, Bovik, Sheikh, Simoncelli 2004) on luminance.
#include <string>

#include "rtmini/io/image.hpp"

namespace rtmini {

struct ImageErrors {
  double rmse = 0;     // sqrt(mean over pixels and RGB of (a - b)^2)
  double rel_mse = 0;  // mean of (a - b)^2 / (b^2 + 1e-2), Rousselle et al.'s relative MSE
  double psnr = 0;  // 10 log10(peak^2 / MSE), peak = max(1, largest reference value); +inf if equal
  double ssim = 1;  // mean SSIM of luminance over 8x8 windows (stride 4), 1 = identical
};

// Compares the first three channels of `image` with those of `reference`. A size or
// channel mismatch is an InputError naming `what` (e.g. the reference's path).
ImageErrors compare_images(const Image& image, const Image& reference, const std::string& what);

}  // namespace rtmini
