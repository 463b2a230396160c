#include <gtest/gtest.h>

#include <cmath>

#include "rtmini/geometry/aabb.hpp"
#include "rtmini/geometry/offset.hpp"
#include "rtmini/geometry/triangle.hpp"
#include "rtmini/scene/primitives.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

bool hit(const Vec3& o, const Vec3& d, const Triangle& t, Real& tt) {
  Real u, v;
  return intersect_triangle(WatertightRay(o, d), t.a, t.b, t.c, 0, Real(1e30), tt, u, v);
}

TEST(Triangle, HitsBothWindingsAndReportsBarycentrics) {
  const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Real tt, u, v;
  ASSERT_TRUE(intersect_triangle(WatertightRay({Real(0.25), Real(0.5), 2}, {0, 0, -1}), t.a, t.b,
                                 t.c, 0, 10, tt, u, v));
  EXPECT_FLOAT_EQ(tt, 2);
  EXPECT_FLOAT_EQ(u, Real(0.25));
  EXPECT_FLOAT_EQ(v, Real(0.5));
  ASSERT_TRUE(hit({Real(0.25), Real(0.25), -3}, {0, 0, 1}, t, tt));
  EXPECT_FLOAT_EQ(tt, 3);
  EXPECT_FALSE(hit({Real(0.75), Real(0.75), 2}, {0, 0, -1}, t, tt));
  EXPECT_FALSE(hit({Real(0.25), Real(0.25), 2}, {0, 0, 1}, t, tt)) << "behind the origin";
}

TEST(Triangle, SharedEdgeIsHitByExactlyOneOrBothNeverNeither) {
  // Two triangles sharing the diagonal of a square; rays through points on the diagonal.
  const Triangle t0{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, t1{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  int misses = 0;
  for (int i = 1; i < 1000; ++i) {
    const Real s = Real(0.1) + Real(0.8) * Real(i) / 1000;  // stay inside the square
    const Vec3 o(s, s, Real(0.7));
    const Vec3 d = normalize(Vec3(Real(0.001) * (i % 7), Real(-0.0007) * (i % 5), -1));
    Real a, b;
    if (!hit(o, d, t0, a) && !hit(o, d, t1, b)) ++misses;
  }
  EXPECT_EQ(misses, 0);
}

TEST(Triangle, DegenerateTrianglesAreMissedWithoutNaN) {
  const Triangle line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, point{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  Real tt;
  EXPECT_FALSE(hit({1, 0, 1}, {0, 0, -1}, line, tt));
  EXPECT_FALSE(hit({1, 1, 2}, {0, 0, -1}, point, tt));
}

TEST(Aabb, SlabTestIsConservativeForAxisParallelRaysOnTheBoundary) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  Real tn;
  // Ray lying in the x = 0 face plane, parallel to it: counts as hitting.
  EXPECT_TRUE(slab_test(RaySlab({0, Real(0.5), -1}, {0, 0, 1}), lo, hi, 0, 10, tn));
  EXPECT_FALSE(slab_test(RaySlab({-1, Real(0.5), -1}, {0, 0, 1}), lo, hi, 0, 10, tn));
  EXPECT_TRUE(slab_test(RaySlab({Real(0.5), Real(0.5), -1}, {0, 0, 1}), lo, hi, 0, 10, tn));
  EXPECT_FLOAT_EQ(tn, 1);
  EXPECT_FALSE(slab_test(RaySlab({Real(0.5), Real(0.5), -1}, {0, 0, 1}), lo, hi, 0, Real(0.5), tn));
}

TEST(Offset, ScalesWithTheCoordinateBoundAndLeavesTheSurface) {
  for (double mag : {1e-10, 1e-6, 1e-2, 1.0, 1e3, 1e5, 1e6, 1e10}) {
    const Vec3 p(Real(mag), Real(-mag), Real(0.5 * mag));
    const Vec3 n = normalize(Vec3(1, 1, 1));
    const Vec3 q = offset_ray_origin(p, n, Real(2 * mag));
    const Vec3 d = q - p;
    EXPECT_GT(dot(d, n), 0) << mag;
    // gamma(32) 2 mag along n, plus one ulp per component.
    EXPECT_LT(length(d), Real(4) * offset_distance(Real(2 * mag))) << mag;
  }
  // A point at the origin of a scene of size 1e-6 moves by a distance of that size's order,
  // not by an absolute step.
  const Vec3 q = offset_ray_origin(Vec3(0), Vec3(0, 0, 1), Real(1e-6));
  EXPECT_GT(q.z, Real(0));
  EXPECT_LT(q.z, Real(1e-11));
}

TEST(Primitives, BoxAndIcosphereFaceOutward) {
  Mesh m;
  append_box(m, {-1, -1, -1}, {1, 1, 1}, -1, 0);
  append_icosphere(m, {5, 0, 0}, 1, 2, -1, 1);
  for (const Face& f : m.faces) {
    const Vec3d c = f.object == 0 ? Vec3d(0, 0, 0) : Vec3d(5, 0, 0);
    const Vec3d a = m.positions[f.v[0]], b = m.positions[f.v[1]], cc = m.positions[f.v[2]];
    EXPECT_GT(dot(cross(b - a, cc - a), a - c), 0);
  }
}

}  // namespace
}  // namespace rtmini::test
