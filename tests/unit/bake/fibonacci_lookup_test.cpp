// Both viewpoint lookups (heap KD-tree, inverse spherical Fibonacci) against exhaustive search.
#include "rtmini/sampling/fibonacci_lookup.hpp"

#include <gtest/gtest.h>

#include <utility>

#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Mem = Exec::memory_space;
constexpr int kDirections = 100000;

KOKKOS_INLINE_FUNCTION Vec3 random_direction(int i) {
  const Rng rng(20240607u, static_cast<std::uint64_t>(i), 0u);
  return uniform_sphere(Real(rng.uniform(0)), Real(rng.uniform(1)));
}

// Exhaustive nearest (ties -> lower index). For large N it scans outward from the query's
// z-position (the Fibonacci index is monotone in z) and stops once |dz| exceeds the best
// distance: still exact, but O(sqrt N) instead of O(N) per query.
KOKKOS_INLINE_FUNCTION int exact_nearest(const Kokkos::View<Vec3*, Mem>& pts, const Vec3& q) {
  const int n = static_cast<int>(pts.extent(0));
  if (n <= 2000) return brute_force_nearest(pts, q);
  int start = static_cast<int>((1.0 - double(q.z)) * 0.5 * n);
  start = start < 0 ? 0 : (start >= n ? n - 1 : start);
  int best = start;
  Real best_d2 = length_squared(pts(start) - q);
  for (int dir = -1; dir <= 1; dir += 2) {
    for (int i = start + dir; i >= 0 && i < n; i += dir) {
      const Real dz = pts(i).z - q.z;
      if (dz * dz > best_d2 * Real(1.0001) + Real(1e-12)) break;
      const Real d2 = length_squared(pts(i) - q);
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = i;
      }
    }
  }
  return best;
}

class FibonacciLookup : public ::testing::TestWithParam<int> {};

// Queries whose nearest viewpoint differs from exhaustive search (KD-tree, inverse mapping).
std::pair<int, int> nearest_mismatches(int n) {
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  int kd_wrong = 0, sf_wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::lookup_nearest", Kokkos::RangePolicy<Exec>(0, kDirections),
      KOKKOS_LAMBDA(int i, int& kw, int& sw) {
        const Vec3 q = random_direction(i);
        const int ref = exact_nearest(pts, q);
        kw += kd.nearest(q) != ref ? 1 : 0;
        sw += sf.nearest(q) != ref ? 1 : 0;
      },
      kd_wrong, sf_wrong);
  return {kd_wrong, sf_wrong};
}

TEST_P(FibonacciLookup, NearestMatchesExhaustiveSearch) {
  const int n = GetParam();
  const auto wrong = nearest_mismatches(n);
  EXPECT_EQ(wrong.first, 0) << "N = " << n;
  EXPECT_EQ(wrong.second, 0) << "N = " << n;
}

INSTANTIATE_TEST_SUITE_P(ViewpointCounts, FibonacciLookup,
                         ::testing::Values(1, 2, 10, 100, 1000, 100000));

// Queries whose cap neighbours (indices and weights) differ from exhaustive search,
// for the KD-tree (first) and the inverse mapping (second). A free function: nvcc
// cannot compile a device lambda inside a gtest TEST body (a private member).
std::pair<int, int> neighbor_mismatches(int n) {
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  const Real r = fibonacci_radius(n);
  int kd_wrong = 0, sf_wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::lookup_neighbors", Kokkos::RangePolicy<Exec>(0, 20000),
      KOKKOS_LAMBDA(int i, int& kw, int& sw) {
        const Vec3 q = random_direction(i);
        const ViewNeighbors ref = brute_force_neighbors(pts, q, r);
        const ViewNeighbors a = kd.neighbors(q, r), b = sf.neighbors(q, r);
        bool ka = a.count == ref.count, kb = b.count == ref.count;
        for (int k = 0; k < ref.count; ++k) {
          ka = ka && a.index[k] == ref.index[k] && a.weight[k] == ref.weight[k];
          kb = kb && b.index[k] == ref.index[k] && b.weight[k] == ref.weight[k];
        }
        kw += ka ? 0 : 1;
        sw += kb ? 0 : 1;
      },
      kd_wrong, sf_wrong);
  return {kd_wrong, sf_wrong};
}

// The cap query returns the same neighbours and weights as exhaustive search.
TEST(FibonacciLookupNeighbors, MatchBruteForce) {
  for (int n : {1, 7, 20, 100, 1000, 20000}) {
    const auto wrong = neighbor_mismatches(n);
    EXPECT_EQ(wrong.first, 0) << "N = " << n;
    EXPECT_EQ(wrong.second, 0) << "N = " << n;
  }
}

// Mean neighbour count in the cap over 10000 random queries, and the worst deviation of
// a query's weight sum from one.
std::pair<double, double> cap_statistics(int n) {
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const Real r = fibonacci_radius(n);
  double mean = 0;
  double worst_sum = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::lookup_count", Kokkos::RangePolicy<Exec>(0, 10000),
      KOKKOS_LAMBDA(int i, double& m, double& ws) {
        const ViewNeighbors nb = kd.neighbors(random_direction(i), r);
        Real s = 0;
        for (int k = 0; k < nb.count; ++k) s += nb.weight[k];
        m += nb.count;
        const double e = math::fabs(double(s) - 1.0);
        ws = e > ws ? e : ws;
      },
      mean, Kokkos::Max<double>(worst_sum));
  return {mean / 10000, worst_sum};
}

// About 8 neighbours in the cap (the seed's "8 plus or minus 2"), weights summing to one.
TEST(FibonacciLookupNeighbors, SeedRadiusHoldsAboutEightPoints) {
  const auto stats = cap_statistics(1000);
  EXPECT_GT(stats.first, 6.0);
  EXPECT_LT(stats.first, 10.0);
  EXPECT_LT(stats.second, 1e-5);
}

}  // namespace
}  // namespace rtmini
