// The receivers' world triangles, formed on the device from the stored meshes and the
// instance transforms (upload_plan), against the host's expansion of the same instances.
#include <gtest/gtest.h>

#include <cstring>

#include "ao_test_util.hpp"
#include "ao_trace.hpp"

namespace rtmini::ao {
namespace {

// Two stored meshes, each received by several instances under rotations, non-uniform scales
// and translations far from the origin (so the world coordinates are not the object ones),
// an empty receiver between them, and a blocker that must get no triangles.
AoScene mixed_instances() {
  AoScene scene;
  Mesh shapes;
  append_grid(shapes, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 9, 7, -1, 0);
  append_icosphere(shapes, {0.1, 0.75, -0.3}, 0.7, 2, -1, 0);
  test::add_instance(scene, shapes);
  AoInstance turned = scene.instances[0];
  turned.xform = make_trs({5.3, -1.7, 1e3 / 3}, {13, 47, -71}, {1, 1, 1});
  scene.instances.push_back(turned);
  test::add_instance(scene, Mesh{});  // a receiver without triangles
  test::add_instance(scene, test::quad_mesh({-3, 2, -3}, {6, 0, 0}, {0, 0, 6}), AffineD{}, true);
  const int disk = test::add_instance(scene, test::disk_mesh(0.9, 0.2, 37),
                                      make_trs({-7.1, 0.3, 2.9}, {90, 0, 33}, {0.3, 2.5, 1.7}));
  AoInstance squashed = scene.instances[disk];
  squashed.xform = make_trs({0.7, 11.9, -4.4}, {-5, 170, 8}, {1.9, 0.04, 1.1});
  scene.instances.push_back(squashed);
  scene.instances.push_back(turned);  // a receiver after the disk's, on the first mesh again
  return scene;
}

TEST(AoExpand, DeviceWorldTrianglesEqualTheHostExpansionBitForBit) {
  const AoScene scene = mixed_instances();
  const SamplePlan plan = plan_samples(scene, 5000, 2);
  ASSERT_EQ(plan.receivers.size(), 6u);  // the blocker receives nothing
  ASSERT_EQ(plan.tri_base[2], plan.tri_base[3]);
  const DeviceSamplePlan d = upload_plan(scene, plan);
  ASSERT_EQ(static_cast<std::int64_t>(d.tris.extent(0)), plan.total_triangles());
  const auto tris = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.tris);
  const auto items = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.items);
  const auto keys = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.ray_keys);
  const auto offsets = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.offsets);
  std::int64_t differ = 0;
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& inst = scene.instances[plan.receivers[r]];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    for (std::int64_t g = plan.tri_base[r]; g < plan.tri_base[r + 1]; ++g) {
      const auto& t = mesh.tris[g - plan.tri_base[r]];
      const Triangle host{Vec3(inst.xform.point(mesh.positions[t[0]])),
                          Vec3(inst.xform.point(mesh.positions[t[1]])),
                          Vec3(inst.xform.point(mesh.positions[t[2]]))};
      if (std::memcmp(&host, &tris(g), sizeof(Triangle)) != 0 && differ++ < 5)
        ADD_FAILURE() << "receiver " << r << " triangle " << g << ": device (" << tris(g).a.x
                      << ", " << tris(g).a.y << ", " << tris(g).a.z << ") host (" << host.a.x
                      << ", " << host.a.y << ", " << host.a.z << ")";
      EXPECT_EQ(items(g), plan.item(r, g));
      EXPECT_EQ(keys(g), static_cast<std::uint32_t>(plan.receivers[r]));
    }
  }
  EXPECT_EQ(differ, 0) << "triangles whose bits differ";
  ASSERT_EQ(offsets.extent(0), plan.offsets.size());
  for (std::size_t g = 0; g < plan.offsets.size(); ++g) EXPECT_EQ(offsets(g), plan.offsets[g]);
}

}  // namespace
}  // namespace rtmini::ao
