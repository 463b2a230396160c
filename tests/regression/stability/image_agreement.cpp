// rtmini-image-agreement IMAGE REFERENCE [MAX_MEAN MAX_FRACTION]: does a render of a moved or
// rescaled scene agree with the render of the original (extremes_checks.sh)? Prints the relative
// difference of the mean and the fraction of pixels whose luminance differs by more than 10 %
// (a pixel darker than 2 % of the reference mean is compared with 10 % of that floor: 8-bit
// quantisation and black pixels give no relative error). Exit 0 within MAX_MEAN (default 0.005)
// and MAX_FRACTION (default 0.01), 1 outside, 2 on bad input.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"

namespace {

double luminance(const rtmini::Image& im, int x, int y) {
  return 0.2126 * im.at(x, y, 0) + 0.7152 * im.at(x, y, 1) + 0.0722 * im.at(x, y, 2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 5) {
    std::fprintf(stderr, "usage: %s IMAGE REFERENCE [MAX_MEAN MAX_FRACTION]\n", argv[0]);
    return rtmini::kExitBadInput;
  }
  try {
    const rtmini::Image a = rtmini::read_image(argv[1]), b = rtmini::read_image(argv[2]);
    if (a.width != b.width || a.height != b.height)
      throw rtmini::InputError(std::string(argv[1]) + ": size differs from the reference");
    const double max_mean = argc == 5 ? std::atof(argv[3]) : 0.005;
    const double max_fraction = argc == 5 ? std::atof(argv[4]) : 0.01;
    double sum_a = 0, sum_b = 0;
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x) {
        sum_a += luminance(a, x, y);
        sum_b += luminance(b, x, y);
      }
    const double n = double(b.width) * b.height;
    const double floor = 0.02 * sum_b / n;
    long off = 0;
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x) {
        const double la = luminance(a, x, y), lb = luminance(b, x, y);
        if (!(std::fabs(la - lb) <= 0.1 * std::fmax(lb, floor))) ++off;
      }
    const double mean = sum_b > 0 ? (sum_a - sum_b) / sum_b : (sum_a == 0 ? 0 : 1);
    const double fraction = off / n;
    std::printf("mean %+.4f %%, %ld of %.0f pixels beyond 10 %% (%.3f %%)\n", 100 * mean, off, n,
                100 * fraction);
    return std::fabs(mean) <= max_mean && fraction <= max_fraction ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return rtmini::kExitBadInput;
  }
}
