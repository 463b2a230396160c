// BVH against the brute-force reference: every hit distance and triangle id
// equal, for every builder, on the bundled meshes and on degenerate inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "rtmini/bvh/brute_force.hpp"
#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/gpu_collapse.hpp"
#include "rtmini/bvh/presplit.hpp"
#include "rtmini/bvh/quality.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "rtmini/scene/primitives.hpp"
#include "test_space.hpp"
#include "trace_answers.hpp"

namespace rtmini::test {
namespace {

using Policy = Kokkos::RangePolicy<TestExecSpace>;

// Random rays: origins in a box 1.5x the scene, directions uniform; half of
// them aimed at a random triangle's vertex or edge point (the hard cases).
Kokkos::View<Ray*, TestMemSpace> random_rays(Kokkos::View<const Triangle*, TestMemSpace> tris,
                                             const Aabb& box, int n, std::uint64_t seed) {
  Kokkos::View<Ray*, TestMemSpace> rays("rays", n);
  const int nt = static_cast<int>(tris.extent(0));
  const Vec3 c = box.center(), e = box.extent() * Real(0.75);
  Kokkos::parallel_for(
      "test::random_rays", Policy(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(seed, std::uint64_t(i), 0);
        const auto a = rng.block(0), b = rng.block(1);
        Ray r;
        r.org = c + Vec3(e.x * (2 * Rng::to_unit(a.v[0]) - 1), e.y * (2 * Rng::to_unit(a.v[1]) - 1),
                         e.z * (2 * Rng::to_unit(a.v[2]) - 1));
        if (i % 2 == 0) {
          r.dir = uniform_sphere(Rng::to_unit(b.v[0]), Rng::to_unit(b.v[1]));
        } else {
          const Triangle t = tris(int(b.v[0] % std::uint32_t(nt)));
          const int kind = int(b.v[1] % 3u);
          const Real s = Rng::to_unit(b.v[2]);
          const Vec3 target =
              kind == 0 ? t.a : (kind == 1 ? t.a + (t.b - t.a) * s : t.b + (t.c - t.b) * s);
          r.dir = normalize(target - r.org);
        }
        r.tmin = 0;
        r.tmax = (i % 7 == 0) ? Real(0.3) * box.diagonal() : Real(1e30);
        rays(i) = r;
      });
  return rays;
}

void expect_same(const Answers& x, const Answers& ref, const std::string& what) {
  auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x.hit);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ref.hit);
  auto oa = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x.any);
  auto ob = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ref.any);
  const int n = static_cast<int>(ha.extent(0));
  int mismatches = 0, hits = 0;
  for (int i = 0; i < n; ++i) {
    hits += hb(i).valid();
    const bool same = ha(i).prim == hb(i).prim && (ha(i).prim < 0 || ha(i).t == hb(i).t) &&
                      oa(i) == ob(i) && ob(i) == int(hb(i).valid());
    if (!same && ++mismatches <= 5)
      ADD_FAILURE() << what << " ray " << i << ": bvh (" << ha(i).prim << ", t=" << ha(i).t
                    << ", any " << oa(i) << ") vs reference (" << hb(i).prim << ", t=" << hb(i).t
                    << ", any " << ob(i) << ")";
  }
  EXPECT_EQ(mismatches, 0) << what;
  EXPECT_GT(hits, n / 20) << what << ": too few rays hit anything for the test to mean much";
}

template <class Accel, class Ref>
void expect_same_hits(const Accel& accel, const Ref& ref, Kokkos::View<Ray*, TestMemSpace> rays,
                      const std::string& what) {
  expect_same(trace_all(accel, rays), trace_all(ref, rays), what);
}

Mesh load_scene(const std::string& name) {
  return read_mesh(std::string(scenes_dir()) + "/" + name);
}

// Rays straight up through the unit square (a free function: CUDA lambdas may
// not live inside a test body).
Kokkos::View<Ray*, TestMemSpace> axis_rays(int n) {
  Kokkos::View<Ray*, TestMemSpace> rays("rays", n);
  Kokkos::parallel_for(
      "test::axis_rays", Policy(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(3, std::uint64_t(i), 0);
        Ray r;
        r.org = Vec3(rng.uniform(0), rng.uniform(1), Real(-0.5));
        r.dir = Vec3(0, 0, 1);
        rays(i) = r;
      });
  return rays;
}

class BvhVsBruteForce : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhVsBruteForce, EveryHitEqual) {
  const Mesh mesh = load_scene(GetParam());
  auto tris = upload_triangles(mesh);
  Aabb box;
  for (const auto& p : mesh.positions) box.expand(Vec3(p));
  auto rays = random_rays(tris, box, 50000, 7);
  const Answers ref = trace_all(bvh::BruteForce<TestMemSpace>{tris}, rays);
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
    const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    expect_same(trace_all(accel, rays), ref, GetParam() + " " + bvh::to_string(q));
  }
  // Spatial splits forced on: chopped references, whole triangles in the leaves.
  const auto spatial = bvh::build<TestExecSpace, TestMemSpace>(
      TestExecSpace(), tris, bvh::BuildQuality::kSah, bvh::QuantizedWide::kOnDevices,
      bvh::kDefaultSplitBudget, bvh::SpatialSplits::kOn);
  expect_same(trace_all(spatial, rays), ref, GetParam() + " sah, spatial splits");
}

INSTANTIATE_TEST_SUITE_P(SmallMeshes, BvhVsBruteForce,
                         ::testing::Values("teapot.obj", "spot.obj", "cow.obj",
                                           "CornellBox-Original.obj"));

// On the large meshes brute force is too slow for a million rays: the two
// builders must agree with each other on 1M rays, and with brute force on 5K.
class BvhLargeMesh : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhLargeMesh, BuildersAgreeAndMatchBruteForce) {
  const Mesh mesh = load_scene(GetParam());
  auto tris = upload_triangles(mesh);
  const auto lbvh =
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kLbvh);
  const auto sah =
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kSah);
  expect_same_hits(lbvh, sah, random_rays(tris, lbvh.bounds, 1000000, 11),
                   GetParam() + " lbvh vs sah");
  const auto ploc =
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kPloc);
  expect_same_hits(ploc, sah, random_rays(tris, sah.bounds, 200000, 29),
                   GetParam() + " ploc vs sah");
  // Brute force is nine tenths of this test's time: trace it once for both builders.
  const auto few = random_rays(tris, sah.bounds, 5000, 13);
  const Answers ref = trace_all(bvh::BruteForce<TestMemSpace>{tris}, few);
  expect_same(trace_all(sah, few), ref, GetParam() + " sah vs brute force");
  expect_same(trace_all(ploc, few), ref, GetParam() + " ploc vs brute force");
}

// The device builders lay every input triangle out exactly once, with its id (prim) pointing
// back at it, and give trees no deeper than traversal's stack.
TEST(Bvh, DeviceBuildersKeepEveryTriangleOnce) {
  const Mesh mesh = load_scene("stanford-bunny.obj");
  auto tris = upload_triangles(mesh);
  const auto input = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
  const int n = static_cast<int>(tris.extent(0));
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kPloc}) {
    // The raw builders: build() would turn zero-area triangles into points.
    const auto accel = q == bvh::BuildQuality::kLbvh
                           ? bvh::build_lbvh<TestExecSpace, TestMemSpace>(TestExecSpace(), tris)
                           : bvh::build_ploc<TestExecSpace, TestMemSpace>(TestExecSpace(), tris);
    EXPECT_EQ(accel.quality, q);
    const auto prim = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.prim);
    const auto laid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.tris);
    std::vector<int> seen(n, 0);
    int moved = 0;
    for (int i = 0; i < n; ++i) {
      ++seen[prim(i)];
      const Triangle& a = laid(i);
      const Triangle& b = input(prim(i));
      for (const auto& [u, v] : {std::pair(a.a, b.a), std::pair(a.b, b.b), std::pair(a.c, b.c)})
        moved += !(u.x == v.x && u.y == v.y && u.z == v.z);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n) << bvh::to_string(q);
    EXPECT_EQ(moved, 0) << bvh::to_string(q);
    EXPECT_LT(bvh::measure_quality(accel).max_depth, bvh::kStackSize) << bvh::to_string(q);
  }
}

INSTANTIATE_TEST_SUITE_P(LargeMeshes, BvhLargeMesh,
                         ::testing::Values("stanford-bunny.obj", "dragon.obj"));

// The adaptive Morton axes (build_lbvh.hpp): classic codes unless the scene is flat, and on the
// rooms scene's 16-room building (25 x 3 x 25) cells near cubes: x and z 11 bits, y 8.
TEST(Bvh, MortonAxesKeepCellsNearCubesOnFlatScenes) {
  EXPECT_TRUE(bvh::detail::morton_axes(Vec3(1, Real(0.6), Real(0.3))).classic);
  const auto flat = bvh::detail::morton_axes(Vec3(Real(24.7), Real(3.2), Real(24.7)));
  EXPECT_FALSE(flat.classic);
  EXPECT_EQ(flat.bits[0], 11);
  EXPECT_EQ(flat.bits[1], 8);
  EXPECT_EQ(flat.bits[2], 11);
  EXPECT_EQ(flat.mask[0] & flat.mask[1], 0u);
  EXPECT_EQ((flat.mask[0] | flat.mask[1]) & flat.mask[2], 0u);
  EXPECT_EQ(flat.mask[0] | flat.mask[1] | flat.mask[2], 0x3fffffffu);
  EXPECT_NE(flat.mask[0] & (1u << 29), 0u) << "the long axes' extra bits on top";
  EXPECT_NE(flat.mask[2] & (1u << 28), 0u);
  EXPECT_EQ(bvh::detail::adaptive_morton_code(Vec3(1, 1, 1), flat), 0x3fffffffu);
  EXPECT_EQ(bvh::detail::adaptive_morton_code(Vec3(0, 0, 0), flat), 0u);
}

// A floor of small triangles under one lamp triangle as wide as the floor (the rooms scene's
// light): the LBVH hangs the lamp's leaf from the root, as an SAH build would, instead of below
// the leaf of its centroid's cell, where its box would widen every box above that leaf.
TEST(Bvh, LbvhSetsLargeTrianglesApartAtTheRoot) {
  Mesh m;
  const int side = 40;
  for (int j = 0; j <= side; ++j)
    for (int i = 0; i <= side; ++i)
      m.positions.push_back({0.5 * i, 0.02 * ((7 * i + 3 * j) % 5), 0.5 * j});
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      const int a = j * (side + 1) + i;
      Face f;
      f.v = {a, a + 1, a + side + 2, a + side + 1};
      f.count = 4;
      m.faces.push_back(f);
    }
  const int lamp_vertex = static_cast<int>(m.positions.size());
  for (const Vec3d& p : {Vec3d(0, 3, 0), Vec3d(20, 3, 0), Vec3d(0, 3, 20)})
    m.positions.push_back(p);
  Face lamp;
  lamp.v = {lamp_vertex, lamp_vertex + 1, lamp_vertex + 2, -1};
  m.faces.push_back(lamp);
  auto tris = upload_triangles(m);
  const int lamp_tri = static_cast<int>(tris.extent(0)) - 1;
  const auto accel = bvh::build_lbvh<TestExecSpace, TestMemSpace>(TestExecSpace(), tris);
  const auto nodes = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.nodes);
  const auto prim = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.prim);
  EXPECT_EQ(prim(0), lamp_tri) << "large triangles sort first";
  EXPECT_EQ(nodes(0).child[0], bvh::make_leaf(0, 1)) << "the lamp alone, below the root";
  const bvh::BruteForce<TestMemSpace> ref{tris};
  const auto finished =
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kLbvh);
  expect_same_hits(finished, ref, random_rays(tris, finished.bounds, 2000, 7),
                   "floor under a lamp");
}

TEST(Bvh, TinyAndDegenerateInputs) {
  // 0, 1, 2 and 9 triangles; zero-area and duplicate triangles; all centroids equal.
  Mesh m;
  for (int count : {0, 1, 2, 9, 40}) {
    m = Mesh();
    for (int i = 0; i < count; ++i) {
      const double z = (i % 3 == 0) ? 0.0 : double(i);  // duplicates at z = 0
      m.positions.push_back({0, 0, z});
      m.positions.push_back({1, 0, z});
      m.positions.push_back({i % 5 == 4 ? 2.0 : 0.0, i % 5 == 4 ? 0.0 : 1.0, z});  // some zero-area
      Face f;
      f.v = {3 * i, 3 * i + 1, 3 * i + 2, -1};
      m.faces.push_back(f);
    }
    auto tris = upload_triangles(m);
    const bvh::BruteForce<TestMemSpace> ref{tris};
    Aabb box;
    box.expand(Vec3(-1, -1, -1));
    box.expand(Vec3(2, 2, Real(count + 1)));
    for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
      const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
      if (count == 0) continue;
      auto rays = axis_rays(2000);
      expect_same_hits(accel, ref, rays,
                       "degenerate n=" + std::to_string(count) + " " + bvh::to_string(q));
    }
    const auto spatial = bvh::build<TestExecSpace, TestMemSpace>(
        TestExecSpace(), tris, bvh::BuildQuality::kSah, bvh::QuantizedWide::kOnDevices,
        bvh::kDefaultSplitBudget, bvh::SpatialSplits::kOn);
    if (count > 0)
      expect_same_hits(spatial, ref, axis_rays(2000),
                       "degenerate n=" + std::to_string(count) + " sah, spatial splits");
  }
}

// Rays grazing the faces of `tris`: aimed at a vertex or an edge point of a random triangle, with
// a direction almost in its plane (the normal component 1-2 thousandths), from 0.01-3 `reach`
// away; a third end exactly at the target (tmax = its distance).
Kokkos::View<Ray*, TestMemSpace> grazing_rays(Kokkos::View<const Triangle*, TestMemSpace> tris,
                                              Real reach, int n, std::uint64_t seed) {
  Kokkos::View<Ray*, TestMemSpace> rays("rays", n);
  const int nt = static_cast<int>(tris.extent(0));
  Kokkos::parallel_for(
      "test::grazing_rays", Policy(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(seed, std::uint64_t(i), 0);
        const auto a = rng.block(0), b = rng.block(1);
        const Triangle t = tris(int(a.v[0] % std::uint32_t(nt)));
        const Real s = Rng::to_unit(a.v[1]);
        const int kind = int(a.v[2] % 3u);
        const Vec3 target =
            kind == 0 ? t.b : (kind == 1 ? t.a + (t.b - t.a) * s : t.b + (t.c - t.b) * s);
        const Vec3 normal = normalize(cross(t.b - t.a, t.c - t.a));
        const Vec3 along = uniform_sphere(Rng::to_unit(b.v[0]), Rng::to_unit(b.v[1]));
        const Vec3 tangent = normalize(along - normal * dot(along, normal));
        const Real lift = Real(0.001) * (1 + Rng::to_unit(b.v[2]));
        Ray r;
        r.dir = normalize(tangent + normal * (b.v[3] % 2u ? lift : -lift));
        r.org = target - r.dir * (reach * (Real(0.01) + 3 * Rng::to_unit(a.v[3])));
        r.tmin = 0;
        r.tmax = i % 3 == 0 ? length(target - r.org) : Real(1e30);
        rays(i) = r;
      });
  return rays;
}

// The box test is conservative by a margin that depends on the coordinates' magnitude (the FMA
// test of traverse.hpp): rays grazing the faces, edges and corners of touching boxes, at large
// and small scales far from the origin, find exactly what brute force finds.
TEST(Bvh, GrazingRaysAtManyScalesMatchBruteForce) {
  const Placement placements[] = {
      {"unit", 1, 0}, {"far", 1, 1e3}, {"small-far", 1e-2, 1e3}, {"far-huge", 1e3, 1e4}};
  for (const Placement& p : placements) {
    Mesh m;
    const Vec3d origin(p.offset, -0.5 * p.offset, 0.25 * p.offset);
    for (int i = 0; i < 27; ++i) {  // a 3x3x3 block of touching boxes
      const Vec3d lo = origin + Vec3d(i % 3, i / 3 % 3, i / 9) * p.scale;
      append_box(m, lo, lo + Vec3d(p.scale, p.scale, p.scale), -1, 0);
    }
    auto tris = upload_triangles(m);
    const bvh::BruteForce<TestMemSpace> ref{tris};
    const auto rays = grazing_rays(tris, Real(p.scale), 20000, 23);
    for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
      const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
      expect_same_hits(accel, ref, rays,
                       std::string("grazing, ") + p.name + " " + bvh::to_string(q));
    }
  }
}

TEST(Bvh, QualityReportIsConsistent) {
  const Mesh mesh = load_scene("teapot.obj");
  auto tris = upload_triangles(mesh);
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
    const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    const auto r = bvh::measure_quality(accel);
    int prims = 0;
    for (int s = 1; s <= bvh::kMaxLeafSize; ++s) prims += s * r.leaf_size_histogram[s];
    EXPECT_EQ(prims, int(tris.extent(0)))
        << bvh::to_string(q) << ": every triangle in exactly one leaf";
    EXPECT_LE(r.max_depth, bvh::kStackSize);
    EXPECT_GT(r.sah_cost, 1.0);
  }
  const auto lb = bvh::measure_quality(
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kLbvh));
  const auto sa = bvh::measure_quality(
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kSah));
  EXPECT_LT(sa.sah_cost, lb.sah_cost) << "the SAH build must have the lower SAH cost";
  const auto pl = bvh::measure_quality(
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kPloc));
  EXPECT_LT(pl.sah_cost, lb.sah_cost) << "PLOC must beat the LBVH's SAH cost";
}

// Issue 21's bar for the device quality builder: within 10 % of the host SAH build's cost. The
// bunny is the hardest bundled mesh (PLOC alone was +10.7 %; with treelet restructuring +8.2 %).
TEST(Bvh, PlocCostWithinTenPercentOfSahBuild) {
  auto tris = upload_triangles(load_scene("stanford-bunny.obj"));
  const double sah = bvh::measure_quality(bvh::build<TestExecSpace, TestMemSpace>(
                                              TestExecSpace(), tris, bvh::BuildQuality::kSah))
                         .sah_cost;
  const double ploc = bvh::measure_quality(bvh::build<TestExecSpace, TestMemSpace>(
                                               TestExecSpace(), tris, bvh::BuildQuality::kPloc))
                          .sah_cost;
  EXPECT_LT(ploc, 1.10 * sah) << "PLOC " << ploc << ", host SAH " << sah;
}

// --bvh auto's choice depends on rays per triangle only, each builder owning one interval
// (crossovers of the measured costs in build_quality.hpp; results/bvh/README.md "--bvh auto").
TEST(Bvh, AutoBuildFollowsRaysPerTriangle) {
  const double tris = 1e5;
  const auto device = [&](double rays_per_tri) {
    return bvh::choose_build_quality(tris, rays_per_tri * tris, true);
  };
  EXPECT_EQ(device(192), bvh::BuildQuality::kLbvh) << "AO's default 3 x 64 rays per triangle";
  EXPECT_EQ(device(5000), bvh::BuildQuality::kPloc);
  EXPECT_EQ(device(50000), bvh::BuildQuality::kSah);
  EXPECT_EQ(bvh::choose_build_quality(tris, 10 * tris, false), bvh::BuildQuality::kLbvh);
  EXPECT_EQ(bvh::choose_build_quality(tris, 192 * tris, false), bvh::BuildQuality::kSah);
}

// The compressed 8-wide layout (built on devices by default) asked for explicitly, so the host
// backends check it too: every hit equal to brute force, for both builders.
template <class BvhT>
BvhT with_quantized_wide(BvhT accel) {
  bvh::add_quantized_wide(TestExecSpace(), accel);
  return accel;
}

// Both queries through the compressed wide traversal itself (bvh::any_hit takes the binary tree
// on devices, where it measured faster, so the public entry points would not reach it).
template <class BvhT>
Answers trace_quantized(const BvhT& accel, Kokkos::View<Ray*, TestMemSpace> rays) {
  const int n = static_cast<int>(rays.extent(0));
  Answers a{Kokkos::View<Hit*, TestMemSpace>("hit", n), Kokkos::View<int*, TestMemSpace>("any", n)};
  Kokkos::parallel_for(
      "test::trace_quantized", Policy(0, n), KOKKOS_LAMBDA(int i) {
        Hit h;
        h.t = rays(i).tmax;
        bvh::detail::traverse_quantized<BvhT, false, false, bvh::TraversalStats>(accel, rays(i), h,
                                                                                 nullptr);
        a.hit(i) = h;
        Hit any;
        a.any(i) = bvh::detail::traverse_quantized<BvhT, true, false, bvh::TraversalStats>(
                       accel, rays(i), any, nullptr)
                       ? 1
                       : 0;
      });
  return a;
}

class QuantizedWideVsBruteForce : public ::testing::TestWithParam<std::string> {};

TEST_P(QuantizedWideVsBruteForce, EveryHitEqual) {
  const Mesh mesh = load_scene(GetParam());
  auto tris = upload_triangles(mesh);
  Aabb box;
  for (const auto& p : mesh.positions) box.expand(Vec3(p));
  auto rays = random_rays(tris, box, 30000, 17);
  const Answers ref = trace_all(bvh::BruteForce<TestMemSpace>{tris}, rays);
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
    const auto accel =
        with_quantized_wide(bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q));
    ASSERT_GT(accel.qwide.extent(0), 0u);
    expect_same(trace_quantized(accel, rays), ref, GetParam() + " quantized " + bvh::to_string(q));
  }
}

INSTANTIATE_TEST_SUITE_P(SmallMeshes, QuantizedWideVsBruteForce,
                         ::testing::Values("teapot.obj", "CornellBox-Original.obj"));

// On the dragon the quantised tree must give the binary tree's answers (which the tests above
// check against brute force), and brute force's own on a few thousand rays.
TEST(QuantizedWide, DragonMatchesBinaryAndBruteForce) {
  const Mesh mesh = load_scene("dragon.obj");
  auto tris = upload_triangles(mesh);
  Aabb box;
  for (const auto& p : mesh.positions) box.expand(Vec3(p));
  // Every builder's tree bounds the same triangles: one set of rays and one brute-force trace.
  const auto rays = random_rays(tris, box, 100000, 19);
  const auto few = random_rays(tris, box, 1000, 23);
  const Answers ref = trace_all(bvh::BruteForce<TestMemSpace>{tris}, few);
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
    auto binary = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    const auto wide = with_quantized_wide(binary);
    binary.qwide = {};  // on devices build() adds it: trace the binary tree itself
    binary.wide = {};
    expect_same(trace_quantized(wide, rays), trace_all(binary, rays),
                std::string("dragon quantized vs binary ") + bvh::to_string(q));
    expect_same(trace_quantized(wide, few), ref,
                std::string("dragon quantized vs brute force ") + bvh::to_string(q));
  }
}

// Every triangle in exactly one quantised leaf, and tiny or degenerate inputs traced right.
TEST(QuantizedWide, TinyAndDegenerateInputs) {
  for (int count : {1, 2, 3, 9, 40, 200}) {
    Mesh m;
    for (int i = 0; i < count; ++i) {
      const double z = (i % 3 == 0) ? 0.0 : double(i);
      m.positions.push_back({0, 0, z});
      m.positions.push_back({1, 0, z});
      m.positions.push_back({i % 5 == 4 ? 2.0 : 0.0, i % 5 == 4 ? 0.0 : 1.0, z});
      Face f;
      f.v = {3 * i, 3 * i + 1, 3 * i + 2, -1};
      m.faces.push_back(f);
    }
    auto tris = upload_triangles(m);
    for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah, bvh::BuildQuality::kPloc}) {
      const auto accel =
          with_quantized_wide(bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q));
      auto ids = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.qwide_prim);
      std::vector<int> seen(count, 0);
      for (int i = 0; i < count; ++i) ++seen[ids(i)];
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), count) << "n=" << count;
      auto rays = axis_rays(2000);
      expect_same(trace_quantized(accel, rays),
                  trace_all(bvh::BruteForce<TestMemSpace>{tris}, rays),
                  "quantized degenerate n=" + std::to_string(count) + " " + bvh::to_string(q));
    }
  }
}

// The sliver fan of issue 18, scaled down: 800 triangles sharing one apex over one radian
// (aspect 800). Every diagonal sliver's box is mostly empty, so without pre-splitting a ray
// through the fan tests a third of them. The tests per ray of a flat fan fall only as
// 1 / (references per triangle) (results/bvh/slivers.md), so a budget of 1 (2x) halves them:
// 800 is the size where that half is under the bound of 150.
Mesh sliver_fan() {
  Mesh m;
  m.materials.push_back(Material{});
  append_fan(m, {0, 0, 0}, 1.0, 1.0, 800, 0, 0);
  return m;
}

// Rays from above the fan to uniform points of its bounding box (some miss the fan).
template <class ExecSpace>
Kokkos::View<Ray*, typename ExecSpace::memory_space> fan_rays(int n) {
  Kokkos::View<Ray*, typename ExecSpace::memory_space> rays("fan_rays", n);
  Kokkos::parallel_for(
      "test::fan_rays", Kokkos::RangePolicy<ExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(5, std::uint64_t(i), 0);
        const Vec3 target(Real(1.1) * rng.uniform(0) - Real(0.05),
                          Real(0.95) * rng.uniform(1) - Real(0.05), 0);
        Ray r;
        r.org = Vec3(Real(0.4), Real(0.3), Real(1.5));
        r.dir = normalize(target - r.org);
        rays(i) = r;
      });
  return rays;
}

TEST(Bvh, PresplitSliverFanMatchesBruteForce) {
  const Mesh mesh = sliver_fan();
  auto tris = upload_triangles(mesh);
  const bvh::BruteForce<TestMemSpace> ref{tris};
  const auto sah =
      bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, bvh::BuildQuality::kSah);
  EXPECT_GT(sah.num_prims, int(tris.extent(0))) << "the fan's slivers must be pre-split";
  expect_same_hits(sah, ref, random_rays(tris, sah.bounds, 20000, 17), "sliver fan, random rays");
  expect_same_hits(sah, ref, fan_rays<TestExecSpace>(20000), "sliver fan, rays from above");
}

TEST(Bvh, SpatialSplitSliverFanMatchesBruteForce) {
  const Mesh mesh = sliver_fan();
  auto tris = upload_triangles(mesh);
  const bvh::BruteForce<TestMemSpace> ref{tris};
  const auto sah = bvh::build<TestExecSpace, TestMemSpace>(
      TestExecSpace(), tris, bvh::BuildQuality::kSah, bvh::QuantizedWide::kOnDevices,
      bvh::kDefaultSplitBudget, bvh::SpatialSplits::kOn);
  EXPECT_GT(sah.num_prims, int(tris.extent(0))) << "spatial splits must chop the fan's slivers";
  expect_same_hits(sah, ref, random_rays(tris, sah.bounds, 20000, 19),
                   "sliver fan, spatial splits, random rays");
  expect_same_hits(sah, ref, fan_rays<TestExecSpace>(20000),
                   "sliver fan, spatial splits, rays from above");
}

// Mean ray-triangle tests per ray on the host (binary or 8-wide layout).
double host_tests_per_ray(const bvh::Bvh<Kokkos::HostSpace>& accel,
                          const Kokkos::View<Ray*, Kokkos::HostSpace>& rays) {
  double tests = 0;
  for (std::size_t i = 0; i < rays.extent(0); ++i) {
    bvh::TraversalStats st;
    bvh::closest_hit(accel, rays(i), st);
    tests += st.tests;
  }
  return tests / double(rays.extent(0));
}

Kokkos::View<Triangle*, Kokkos::HostSpace> host_triangles(const Mesh& mesh) {
  const TriangleList tl = triangulate(mesh);
  Kokkos::View<Triangle*, Kokkos::HostSpace> tris("tris", tl.vertices.size());
  for (std::size_t t = 0; t < tl.vertices.size(); ++t)
    tris(t) = {Vec3(mesh.positions[tl.vertices[t][0]]), Vec3(mesh.positions[tl.vertices[t][1]]),
               Vec3(mesh.positions[tl.vertices[t][2]])};
  return tris;
}

// The fan's tests per ray fall as 1 / (references per triangle) whatever the splitter: a fixed
// budget of 1 halves them; the auto budget doubles the references while each doubling removes a
// quarter of the summed box area (here up to 64 per triangle, where the parts near the apex stop
// being slivers).
TEST(Bvh, PresplitSliverFanTestsPerRay) {
  using Host = Kokkos::DefaultHostExecutionSpace;
  const auto tris = host_triangles(sliver_fan());
  const int n = int(tris.extent(0));
  const auto rays = fan_rays<Host>(4000);
  double unsplit = 0;
  struct Case {
    bvh::SpatialSplits spatial;
    double budget;
  };
  for (const Case c : {Case{bvh::SpatialSplits::kOff, 0.0}, Case{bvh::SpatialSplits::kOff, 1.0},
                       Case{bvh::SpatialSplits::kOff, bvh::kAutoSplitBudget},
                       Case{bvh::SpatialSplits::kOn, 1.0}}) {
    auto accel = bvh::build<Host, Kokkos::HostSpace>(
        Host(), tris, bvh::BuildQuality::kSah, bvh::QuantizedWide::kOnDevices, c.budget, c.spatial);
    const double wide = host_tests_per_ray(accel, rays);
    accel.wide = {};  // the binary layout, as traversed on devices
    const double binary = host_tests_per_ray(accel, rays);
    std::printf(
        "spatial splits %s, split budget %s: %d references, %.1f tests per ray (8-wide), "
        "%.1f (binary)\n",
        bvh::to_string(c.spatial), bvh::split_budget_to_string(c.budget).c_str(), accel.num_prims,
        wide, binary);
    if (c.budget == 0.0) {
      unsplit = binary;
      EXPECT_GT(binary, 200.0) << "without pre-splitting the fan must be a hard case";
    } else if (c.spatial == bvh::SpatialSplits::kOn) {
      EXPECT_LE(binary, 0.75 * unsplit);
      EXPECT_LE(wide, 0.75 * unsplit);
    } else if (c.budget == 1.0) {
      EXPECT_LE(wide, 150.0);
      EXPECT_LE(binary, 150.0);
    } else {  // auto: stops at 64 references per triangle (the 128th halves no more)
      EXPECT_GE(accel.num_prims, 32 * n);
      EXPECT_LE(accel.num_prims, int(bvh::kAutoMaxReferencesPerTriangle) * n);
      EXPECT_LE(wide, 10.0);
      EXPECT_LE(binary, 10.0);
    }
  }
}

// The auto budget on a mesh whose triangles fill their boxes: no candidate passes the first
// check, so the SAH build gets the triangles as they are (the same tree as budget 0).
TEST(Bvh, AutoSplitBudgetLeavesOrdinaryMeshesUnsplit) {
  for (const char* name : {"teapot.obj", "spot.obj", "cow.obj", "CornellBox-Original.obj"}) {
    const auto tris = host_triangles(load_scene(name));
    const std::vector<Triangle> v(tris.data(), tris.data() + tris.extent(0));
    Aabb box;
    for (const Triangle& t : v) {
      box.expand(t.a);
      box.expand(t.b);
      box.expand(t.c);
    }
    EXPECT_TRUE(bvh::presplit_triangles(v, box, bvh::kAutoSplitBudget).empty()) << name;
  }
}

// Four long thin diagonal slivers over a grid of 1,600 small right triangles: the first step
// (budget 1) cuts the slivers into ~400 parts each and removes most of the summed box area; the
// next doubling could still cut them finer, but what is left of their boxes is ~1 % of the
// grid's, so that step is undone. The hits stay exact.
TEST(Bvh, AutoSplitBudgetStopsWhenSplittingNoLongerPays) {
  Mesh m;
  m.materials.push_back(Material{});
  auto add_triangle = [&m](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const int base = int(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    Face f;
    f.v = {base, base + 1, base + 2, -1};
    m.faces.push_back(f);
  };
  constexpr int kGrid = 40;
  const double h = 1.0 / kGrid;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j)
      add_triangle({i * h, j * h, 0}, {i * h + h, j * h, 0}, {i * h, j * h + h, 0});
  for (int k = 1; k <= 4; ++k) {  // aspect ~1e6, each at its own height
    const double z = 0.2 * k, w = 1e-6;
    add_triangle({0, 0, z}, {1, 1, z}, {1 + w, 1 - w, z});
  }
  auto tris = upload_triangles(m);
  const int n = int(tris.extent(0));
  const auto accel = bvh::build<TestExecSpace, TestMemSpace>(
      TestExecSpace(), tris, bvh::BuildQuality::kSah, bvh::QuantizedWide::kOnDevices,
      bvh::kAutoSplitBudget);
  std::printf("grid and slivers, auto budget: %d references for %d triangles\n", accel.num_prims,
              n);
  EXPECT_GT(accel.num_prims, n + 1000) << "the slivers must be split";
  EXPECT_LE(accel.num_prims, 2 * n) << "the second step must not pay here";
  const bvh::BruteForce<TestMemSpace> ref{tris};
  expect_same_hits(accel, ref, random_rays(tris, accel.bounds, 20000, 29),
                   "grid and slivers, auto budget");
}

TEST(Bvh, SplitBudgetParsesAutoAndNumbers) {
  double b = 7;
  EXPECT_TRUE(bvh::parse_split_budget("auto", b));
  EXPECT_TRUE(bvh::is_auto_split_budget(b));
  EXPECT_TRUE(bvh::parse_split_budget("2.5", b));
  EXPECT_EQ(b, 2.5);
  EXPECT_TRUE(bvh::parse_split_budget("0", b));
  EXPECT_EQ(b, 0.0);
  for (const char* bad : {"", "-1", "1x", "nan", "inf", "Auto"})
    EXPECT_FALSE(bvh::parse_split_budget(bad, b)) << bad;
  EXPECT_EQ(b, 0.0);
  EXPECT_EQ(bvh::split_budget_to_string(bvh::kAutoSplitBudget), "auto");
  EXPECT_EQ(bvh::split_budget_to_string(2.5), "2.5");
  EXPECT_EQ(bvh::split_budget_to_string(1.0), "1");
}

// A mesh's triangles as the host-only builders take them.
std::vector<Triangle> triangle_vector(const Mesh& mesh) {
  const auto h = host_triangles(mesh);
  return std::vector<Triangle>(h.data(), h.data() + h.extent(0));
}

bool encloses(const Aabb& outer, const Aabb& inner) {
  return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
         inner.hi.x <= outer.hi.x && inner.hi.y <= outer.hi.y && inner.hi.z <= outer.hi.z;
}

Aabb wide_child_box(const bvh::WideNode& n, int k) {
  Aabb b;
  b.lo = Vec3(n.lo_x[k], n.lo_y[k], n.lo_z[k]);
  b.hi = Vec3(n.hi_x[k], n.hi_y[k], n.hi_z[k]);
  return b;
}

// Devices traverse the binary tree one triangle at a time, so their SAH trees count single
// triangles (SahLeafCost::kPerTriangle): on the bunny about twice the inner nodes of the host's
// tree, whose SAH counts compact leaves' blocks of four. build() picks by the memory space.
TEST(SahBuild, DeviceTreesCountSingleTriangles) {
  const Mesh mesh = load_scene("stanford-bunny.obj");
  const std::vector<Triangle> input = triangle_vector(mesh);
  const bvh::HostBvh blocks = bvh::build_sah_host(input);
  const bvh::HostBvh single =
      bvh::build_sah_host(input, bvh::kDefaultSplitBudget, bvh::kDefaultSpatialSplits,
                          bvh::SahLeafCost::kPerTriangle);
  EXPECT_GT(single.nodes.size(), blocks.nodes.size() * 3 / 2);
  const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), upload_triangles(mesh),
                                                             bvh::BuildQuality::kSah);
  constexpr bool on_host =
      Kokkos::SpaceAccessibility<Kokkos::HostSpace, TestMemSpace>::accessible;
  EXPECT_EQ(accel.nodes.extent(0), on_host ? blocks.nodes.size() : single.nodes.size());
}

// The SAH-optimal 8-wide collapse (wide.cpp) lays every binary leaf slot out exactly once, in a
// leaf of at most eight lanes (compact leaves of at most four in half a block), each wide node and
// leaf referenced once, every child box enclosing what is under it (its leaf's triangles, or the
// child node's own child boxes).
TEST(WideCollapse, EveryTriangleOnceUnderEnclosingBoxes) {
  std::vector<std::vector<Triangle>> inputs = {triangle_vector(load_scene("stanford-bunny.obj"))};
  for (const int count : {1, 2, 9, 40})
    inputs.push_back({inputs[0].begin(), inputs[0].begin() + count});
  for (const auto& input : inputs) {
    const bvh::HostBvh h = bvh::build_sah_host(input);
    const bvh::WideBvh w = bvh::collapse_to_wide(h.nodes, h.tris.data(), h.prim.data());
    const std::string what = std::to_string(input.size()) + " triangles";
    std::vector<int> node_refs(w.nodes.size(), 0), half_refs(2 * w.leaves.size(), 0);
    std::vector<int> prim_expected(input.size(), 0), prim_seen(input.size(), 0);
    for (const int p : h.prim) ++prim_expected[p];
    node_refs[0] = 1;  // the root
    for (const bvh::WideNode& n : w.nodes)
      for (int k = 0; k < bvh::kWidth; ++k) {
        const std::uint32_t c = n.child[k];
        if (c == bvh::kEmptyLeaf) continue;
        const Aabb box = wide_child_box(n, k);
        if (!bvh::is_leaf(c)) {
          ++node_refs[c];
          for (int j = 0; j < bvh::kWidth; ++j) {
            if (w.nodes[c].child[j] == bvh::kEmptyLeaf) continue;
            EXPECT_TRUE(encloses(box, wide_child_box(w.nodes[c], j))) << what;
          }
          continue;
        }
        ASSERT_LE(bvh::leaf_count(c), std::uint32_t(bvh::kMaxLeafSize));
        const bool compact = bvh::leaf_count(c) <= std::uint32_t(bvh::kCompactLeafSize);
        const std::uint32_t half = bvh::leaf_first(c);
        ASSERT_LT(half / 2, w.leaves.size());
        ++half_refs[half];
        if (!compact) {
          EXPECT_EQ(half % 2, 0u) << what;  // a full leaf fills its block
          ++half_refs[half + 1];
        }
        const Real* rows = bvh::detail::leaf_rows(w.leaves[half / 2], c);
        for (int j = 0; j < int(bvh::leaf_count(c)); ++j) {
          Triangle t;
          int id;
          if (compact) {
            const bvh::detail::LeafRows<bvh::kCompactLeafSize> l{rows};
            t = l.triangle(j), id = l.prim(j);
          } else {
            const bvh::detail::LeafRows<bvh::kMaxLeafSize> l{rows};
            t = l.triangle(j), id = l.prim(j);
          }
          ++prim_seen[id];
          Aabb tb;
          tb.expand(t.a);
          tb.expand(t.b);
          tb.expand(t.c);
          EXPECT_TRUE(encloses(box, tb)) << what;
        }
      }
    EXPECT_EQ(prim_seen, prim_expected) << what;
    EXPECT_EQ(std::count(node_refs.begin(), node_refs.end(), 1), std::ptrdiff_t(w.nodes.size()))
        << what;
    // Every block holds a leaf, no half holds two (the last block's second half may be free).
    EXPECT_EQ(std::count_if(half_refs.begin(), half_refs.end(), [](int r) { return r > 1; }), 0)
        << what;
    for (std::size_t b = 0; b < w.leaves.size(); ++b) EXPECT_EQ(half_refs[2 * b], 1) << what;
  }
}

// Packets (traverse.hpp's closest_hit_packet and any_hit_packet, host): every ray's answer equals
// its single-ray answer bit for bit (t, u, v and id), for coherent packets (a camera's rays,
// shadow rays toward one light from the camera's hits) and incoherent ones (random_rays: short and
// endless, aimed at vertices and edges; AO-like groups of eight from one point), with empty
// segments, direction components near zero (a packet mixing the FMA and the robust box test) and
// every packet size from 1 to 8; camera and shadow rays also in pixel order (packets of one
// direction octant).
std::vector<Ray> packet_test_rays(const Kokkos::View<const Triangle*, Kokkos::HostSpace>& tris,
                                  const Aabb& box) {
  auto random = Kokkos::create_mirror_view_and_copy(
      Kokkos::HostSpace(),
      random_rays(Kokkos::create_mirror_view_and_copy(TestMemSpace(), tris), box, 4000, 11));
  std::vector<Ray> rays(random.data(), random.data() + random.extent(0));
  const Vec3 eye = box.center() + Vec3(Real(0.2), Real(0.3), Real(1.5)) * box.diagonal();
  const Vec3 light = box.center() + Vec3(Real(0.3), 1, Real(0.5)) * box.diagonal();
  const Frame f(normalize(box.center() - eye));
  const auto host = bvh::build<Kokkos::DefaultHostExecutionSpace, Kokkos::HostSpace>(
      Kokkos::DefaultHostExecutionSpace(), tris, bvh::BuildQuality::kLbvh);
  constexpr int kSide = 64;
  std::vector<Ray> camera_rays, shadow_rays;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      Ray cam;
      cam.org = eye;
      cam.dir = normalize(f.n + f.t * (Real(0.7) * (x + Real(0.5)) / kSide - Real(0.35)) +
                          f.b * (Real(0.7) * (y + Real(0.5)) / kSide - Real(0.35)));
      if (x % 29 == 0) cam.dir = normalize(Vec3(cam.dir.x, Real(1e-6), cam.dir.z));  // robust test
      if (x % 31 == 0) cam.tmax = Real(-1);  // an empty segment
      rays.push_back(cam);
      camera_rays.push_back(cam);
      const Hit h = bvh::closest_hit(host, cam);
      Ray shadow = cam;
      if (h.valid()) {
        shadow.org = cam.org + cam.dir * (h.t * Real(0.999));
        shadow.dir = normalize(light - shadow.org);
        shadow.tmax = length(light - shadow.org);
      }
      rays.push_back(shadow);
      shadow_rays.push_back(shadow);
      // Every 13th camera hit: eight AO-like rays from one point just above it (packets whose
      // rays share their origin test each leaf relative to it once), aimed at vertices and edges
      // of nearby triangles or at random, some short.
      if (h.valid() && (x + kSide * y) % 13 == 0) {
        const Vec3 point = cam.org + cam.dir * (h.t * Real(0.999));
        const Rng rng(17, std::uint64_t(x + kSide * y), 0);
        for (int k = 0; k < bvh::kPacketSize; ++k) {
          const auto a = rng.block(std::uint32_t(k));
          Ray ao;
          ao.org = point;
          if (k % 2 == 0) {
            ao.dir = uniform_sphere(Rng::to_unit(a.v[0]), Rng::to_unit(a.v[1]));
          } else {
            const Triangle t = tris(int((h.prim + int(a.v[0] % 64u)) % int(tris.extent(0))));
            const Real s = Rng::to_unit(a.v[1]);
            ao.dir = normalize((k % 4 == 1 ? t.c : t.a + (t.b - t.a) * s) - point);
          }
          ao.tmax = k % 3 == 0 ? Real(0.01) * box.diagonal() : Real(10) * box.diagonal();
          rays.push_back(ao);
        }
      }
    }
  // The camera's rays and their shadow rays each in pixel order too (as the bench traces them):
  // packets whose rays mostly share their direction octant (their box tests go child by child).
  rays.insert(rays.end(), camera_rays.begin(), camera_rays.end());
  rays.insert(rays.end(), shadow_rays.begin(), shadow_rays.end());
  return rays;
}

TEST(WidePackets, EveryRayAnswersAsAlone) {
  using HostExec = Kokkos::DefaultHostExecutionSpace;
  for (const char* name : {"stanford-bunny.obj", "teapot.obj"}) {
    const auto tris = host_triangles(load_scene(name));
    Aabb box;
    for (std::size_t t = 0; t < tris.extent(0); ++t) {
      box.expand(tris(t).a);
      box.expand(tris(t).b);
      box.expand(tris(t).c);
    }
    const std::vector<Ray> rays = packet_test_rays(tris, box);
    for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
      const auto accel = bvh::build<HostExec, Kokkos::HostSpace>(HostExec(), tris, q);
      ASSERT_GT(accel.wide.extent(0), 0u);
      const std::string what = std::string(name) + " " + bvh::to_string(q);
      int mismatches = 0, hits = 0, blocked = 0;
      std::size_t at = 0;
      for (int size = 1; at < rays.size(); size = size % bvh::kPacketSize + 1) {
        const int n = static_cast<int>(std::min<std::size_t>(size, rays.size() - at));
        Hit packet_hits[bvh::kPacketSize];
        bool packet_blocked[bvh::kPacketSize];
        bvh::closest_hit_packet(accel, rays.data() + at, n, packet_hits);
        bvh::any_hit_packet(accel, rays.data() + at, n, packet_blocked);
        for (int r = 0; r < n; ++r) {
          const Hit alone = bvh::closest_hit(accel, rays[at + r]);
          const bool alone_blocked = bvh::any_hit(accel, rays[at + r]);
          const Hit& p = packet_hits[r];
          hits += alone.valid();
          blocked += alone_blocked;
          const bool same = p.prim == alone.prim && p.t == alone.t && p.u == alone.u &&
                            p.v == alone.v && packet_blocked[r] == alone_blocked;
          if (!same && ++mismatches <= 5)
            ADD_FAILURE() << what << " ray " << at + r << " (packet of " << n << "): packet ("
                          << p.prim << ", t=" << p.t << ", any " << packet_blocked[r]
                          << ") vs alone (" << alone.prim << ", t=" << alone.t << ", any "
                          << alone_blocked << ")";
        }
        at += n;
      }
      EXPECT_EQ(mismatches, 0) << what;
      EXPECT_GT(hits, int(rays.size() / 8)) << what;
      EXPECT_GT(blocked, int(rays.size() / 8)) << what;
      EXPECT_LT(blocked, int(rays.size())) << what;
    }
  }
}

}  // namespace
}  // namespace rtmini::test
