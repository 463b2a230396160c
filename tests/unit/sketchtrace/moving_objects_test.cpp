// Object motion blur (moving_objects.hpp): a moving triangle is hit exactly where it is at
// the ray's time, and the two-level trace (bounding-sphere cull + per-object BVH) finds the
// same closest hits as a brute-force loop over every triangle at that time.
#include <gtest/gtest.h>

#include <cmath>

#include "motion_trace.hpp"
#include "moving_objects_host.hpp"
#include "rtmini/sampling/rng.hpp"
#include "sketch_test_util.hpp"

namespace rtmini::sketch::test {
namespace {

ObjectMotion motion_of(const Vec3d& velocity, const Vec3d& axis, double spin_deg) {
  ObjectMotion m;
  m.velocity = velocity;
  m.spin_axis = axis;
  m.spin_deg = spin_deg;
  return m;
}

// A floor at y = 0 and a horizontal 0.4 x 0.4 square at height 1 centred on (0, 1, 0) at
// t = 0, moving by `motion` over t in [0, 1].
MovingScene square_scene(const ObjectMotion& motion) {
  HostScene s;
  add_floor(s, 4.0, 0.5f);
  Material m;
  const int mat = add_scene_material(s, m);
  const int obj = add_mesh_object(s, "square");
  append_quad(s.mesh, Vec3d(-0.2, 1, 0.2), Vec3d(0.4, 0, 0), Vec3d(0, 0, -0.4), mat, obj);
  add_mover(s, obj, obj + 1, Vec3d(0, 1, 0), motion, 1);
  s.max_abs_time = 1.0;
  place_moving_objects_last(s, "test");
  return upload_scene(s, bvh::BuildQuality::kSah, 0.5);
}

// Closest hit and surface point of a vertical ray down through (x, z) at `time`.
struct DownHit {
  bool on_square = false;  // on a moving object
  Vec3 p;
};
DownHit shoot_down(const MovingScene& scene, Real x, Real z, Real time) {
  Kokkos::View<DownHit*> result("result", 1);
  const MovingScene sc = scene;
  Kokkos::parallel_for(
      "rtmini::test::shoot_down", Kokkos::RangePolicy<>(0, 1), KOKKOS_LAMBDA(int) {
        Ray r;
        r.org = Vec3(x, 3, z);
        r.dir = Vec3(0, -1, 0);
        r.time = time;
        TraceCounter c;
        const Hit h = scene_closest(sc, r, c);
        DownHit d;
        if (h.valid()) {
          const Surface s = scene_surface(sc, r, h, true);
          d.on_square = sc.motion.mover_of_object(s.object) >= 0;
          d.p = s.p;
        }
        result(0) = d;
      });
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result);
  return host(0);
}

TEST(SketchMotion, TranslatedSquareIsHitWhereItIsAtTheRaysTime) {
  const MovingScene scene = square_scene(motion_of(Vec3d(2, 0, 0), Vec3d(0, 1, 0), 0));
  ASSERT_EQ(scene.motion.count, 1);
  for (const Real t : {Real(0), Real(0.5), Real(1)}) {
    const Real cx = Real(2) * t;  // the square's centre at time t
    const DownHit centre = shoot_down(scene, cx, Real(0.05), t);
    EXPECT_TRUE(centre.on_square) << "t = " << t;
    EXPECT_NEAR(centre.p.x, cx, 1e-5) << "t = " << t;
    EXPECT_NEAR(centre.p.y, 1.0, 1e-5) << "t = " << t;
    EXPECT_NEAR(centre.p.z, 0.05, 1e-5) << "t = " << t;
    // Just inside and just outside its moving edges.
    EXPECT_TRUE(shoot_down(scene, cx + Real(0.19), 0, t).on_square) << "t = " << t;
    EXPECT_FALSE(shoot_down(scene, cx + Real(0.21), 0, t).on_square) << "t = " << t;
    EXPECT_TRUE(shoot_down(scene, cx - Real(0.19), 0, t).on_square) << "t = " << t;
    EXPECT_FALSE(shoot_down(scene, cx - Real(0.21), 0, t).on_square) << "t = " << t;
  }
}

TEST(SketchMotion, SpinningSquareTurnsAboutItsPivot) {
  // 90 degrees about y over the shutter: at t = 0.5 the square has turned by 45 degrees, so
  // its corner direction (1, 0, 1) now points along +x, reaching 0.2 * sqrt(2) from the pivot.
  const MovingScene scene = square_scene(motion_of(Vec3d(0, 0, 0), Vec3d(0, 1, 0), 90));
  const Real reach = Real(0.2 * std::sqrt(2.0));
  EXPECT_FALSE(shoot_down(scene, Real(0.25), 0, 0).on_square);  // corner at 0.2 along x
  EXPECT_TRUE(shoot_down(scene, reach - Real(0.01), 0, Real(0.5)).on_square);
  EXPECT_FALSE(shoot_down(scene, reach + Real(0.01), 0, Real(0.5)).on_square);
  EXPECT_TRUE(shoot_down(scene, Real(0.19), 0, 1).on_square);  // a quarter turn: a square again
  EXPECT_FALSE(shoot_down(scene, Real(0.21), 0, 1).on_square);
}

struct BruteForceCounts {
  long long hits = 0, mover_hits = 0, differ = 0, world_differ = 0, occl_differ = 0;
};

// `rays` random rays at random times through the two-level trace and a brute-force loop over
// all triangles. A free function: nvcc refuses device lambdas inside a gtest TEST body.
BruteForceCounts compare_with_brute_force(const MovingScene& sc, int rays) {
  BruteForceCounts counts;
  Kokkos::parallel_reduce(
      "rtmini::test::motion_brute_force", Kokkos::RangePolicy<>(0, rays),
      KOKKOS_LAMBDA(int i, long long& nh, long long& nm, long long& nd, long long& nw,
                    long long& no) {
        const Rng rng(11, std::uint64_t(i), 0);
        float a, b, c2, d2, e, f;
        rng.uniform2(0, a, b);
        rng.uniform2(1, c2, d2);
        rng.uniform2(2, e, f);
        Ray r;
        r.org = Vec3(Real(-4 + 8 * a), Real(0.05 + 3 * b), Real(-4 + 8 * c2));
        const Vec3 target(Real(-1.5 + 3 * d2), Real(0.2 + 1.6 * e), Real(-1.5 + 3 * f));
        r.dir = normalize(target - r.org);
        float t, unused;
        rng.uniform2(3, t, unused);
        r.time = Real(t);
        TraceCounter counter;
        const Hit h = scene_closest(sc, r, counter);
        // Brute force: every triangle; moving ones in object space (the trace's own test).
        Hit ref;
        ref.t = r.tmax;
        int world_prim = -1;
        Real world_t = r.tmax;
        const int n = int(sc.mesh.tris.extent(0));
        for (int k = 0; k < n; ++k) {
          const Triangle tri = sc.mesh.tris(k);
          const int mv = sc.motion.mover_of_object(sc.mesh.tri_object(k));
          Ray q = r;
          Triangle w = tri;
          if (mv >= 0) {
            const RigidPose pose = pose_at(sc.motion.objects(mv), r.time);
            q = pose.ray_to_object(r);
            w = {pose.point_to_world(tri.a), pose.point_to_world(tri.b),
                 pose.point_to_world(tri.c)};
          }
          Real tt, u, v;
          if (intersect_triangle(WatertightRay(q.org, q.dir), tri.a, tri.b, tri.c, q.tmin, ref.t,
                                 tt, u, v) &&
              (tt < ref.t || k < ref.prim || !ref.valid())) {
            ref.t = tt;
            ref.prim = k;
          }
          if (intersect_triangle(WatertightRay(r.org, r.dir), w.a, w.b, w.c, r.tmin, world_t, tt, u,
                                 v)) {
            world_t = tt;
            world_prim = k;
          }
        }
        if (h.valid()) ++nh;
        if (h.valid() && sc.motion.mover_of_object(sc.mesh.tri_object(h.prim)) >= 0) ++nm;
        if (h.prim != ref.prim || (h.valid() && h.t != ref.t)) ++nd;
        if (h.prim != world_prim) ++nw;
        // Any-hit over the whole segment agrees with "some closest hit exists".
        if (scene_occluded(sc, r, counter) != h.valid()) ++no;
      },
      counts.hits, counts.mover_hits, counts.differ, counts.world_differ, counts.occl_differ);
  return counts;
}

// Three moving spheres (translating and spinning) and a moving box over a still floor;
// random rays at random times. The trace must report exactly the hit of a brute-force loop
// over all triangles (moving ones tested in object space with the same moved ray), and the
// same triangle as moving the triangles into world space (up to rounding at edges).
TEST(SketchMotion, TwoLevelTraceMatchesBruteForce) {
  HostScene s;
  add_floor(s, 5.0, 0.5f);
  const Vec3d centres[3] = {{-1.2, 0.6, 0.2}, {0.5, 0.5, -0.8}, {1.4, 0.9, 0.9}};
  const ObjectMotion motions[3] = {motion_of({1.5, 0, 0}, {0, 1, 0}, 0),
                                   motion_of({0, 0.8, 0.3}, {1, 1, 0}, 120),
                                   motion_of({-0.6, 0, 0.5}, {0, 0, 1}, -200)};
  for (int i = 0; i < 3; ++i) {
    const int obj = add_sphere(s, centres[i], 0.5, 2, Material{}, "sphere");
    s.solid_balls.pop_back();
    add_mover(s, obj, obj + 1, centres[i], motions[i], 1);
  }
  Material m;
  const int mat = add_scene_material(s, m);
  const int box = add_mesh_object(s, "box");
  append_quad(s.mesh, Vec3d(-0.3, 1.6, 0.3), Vec3d(0.6, 0, 0), Vec3d(0, 0.5, -0.6), mat, box);
  append_quad(s.mesh, Vec3d(-0.3, 1.6, -0.3), Vec3d(0.6, 0, 0), Vec3d(0, 0.4, 0), mat, box);
  add_mover(s, box, box + 1, Vec3d(0, 1.8, 0), motion_of({0.4, -0.2, 0}, {0, 1, 0}, 360), 1);
  s.max_abs_time = 1.0;
  place_moving_objects_last(s, "test");
  const MovingScene scene = upload_scene(s, bvh::BuildQuality::kSah, 0.5);
  ASSERT_EQ(scene.motion.count, 4);

  const int rays = 40000;
  const BruteForceCounts n = compare_with_brute_force(scene, rays);
  const long long hits = n.hits, mover_hits = n.mover_hits, differ = n.differ,
                  world_differ = n.world_differ, occl_differ = n.occl_differ;
  EXPECT_GT(hits, rays / 2);
  EXPECT_GT(mover_hits, rays / 10);  // the test exercises the moving objects
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(occl_differ, 0);
  EXPECT_LE(world_differ, rays / 2000) << "moving the triangles instead of the ray";
}

TEST(SketchMotion, SceneWithNothingStillHasAnEmptyStillTree) {
  HostScene s;
  const int obj = add_sphere(s, Vec3d(0, 1, 0), 0.3, 2, Material{}, "sphere");
  s.solid_balls.pop_back();
  add_mover(s, obj, obj + 1, Vec3d(0, 1, 0), motion_of(Vec3d(0, 0, -1), Vec3d(0, 1, 0), 0), 1);
  s.max_abs_time = 1.0;
  place_moving_objects_last(s, "test");
  const MovingScene scene = upload_scene(s, bvh::BuildQuality::kSah, 0.5);
  EXPECT_EQ(scene.mesh.accel.num_prims, 0);
  const DownHit h = shoot_down(scene, 0, Real(-0.5), Real(0.5));
  EXPECT_TRUE(h.on_square);  // the sphere, moved to z = -0.5
  EXPECT_NEAR(h.p.y, 1.3, 1e-2);
  EXPECT_FALSE(shoot_down(scene, 0, 0, Real(0.5)).on_square);
}

TEST(SketchMotion, StillSceneHasNoMovers) {
  HostScene s;
  add_floor(s, 1.0, 0.5f);
  add_sphere(s, Vec3d(0, 0.5, 0), 0.5, 1, Material{}, "sphere");
  const DeviceScene d = upload_scene(s, bvh::BuildQuality::kSah, 0.5);
  EXPECT_EQ(d.motion.count, 0);
  EXPECT_EQ(d.mesh.accel.num_prims, static_cast<int>(d.triangles));
}

}  // namespace
}  // namespace rtmini::sketch::test
