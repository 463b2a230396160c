// The counter-based generator: uniform, independent across keys, and the same
// numbers whatever the thread count or execution order.
#include "rtmini/sampling/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rtmini/report/hash.hpp"
#include "rtmini/sampling/fibonacci.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

std::uint64_t draw_hash(int n, int chunk) {
  // Draws computed chunk by chunk in reverse order must equal one pass.
  std::uint64_t total = 0;
  for (int begin = ((n - 1) / chunk) * chunk; begin >= 0; begin -= chunk) {
    std::uint64_t h = 0;
    const int end = std::min(n, begin + chunk);
    Kokkos::parallel_reduce(
        "test::rng_hash", Kokkos::RangePolicy<TestExecSpace>(begin, end),
        KOKKOS_LAMBDA(int i, std::uint64_t& acc) {
          const Rng rng(42, std::uint64_t(i), std::uint32_t(i % 17));
          const float x = rng.uniform(5);
          acc += hash_term(std::uint64_t(i), compat::bit_cast<std::uint32_t>(x));
        },
        h);
    total += h;
  }
  return total;
}

TEST(Rng, IndependentOfPartitioningAndBackend) {
  const std::uint64_t one_pass = draw_hash(1 << 18, 1 << 18);
  EXPECT_EQ(one_pass, draw_hash(1 << 18, 1000));
  EXPECT_EQ(one_pass, draw_hash(1 << 18, 7));
  // The host serial reference.
  std::uint64_t serial = 0;
  for (int i = 0; i < (1 << 18); ++i) {
    const Rng rng(42, std::uint64_t(i), std::uint32_t(i % 17));
    serial += hash_term(std::uint64_t(i), compat::bit_cast<std::uint32_t>(rng.uniform(5)));
  }
  EXPECT_EQ(one_pass, serial);
}

TEST(Rng, UniformAndUncorrelated) {
  // Chi-square over 64 bins, and correlation between neighbouring items and dimensions.
  const int n = 1 << 20, bins = 64;
  std::vector<int> count(bins, 0);
  double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sdd = 0;
  for (int i = 0; i < n; ++i) {
    const float x = Rng(7, std::uint64_t(i), 0).uniform(0);
    const float y = Rng(7, std::uint64_t(i + 1), 0).uniform(0);
    const float z = Rng(7, std::uint64_t(i), 0).uniform(1);
    ASSERT_GE(x, 0.f);
    ASSERT_LT(x, 1.f);
    ++count[int(x * bins)];
    sx += x;
    sy += y;
    sxx += x * x;
    syy += y * y;
    sxy += x * y;
    sdd += (x - 0.5) * (z - 0.5);
  }
  double chi2 = 0;
  for (int c : count) chi2 += (c - n / double(bins)) * (c - n / double(bins)) / (n / double(bins));
  EXPECT_LT(chi2, 120.0) << "63 degrees of freedom; 120 is p < 1e-5";
  const double cov = sxy / n - (sx / n) * (sy / n);
  const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
  EXPECT_LT(std::fabs(corr), 0.005);
  EXPECT_LT(std::fabs(sdd / n / (1.0 / 12)), 0.005);
}

TEST(Sampling, CosineHemisphereMeanCosineIsTwoThirds) {
  double sum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    float a, b;
    Rng(1, std::uint64_t(i), 0).uniform2(0, a, b);
    const Vec3 d = cosine_hemisphere(a, b);
    ASSERT_NEAR(double(length(d)), 1.0, 1e-5);
    sum += d.z;
  }
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 0.003);
}

TEST(Sampling, FibonacciPointsAreUnitAndEvenlySpread) {
  const int n = 1000;
  double cz = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = fibonacci_point(i, n);
    EXPECT_NEAR(double(length(p)), 1.0, 1e-5);
    cz += p.z;
  }
  EXPECT_NEAR(cz / n, 0.0, 1e-6);
}

}  // namespace
}  // namespace rtmini::test
