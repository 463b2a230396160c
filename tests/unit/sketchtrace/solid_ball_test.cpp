// The solid ball of a generated sphere (render_scene.hpp) decides shadow segments without a
// traversal: every segment that enters it must be one the BVH finds blocked.
#include <gtest/gtest.h>

#include <cmath>

#include "device_scene.hpp"
#include "light_sampling.hpp"
#include "rtmini/sampling/rng.hpp"

namespace rtmini::sketch::test {
namespace {

struct BallCounts {
  long long entered = 0;  // segments the ball test calls blocked
  long long missed = 0;   // of those, segments the BVH finds unblocked (must be 0)
};

BallCounts check_sphere(int level, int segments) {
  HostScene scene;
  const Vec3d center(1.3, -0.4, 2.1);
  const double radius = 0.7;
  add_sphere(scene, center, radius, level, Material{}, "sphere");
  EXPECT_EQ(scene.solid_balls.size(), 1u);
  const DeviceScene d = upload_scene(scene, bvh::BuildQuality::kSah, 0.5);
  const SolidBall ball = scene.solid_balls[0];
  const auto accel = d.mesh.accel;
  const Vec3 c(center);
  const Real R = Real(radius);
  long long entered = 0, missed = 0;
  Kokkos::parallel_reduce(
      "rtmini::test::solid_ball", Kokkos::RangePolicy<>(0, segments),
      KOKKOS_LAMBDA(int i, long long& e, long long& m) {
        const Rng rng(7, std::uint64_t(i), 0);
        Vec3 end[2];
        for (int k = 0; k < 2; ++k) {
          float a, b, s, unused;
          rng.uniform2(2 * k, a, b);
          rng.uniform2(2 * k + 1, s, unused);
          const Real z = 1 - 2 * Real(a), phi = 2 * Real(math::kPi) * Real(b);
          const Real rho = math::sqrt(math::fmax(Real(0), 1 - z * z));
          // Endpoints from inside the sphere (0.5 R) to 3 R away from its centre: segments
          // that start or end inside must not be called blocked by the ball.
          end[k] = c + Vec3(rho * math::cos(phi), rho * math::sin(phi), z) *
                           (R * (Real(0.5) + Real(2.5) * s));
        }
        Ray r;
        r.org = end[0];
        const Vec3 dv = end[1] - end[0];
        const Real len = length(dv);
        if (!(len > Real(0))) return;
        r.dir = dv / len;
        r.tmin = 0;
        r.tmax = len;
        if (!segment_blocked_by_ball(r, ball)) return;
        ++e;
        if (!bvh::any_hit(accel, r)) ++m;
      },
      entered, missed);
  EXPECT_GT(ball.inner, Real(radius * (level >= 2 ? 0.98 : 0.7)));
  EXPECT_LT(ball.inner, Real(radius));
  EXPECT_GE(ball.outer, Real(radius));
  return {entered, missed};
}

TEST(SketchSolidBall, EverySegmentThroughTheBallIsBlockedByTheTriangles) {
  for (int level : {0, 1, 3, 5}) {
    const BallCounts n = check_sphere(level, 200000);
    EXPECT_GT(n.entered, 20000) << "level " << level;  // the test exercises the shortcut
    EXPECT_EQ(n.missed, 0) << "level " << level;
  }
}

TEST(SketchSolidBall, SegmentTestHonoursBothEnds) {
  const SolidBall b{Vec3(0), Real(1), Real(1.05)};
  Ray r;
  r.org = Vec3(-3, 0, 0);
  r.dir = Vec3(1, 0, 0);
  r.tmin = 0;
  r.tmax = 1.9f;  // stops short of the ball (enters at t = 2)
  EXPECT_FALSE(segment_blocked_by_ball(r, b));
  r.tmax = 10;  // through it, both ends outside
  EXPECT_TRUE(segment_blocked_by_ball(r, b));
  r.tmin = 4.1f;  // starts past the ball (leaves at t = 4)
  r.tmax = 10;
  EXPECT_FALSE(segment_blocked_by_ball(r, b));
  r.org = Vec3(-3, 1.01f, 0);  // passes above it
  r.tmin = 0;
  EXPECT_FALSE(segment_blocked_by_ball(r, b));
  r.org = Vec3(-3, 0, 0);  // ends inside the outer sphere (t = 2.99 is 0.01 from the centre)
  r.tmax = 2.99f;
  EXPECT_FALSE(segment_blocked_by_ball(r, b));
  r.org = Vec3(-1.04f, 0, 0);  // starts inside the outer sphere
  r.tmax = 10;
  EXPECT_FALSE(segment_blocked_by_ball(r, b));
  r.org = Vec3(-1.06f, 0, 0);  // starts just outside it
  EXPECT_TRUE(segment_blocked_by_ball(r, b));
}

}  // namespace
}  // namespace rtmini::sketch::test
