#include "device_scene.hpp"

namespace rtmini::ao {

DeviceScene::DeviceScene(const AoScene& scene, bvh::BuildQuality quality,
                         const GroundPlane& ground) {
  ExecSpace space;
  Kokkos::View<BvhRef*, MemSpace> refs("rtmini::bake::ao::mesh_bvhs", scene.meshes.size());
  auto refs_h = Kokkos::create_mirror_view(refs);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const AoMesh& mesh = scene.meshes[m];
    Kokkos::View<Triangle*, MemSpace> tris("rtmini::bake::ao::object_tris", mesh.tris.size());
    auto tris_h = Kokkos::create_mirror_view(tris);
    for (std::size_t t = 0; t < mesh.tris.size(); ++t) {
      const auto& v = mesh.tris[t];
      tris_h(t) = {Vec3(mesh.positions[v[0]]), Vec3(mesh.positions[v[1]]),
                   Vec3(mesh.positions[v[2]])};
    }
    Kokkos::deep_copy(tris, tris_h);
    // AO asks any-hit queries only, which trace the binary tree: no wide copy to build.
    bvhs_.push_back(
        bvh::build<ExecSpace, MemSpace>(space, tris, quality, bvh::QuantizedWide::kNever));
    const auto& b = bvhs_.back();
    refs_h(m).nodes = {b.nodes.data(), b.nodes.extent(0)};
    refs_h(m).wide = {b.wide.data(), b.wide.extent(0)};
    refs_h(m).leaves = {b.leaves.data(), b.leaves.extent(0)};
    refs_h(m).tris = {b.tris.data(), b.tris.extent(0)};
    refs_h(m).prim = {b.prim.data(), b.prim.extent(0)};
    refs_h(m).num_prims = b.num_prims;
    bytes_ += b.nodes.span() * sizeof(bvh::BvhNode) + b.wide.span() * sizeof(bvh::WideNode) +
              b.leaves.span() * sizeof(bvh::TriangleLanes) + b.tris.span() * sizeof(Triangle) +
              b.prim.span() * sizeof(int);
  }
  Kokkos::deep_copy(refs, refs_h);

  Kokkos::View<DeviceInstance*, MemSpace> insts("rtmini::bake::ao::instances",
                                                scene.instances.size());
  auto insts_h = Kokkos::create_mirror_view(insts);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const AoInstance& in = scene.instances[i];
    const Bounds wb = scene.instance_bounds(static_cast<int>(i));
    DeviceInstance& d = insts_h(i);
    d.mesh = in.mesh;
    d.identity = is_identity(in.xform) ? 1 : 0;
    d.to_object = inverse(in.xform).cast<Real>();
    // Round the box outward by a relative margin so float conversion never shrinks it.
    const Vec3d pad = (wb.hi - wb.lo) * 1e-6 + Vec3d(1e-30);
    d.lo = Vec3(wb.lo - pad);
    d.hi = Vec3(wb.hi + pad);
  }
  Kokkos::deep_copy(insts, insts_h);
  bytes_ += refs.span() * sizeof(BvhRef) + insts.span() * sizeof(DeviceInstance);

  query_.meshes = refs;
  query_.instances = insts;
  query_.ground = ground;
  query_.num_instances = static_cast<int>(scene.instances.size());
}

}  // namespace rtmini::ao
