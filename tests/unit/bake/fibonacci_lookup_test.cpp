// The viewpoint lookups (heap KD-tree, inverse spherical Fibonacci, cube-map grid) against
// exhaustive search.
#include "rtmini/sampling/fibonacci_lookup.hpp"

#include <gtest/gtest.h>

#include <array>
#include <utility>
#include <vector>

#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/sampling/sphere_grid.hpp"

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

// Queries whose nearest viewpoint differs from exhaustive search (KD-tree, inverse mapping,
// grid).
std::array<int, 3> nearest_mismatches(int n) {
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  const auto grid = build_fibonacci_grid<Mem>(n);
  int kd_wrong = 0, sf_wrong = 0, grid_wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::lookup_nearest", Kokkos::RangePolicy<Exec>(0, kDirections),
      KOKKOS_LAMBDA(int i, int& kw, int& sw, int& gw) {
        const Vec3 q = random_direction(i);
        const int ref = exact_nearest(pts, q);
        kw += kd.nearest(q) != ref ? 1 : 0;
        sw += sf.nearest(q) != ref ? 1 : 0;
        gw += grid.nearest(q) != ref ? 1 : 0;
      },
      kd_wrong, sf_wrong, grid_wrong);
  return {kd_wrong, sf_wrong, grid_wrong};
}

TEST_P(FibonacciLookup, NearestMatchesExhaustiveSearch) {
  const int n = GetParam();
  const auto wrong = nearest_mismatches(n);
  EXPECT_EQ(wrong[0], 0) << "N = " << n;
  EXPECT_EQ(wrong[1], 0) << "N = " << n;
  EXPECT_EQ(wrong[2], 0) << "grid, N = " << n;
}

INSTANTIATE_TEST_SUITE_P(ViewpointCounts, FibonacciLookup,
                         ::testing::Values(1, 2, 10, 100, 1000, 100000));

// Queries whose cap neighbours (indices and weights) differ from exhaustive search, for the
// KD-tree, the inverse mapping and the grid. A free function: nvcc cannot compile a device
// lambda inside a gtest TEST body (a private member).
std::array<int, 3> neighbor_mismatches(int n) {
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  const auto grid = build_fibonacci_grid<Mem>(n);
  const Real r = fibonacci_radius(n);
  int kd_wrong = 0, sf_wrong = 0, grid_wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::lookup_neighbors", Kokkos::RangePolicy<Exec>(0, 20000),
      KOKKOS_LAMBDA(int i, int& kw, int& sw, int& gw) {
        const Vec3 q = random_direction(i);
        const ViewNeighbors ref = brute_force_neighbors(pts, q, r);
        kw += same_neighbors(kd.neighbors(q, r), ref) ? 0 : 1;
        sw += same_neighbors(sf.neighbors(q, r), ref) ? 0 : 1;
        gw += same_neighbors(grid.neighbors(q, r), ref) ? 0 : 1;
      },
      kd_wrong, sf_wrong, grid_wrong);
  return {kd_wrong, sf_wrong, grid_wrong};
}

// The cap query returns the same neighbours and weights as exhaustive search.
TEST(FibonacciLookupNeighbors, MatchBruteForce) {
  for (int n : {1, 7, 20, 100, 1000, 20000}) {
    const auto wrong = neighbor_mismatches(n);
    EXPECT_EQ(wrong[0], 0) << "N = " << n;
    EXPECT_EQ(wrong[1], 0) << "N = " << n;
    EXPECT_EQ(wrong[2], 0) << "grid, N = " << n;
  }
}

// Grid answers (nearest, and the cap at radius r and at 2r, above the built radius) against
// the KD-tree's over the same points, for each query; the KD-tree is exact for any query.
int grid_mismatches(const std::vector<Vec3>& points, Real r, const std::vector<Vec3>& queries) {
  const auto grid = build_point_grid<Mem>(points, r);
  const auto kd = build_point_kdtree<Mem>(points);
  const auto q = compat::upload<Mem>("rtmini::test::grid_queries", queries);
  int wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::grid_vs_kdtree", Kokkos::RangePolicy<Exec>(0, static_cast<int>(q.extent(0))),
      KOKKOS_LAMBDA(int i, int& w) {
        const bool ok = grid.nearest(q(i)) == kd.nearest(q(i)) &&
                        same_neighbors(grid.neighbors(q(i), r), kd.neighbors(q(i), r)) &&
                        same_neighbors(grid.neighbors(q(i), 2 * r), kd.neighbors(q(i), 2 * r));
        w += ok ? 0 : 1;
      },
      wrong);
  return wrong;
}

// Queries where a cube map is most likely to go wrong: cube corners, edges and face centres
// (ties between faces), points of the set themselves, and slightly off-unit and zero-length
// directions (the last two scan every point). NaN is left out: the tests trap invalid
// operations, and the tree's own comparisons would trap first.
std::vector<Vec3> awkward_queries(const std::vector<Vec3>& points) {
  std::vector<Vec3> q;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) q.push_back(normalize(Vec3(Real(x), Real(y), Real(z))));
  for (std::size_t i = 0; i < points.size(); i += 1 + points.size() / 200) q.push_back(points[i]);
  const std::size_t unit = q.size();
  for (std::size_t i = 0; i < unit; ++i) {
    q.push_back(q[i] * Real(1.00003));
    q.push_back(q[i] * Real(1.5));
  }
  q.push_back(Vec3(Real(0)));
  for (int i = 0; i < 2000; ++i) q.push_back(random_direction(i));
  return q;
}

// The grid on point sets other than a Fibonacci sphere: uniform random points at several
// densities and caps, a cluster around one pole (most cells far from every point: they list
// the whole set), and a set of three points.
TEST(SphereGridLookup, MatchesTheKdTreeOnAnyPointSet) {
  for (int n : {3, 50, 400, 2000}) {
    std::vector<Vec3> pts(n), cluster(n);
    for (int i = 0; i < n; ++i) {
      const Rng rng(77u, static_cast<std::uint64_t>(i), 0u);
      pts[i] = uniform_sphere(Real(rng.uniform(0)), Real(rng.uniform(1)));
      cluster[i] = normalize(Vec3(pts[i].x * Real(0.1), pts[i].y * Real(0.1), Real(1)));
    }
    for (Real r : {Real(0.05), fibonacci_radius(n), Real(1.5)}) {
      EXPECT_EQ(grid_mismatches(pts, r, awkward_queries(pts)), 0) << "N = " << n << ", r = " << r;
      EXPECT_EQ(grid_mismatches(cluster, r, awkward_queries(cluster)), 0)
          << "cluster, N = " << n << ", r = " << r;
    }
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
