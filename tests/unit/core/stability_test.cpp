// Numerical extremes (issue "speed versus accuracy", stability): no
// self-intersection acne on an open plane with nothing above it and no leaks
// through shared edges, for scenes scaled by 1e-6 .. 1e6 and moved 1e5 away
// from the origin, including grazing rays.
#include <gtest/gtest.h>

#include <cmath>

#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/geometry/offset.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "rtmini/scene/primitives.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

// Fraction of rays leaving a tessellated plane (upwards, from scale-aware offset
// origins) that wrongly hit the plane itself. grazing: cos(theta) ~ 1e-3.
double acne_fraction(double scale, double offset, bool grazing, long long n) {
  Mesh m;
  const Vec3d corner(offset - scale, offset - 0.5 * scale, offset - scale);
  // A tilted plane: its vertices are not axis-aligned, so rounding is exercised.
  const Vec3d u = Vec3d(2, 0.3, 0.1) * scale, v = Vec3d(-0.2, 0.1, 2) * scale;
  append_grid(m, corner, u, v, 32, 32, -1, 0);
  // Recentred as the apps do (geometry/offset.hpp).
  const auto dm = upload_mesh<TestExecSpace>(m, bvh::BuildQuality::kSah, TestExecSpace(),
                                             bounds_of(m.positions).centre());
  const Real bound = dm.coordinate_bound;
  const auto accel = dm.accel;
  const auto tris = dm.tris;
  const int nt = static_cast<int>(tris.extent(0));
  const Vec3 normal(normalize(cross(u, v)));
  long long bad = 0;
  Kokkos::parallel_reduce(
      "test::acne", Kokkos::RangePolicy<TestExecSpace>(0, n),
      KOKKOS_LAMBDA(long long i, long long& b) {
        const Rng rng(5, std::uint64_t(i), 0);
        const auto r = rng.block(0);
        const Triangle t = tris(int(r.v[0] % std::uint32_t(nt)));
        Real bu, bv;
        uniform_triangle(Rng::to_unit(r.v[1]), Rng::to_unit(r.v[2]), bu, bv);
        const Vec3 p = barycentric_point(t.a, t.b, t.c, bu, bv);
        Ray ray;
        ray.org = offset_ray_origin(p, normal, bound);
        const Frame f(normal);
        Vec3 local = cosine_hemisphere(Rng::to_unit(r.v[3]), Rng::to_unit(rng.block(1).v[0]));
        if (grazing) local = normalize(Vec3(local.x, local.y, Real(1e-3) * (Real(0.5) + local.z)));
        ray.dir = f.to_world(local);
        ray.tmin = 0;
        ray.tmax = Real(1e30);
        if (bvh::any_hit(accel, ray)) ++b;
      },
      bad);
  return double(bad) / double(n);
}

class Stability : public ::testing::TestWithParam<Placement> {};

TEST_P(Stability, NoAcneOnAnOpenPlane) {
  const Placement p = GetParam();
  EXPECT_LT(acne_fraction(p.scale, p.offset, false, 400000), 1e-5)
      << "scale " << p.scale << " offset " << p.offset;
  EXPECT_LT(acne_fraction(p.scale, p.offset, true, 400000), 1e-5)
      << "grazing, scale " << p.scale << " offset " << p.offset;
}

TEST_P(Stability, NoLeaksThroughSharedEdges) {
  const Placement p = GetParam();
  Mesh m;
  const Vec3d c(p.offset, -0.5 * p.offset, 0.25 * p.offset);
  append_icosphere(m, c, p.scale, 4, -1, 0);
  const Vec3d origin = bounds_of(m.positions).centre();
  const auto dm = upload_mesh<TestExecSpace>(m, bvh::BuildQuality::kLbvh, TestExecSpace(), origin);
  const auto accel = dm.accel;
  const auto tris = dm.tris;
  const int nt = static_cast<int>(tris.extent(0));
  const Vec3 inside(c - origin + Vec3d(0.2, -0.1, 0.05) * p.scale);
  long long escapes = 0;
  Kokkos::parallel_reduce(
      "test::leaks", Kokkos::RangePolicy<TestExecSpace>(0, 300000),
      KOKKOS_LAMBDA(long long i, long long& e) {
        const Rng rng(8, std::uint64_t(i), 0);
        const auto r = rng.block(0);
        const Triangle t = tris(int(r.v[0] % std::uint32_t(nt)));
        const Vec3 target = (i % 2 == 0) ? t.a : t.a + (t.b - t.a) * Real(Rng::to_unit(r.v[1]));
        Ray ray;
        ray.org = inside;
        ray.dir = normalize(target - inside);
        if (!bvh::closest_hit(accel, ray).valid()) ++e;
      },
      escapes);
  EXPECT_EQ(escapes, 0) << "scale " << p.scale << " offset " << p.offset;
}

// Scaled at the origin from 1e-6 to 1e6, and moved 1e5 and 1e9 away at unit and 1e3 scale
// (recentring makes the distance free).
INSTANTIATE_TEST_SUITE_P(Extremes, Stability,
                         ::testing::Values(Placement{"micro", 1e-6, 0}, Placement{"milli", 1e-3, 0},
                                           Placement{"unit", 1, 0}, Placement{"kilo", 1e3, 0},
                                           Placement{"mega", 1e6, 0}, Placement{"far", 1, 1e5},
                                           Placement{"far-kilo", 1e3, 1e5},
                                           Placement{"very-far", 1, 1e9}));

}  // namespace
}  // namespace rtmini::test
