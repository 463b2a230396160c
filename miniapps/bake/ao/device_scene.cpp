#include "device_scene.hpp"

#include <array>
#include <utility>

namespace rtmini::ao {
namespace detail {

// Stored mesh m's triangles in object space, rounded to Real: the BVH build's input.
Kokkos::View<Triangle*, MemSpace> object_triangles(const StoredMeshes& meshes, std::size_t m) {
  const std::int64_t vb = meshes.vertex_base[m], tb = meshes.tri_base[m];
  Kokkos::View<Triangle*, MemSpace> tris(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::object_tris"),
      meshes.tri_base[m + 1] - tb);
  const auto positions = meshes.positions;
  const auto corners = meshes.corners;
  Kokkos::parallel_for(
      "rtmini::bake::ao::object_triangles",
      Kokkos::RangePolicy<ExecSpace>(0, static_cast<std::int64_t>(tris.extent(0))),
      KOKKOS_LAMBDA(std::int64_t t) {
        const std::int64_t c = 3 * (tb + t);
        tris(t) = {Vec3(positions(vb + corners(c))), Vec3(positions(vb + corners(c + 1))),
                   Vec3(positions(vb + corners(c + 2)))};
      });
  return tris;
}

}  // namespace detail

StoredMeshes upload_meshes(const AoScene& scene) {
  static_assert(sizeof(std::array<int, 3>) == 3 * sizeof(int), "AoMesh::tris must be packed");
  StoredMeshes d;
  d.vertex_base.assign(1, 0);
  d.tri_base.assign(1, 0);
  for (const AoMesh& mesh : scene.meshes) {
    d.vertex_base.push_back(d.vertex_base.back() +
                            static_cast<std::int64_t>(mesh.positions.size()));
    d.tri_base.push_back(d.tri_base.back() + static_cast<std::int64_t>(mesh.tris.size()));
  }
  // Every element is copied in below: no zero fill first.
  d.positions = Kokkos::View<Vec3d*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::mesh_positions"),
      d.vertex_base.back());
  d.corners = Kokkos::View<int*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::mesh_corners"),
      3 * d.tri_base.back());
  // Straight from the host vectors into their places: no mirror to allocate and fill.
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const AoMesh& mesh = scene.meshes[m];
    Kokkos::deep_copy(
        Kokkos::subview(d.positions, std::make_pair(d.vertex_base[m], d.vertex_base[m + 1])),
        compat::host_view(mesh.positions.data(), mesh.positions.size()));
    Kokkos::deep_copy(
        Kokkos::subview(d.corners, std::make_pair(3 * d.tri_base[m], 3 * d.tri_base[m + 1])),
        compat::host_view(reinterpret_cast<const int*>(mesh.tris.data()), 3 * mesh.tris.size()));
  }
  return d;
}

DeviceScene::DeviceScene(const AoScene& scene, bvh::BuildQuality quality, const GroundPlane& ground)
    : meshes_(upload_meshes(scene)) {
  ExecSpace space;
  Kokkos::View<BvhRef*, MemSpace> refs("rtmini::bake::ao::mesh_bvhs", scene.meshes.size());
  auto refs_h = Kokkos::create_mirror_view(refs);
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Kokkos::View<Triangle*, MemSpace> tris = detail::object_triangles(meshes_, m);
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
  bytes_ += refs.span() * sizeof(BvhRef) + insts.span() * sizeof(DeviceInstance) +
            meshes_.positions.span() * sizeof(Vec3d) + meshes_.corners.span() * sizeof(int);

  query_.meshes = refs;
  query_.instances = insts;
  query_.ground = ground;
  query_.num_instances = static_cast<int>(scene.instances.size());
}

}  // namespace rtmini::ao
