// Hemisphere viewpoint lookups (rtmini/sampling/fibonacci_hemisphere.hpp): the two-query lookup
// with either sphere lookup and the one-query mirrored KD-tree find exactly the neighbours of
// an exhaustive search over the stored half and its mirror images; the frame is orthonormal.
#include "rtmini/sampling/fibonacci_hemisphere.hpp"

#include <gtest/gtest.h>

#include <array>

#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Mem = Exec::memory_space;
constexpr int kQueries = 10000;

// A random direction folded to the front (z >= 0), as HemisphereMap::neighbors folds it.
KOKKOS_INLINE_FUNCTION Vec3 random_front(int i) {
  const Rng rng(20261124u, static_cast<std::uint64_t>(i), 0u);
  Vec3 q = uniform_sphere(Real(rng.uniform(0)), Real(rng.uniform(1)));
  q.z = math::fabs(q.z);
  return q;
}

// Exhaustive: every stored point i < m within the cap of q, and every one whose mirror image is.
KOKKOS_INLINE_FUNCTION ViewNeighbors exhaustive(const Kokkos::View<Vec3*, Mem>& pts, int m,
                                                const Vec3& q, Real radius) {
  detail::NeighborCollector c;
  const Vec3 below(q.x, q.y, -q.z);
  int nearest = 0;
  Real best = Real(1e30);
  for (int i = 0; i < m; ++i) {
    const Real a = length_squared(pts(i) - q), b = length_squared(pts(i) - below);
    if (a <= radius * radius) c.add(i, a);
    if (b <= radius * radius) c.add(i, b);
    if (math::fmin(a, b) < best) {
      best = math::fmin(a, b);
      nearest = i;
    }
  }
  return detail::finish_neighbors(c, radius, nearest);
}

// Mismatches against the exhaustive search: KD-tree, inverse mapping, mirrored tree, grid,
// mirrored grid.
std::array<int, 5> hemisphere_mismatches(int n) {
  const int m = hemisphere_viewpoints(n);
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  const auto mirrored = build_mirrored_kdtree<Mem>(n);
  const auto grid = build_fibonacci_grid<Mem>(n);
  const auto mirrored_grid = build_mirrored_grid<Mem>(n);
  const Real r = fibonacci_radius(n);
  int kd_wrong = 0, sf_wrong = 0, mirrored_wrong = 0, grid_wrong = 0, mirrored_grid_wrong = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::hemisphere_neighbors", Kokkos::RangePolicy<Exec>(0, kQueries),
      KOKKOS_LAMBDA(int i, int& kw, int& sw, int& mw, int& gw, int& mgw) {
        const Vec3 q = random_front(i);
        const ViewNeighbors ref = exhaustive(pts, m, q, r);
        kw += same_neighbors(hemisphere_neighbors(kd, pts, q, r, m), ref) ? 0 : 1;
        sw += same_neighbors(hemisphere_neighbors(sf, pts, q, r, m), ref) ? 0 : 1;
        mw += same_neighbors(mirrored_neighbors(mirrored, q, r, m), ref) ? 0 : 1;
        gw += same_neighbors(hemisphere_neighbors(grid, pts, q, r, m), ref) ? 0 : 1;
        mgw += same_neighbors(mirrored_neighbors(mirrored_grid, q, r, m), ref) ? 0 : 1;
      },
      kd_wrong, sf_wrong, mirrored_wrong, grid_wrong, mirrored_grid_wrong);
  return {kd_wrong, sf_wrong, mirrored_wrong, grid_wrong, mirrored_grid_wrong};
}

TEST(FibonacciHemisphere, LookupsMatchExhaustiveSearchOverStoredHalfAndImages) {
  for (int n : {8, 40, 100, 1000, 4000}) {
    const auto wrong = hemisphere_mismatches(n);
    EXPECT_EQ(wrong[0], 0) << "KD-tree, N = " << n;
    EXPECT_EQ(wrong[1], 0) << "inverse mapping, N = " << n;
    EXPECT_EQ(wrong[2], 0) << "mirrored KD-tree, N = " << n;
    EXPECT_EQ(wrong[3], 0) << "grid, N = " << n;
    EXPECT_EQ(wrong[4], 0) << "mirrored grid, N = " << n;
  }
}

// The stored half is exactly the front: z > 0 for the first N/2 points of an even N.
TEST(FibonacciHemisphere, StoredHalfIsTheFront) {
  for (int n : {2, 40, 1000}) {
    const int m = hemisphere_viewpoints(n);
    EXPECT_GT(fibonacci_point(m - 1, n).z, Real(0)) << n;
    EXPECT_LT(fibonacci_point(m, n).z, Real(0)) << n;
  }
}

// view_frame: orthonormal, z the given front, for fronts all over the sphere (both branches).
TEST(FibonacciHemisphere, FrameIsOrthonormal) {
  double worst = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 f = fibonacci_point(i, 2000);
    const ViewFrame b = view_frame(f);
    for (double e : {double(dot(b.x, b.y)), double(dot(b.x, b.z)), double(dot(b.y, b.z)),
                     double(dot(b.x, b.x)) - 1, double(dot(b.y, b.y)) - 1, double(length(b.z - f))})
      worst = std::max(worst, std::abs(e));
    const Vec3 local = b.to_local(b.to_world(Vec3(Real(0.3), Real(-0.4), Real(0.866))));
    worst = std::max(worst, double(length(local - Vec3(Real(0.3), Real(-0.4), Real(0.866)))));
  }
  EXPECT_LT(worst, 1e-5);
}

}  // namespace
}  // namespace rtmini
