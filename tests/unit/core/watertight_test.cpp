// Watertightness: rays from inside a closed mesh never escape, including rays
// aimed exactly at vertices and along edges, where non-watertight tests leak.
#include <gtest/gtest.h>

#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "rtmini/scene/primitives.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

// Returns the number of escaping rays out of n shot from `inside`.
long long count_escapes(const Mesh& mesh, const Vec3& inside, long long n, bvh::BuildQuality q,
                        bvh::SpatialSplits spatial = bvh::kDefaultSpatialSplits) {
  const auto dm = upload_mesh<TestExecSpace>(mesh, q);
  const auto accel = spatial == bvh::kDefaultSpatialSplits
                         ? dm.accel
                         : bvh::build<TestExecSpace, TestMemSpace>(
                               TestExecSpace(), dm.tris, q, bvh::QuantizedWide::kOnDevices,
                               bvh::kDefaultSplitBudget, spatial);
  const auto tris = dm.tris;
  const int nt = static_cast<int>(tris.extent(0));
  long long escapes = 0;
  Kokkos::parallel_reduce(
      "test::watertight", Kokkos::RangePolicy<TestExecSpace>(0, n),
      KOKKOS_LAMBDA(long long i, long long& esc) {
        const Rng rng(99, std::uint64_t(i), 0);
        const auto r = rng.block(0);
        Ray ray;
        ray.org = inside;
        const int kind = int(i % 4);
        if (kind == 0) {
          ray.dir = uniform_sphere(Rng::to_unit(r.v[0]), Rng::to_unit(r.v[1]));
        } else {
          const Triangle t = tris(int(r.v[0] % std::uint32_t(nt)));
          const Real s = Rng::to_unit(r.v[1]);
          // Aim at a vertex, at a point on an edge, or at an edge's midpoint.
          const Vec3 target =
              kind == 1 ? t.a : (kind == 2 ? t.a + (t.b - t.a) * s : (t.b + t.c) * Real(0.5));
          ray.dir = normalize(target - inside);
        }
        if (!bvh::closest_hit(accel, ray).valid()) ++esc;
      },
      escapes);
  return escapes;
}

TEST(Watertight, IcosphereAtManyScales) {
  // 10.4M rays in all: 13 placements x 800K rays, both builders.
  const Placement cases[] = {{"unit", 1, 0},  {"tiny", 1e-4, 0},      {"huge", 1e4, 0},
                             {"far", 1, 1e3}, {"far-huge", 1e3, 1e4}, {"off-center", 0.37, 11.3}};
  long long total = 0, escaped = 0;
  for (const Placement& c : cases) {
    for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
      Mesh m;
      const Vec3d center(c.offset, -0.5 * c.offset, 0.25 * c.offset);
      append_icosphere(m, center, c.scale, 4, -1, 0);
      // Shoot from a point off the centre so rays are not all symmetric.
      const Vec3 inside(center + Vec3d(0.21, -0.13, 0.08) * c.scale);
      const long long e = count_escapes(m, inside, 800000, q);
      EXPECT_EQ(e, 0) << c.name << " " << bvh::to_string(q);
      escaped += e;
      total += 800000;
    }
  }
  Mesh box;
  append_box(box, {-1, -2, -3}, {4, 5, 6}, -1, 0);
  escaped += count_escapes(box, Vec3(Real(0.5), Real(0.25), 0), 800000, bvh::BuildQuality::kSah);
  total += 800000;
  EXPECT_GE(total, 10000000);
  EXPECT_EQ(escaped, 0);
}

// Spatial splits chop references at planes through the triangles: the chopped parts' boxes must
// still hold every hit the watertight test reports, at every scale.
TEST(Watertight, SpatialSplitsAtManyScales) {
  const Placement cases[] = {
      {"unit", 1, 0}, {"tiny", 1e-4, 0}, {"huge", 1e4, 0}, {"far-huge", 1e3, 1e4}};
  for (const Placement& c : cases) {
    Mesh m;
    const Vec3d center(c.offset, -0.5 * c.offset, 0.25 * c.offset);
    append_icosphere(m, center, c.scale, 3, -1, 0);
    const Vec3 inside(center + Vec3d(0.21, -0.13, 0.08) * c.scale);
    EXPECT_EQ(count_escapes(m, inside, 200000, bvh::BuildQuality::kSah, bvh::SpatialSplits::kOn), 0)
        << c.name;
  }
  const Mesh spot = read_mesh(std::string(scenes_dir()) + "/spot.obj");
  Vec3d c(0, 0, 0);
  for (const auto& p : spot.positions) c += p;
  c = c * (1.0 / double(spot.positions.size()));
  EXPECT_EQ(count_escapes(spot, Vec3(c), 400000, bvh::BuildQuality::kSah, bvh::SpatialSplits::kOn),
            0);
}

TEST(Watertight, SpotFromInside) {
  const Mesh spot = read_mesh(std::string(scenes_dir()) + "/spot.obj");
  Vec3d c(0, 0, 0);
  for (const auto& p : spot.positions) c += p;
  c = c * (1.0 / double(spot.positions.size()));
  EXPECT_EQ(count_escapes(spot, Vec3(c), 1000000, bvh::BuildQuality::kSah), 0);
}

}  // namespace
}  // namespace rtmini::test
