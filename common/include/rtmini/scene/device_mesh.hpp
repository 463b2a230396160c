#pragma once
// A mesh uploaded once to the default memory space, struct-of-arrays per
// triangle, shared by both apps' kernels (docs/architecture.md §2).
#include <vector>

#include "rtmini/bvh/build.hpp"
#include "rtmini/scene/mesh.hpp"
#include "rtmini/scene/recentre.hpp"

namespace rtmini {

struct DeviceMaterial {
  Vec3 diffuse, reflective, emissive;
  Real shininess, ior, opacity;
};

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
struct DeviceMesh {
  Kokkos::View<Vec3*, MemorySpace> positions;
  Kokkos::View<Triangle*, MemorySpace> tris;         // original triangle order
  Kokkos::View<int* [3], MemorySpace> tri_vertices;  // vertex ids of each triangle
  Kokkos::View<int*, MemorySpace> tri_face;          // polygon (quad) id
  Kokkos::View<int*, MemorySpace> tri_material;      // -1 = none
  Kokkos::View<int*, MemorySpace> tri_object;
  Kokkos::View<DeviceMaterial*, MemorySpace> materials;
  bvh::Bvh<MemorySpace> accel;
  // The kernels' frame: world position = device position + origin (geometry/offset.hpp).
  Vec3d origin{0.0};
  // The largest |coordinate| of any vertex in that frame: sizes ray-origin offsets.
  Real coordinate_bound = 0;
};

inline DeviceMaterial to_device(const Material& m) {
  return {Vec3(m.diffuse),   Vec3(m.reflective), Vec3(m.emissive),
          Real(m.shininess), Real(m.ior),        Real(m.opacity)};
}

// Bytes upload_mesh takes at its peak for `triangles` triangles over `vertices` vertices:
// the mesh tables and the BVH (bvh_bytes: up to 2 nodes per triangle, the triangles again in
// leaf order, plus the largest device build's temporaries, PLOC's - per node a box, cost,
// count, parent and children; per cluster two ids, two boxes, a neighbour and a scan slot;
// Morton codes and order - freed after the build but counted towards the peak). For the
// up-front memory check (report/memory_check.hpp), before anything is uploaded.
inline double bvh_bytes(std::size_t triangles) {
  const double nt = static_cast<double>(triangles);
  const double bvh = 2 * nt * sizeof(bvh::BvhNode) + nt * (sizeof(Triangle) + sizeof(int));
  const double build =
      2 * nt * (sizeof(Aabb) + sizeof(Real) + 4 * sizeof(int)) +
      nt * (3 * sizeof(int) + 2 * sizeof(Aabb) + sizeof(std::uint64_t) + 2 * sizeof(std::uint32_t));
  return bvh + build;
}
inline double device_mesh_bytes(std::size_t triangles, std::size_t vertices) {
  const double nt = static_cast<double>(triangles), nv = static_cast<double>(vertices);
  return nv * sizeof(Vec3) + nt * (sizeof(Triangle) + 6 * sizeof(int)) + bvh_bytes(triangles);
}

// bvh_triangles: only triangles [0, bvh_triangles) go into the BVH (sketchtrace keeps its
// moving objects, placed last, in trees of their own); all of them by default.
template <class ExecSpace = Kokkos::DefaultExecutionSpace>
DeviceMesh<typename ExecSpace::memory_space> upload_mesh(
    const Mesh& mesh, bvh::BuildQuality quality, const ExecSpace& space = ExecSpace(),
    const Vec3d& origin = Vec3d(0.0), std::size_t bvh_triangles = ~std::size_t(0)) {
  using MS = typename ExecSpace::memory_space;
  DeviceMesh<MS> d;
  const TriangleList tl = triangulate(mesh);
  const std::size_t nt = tl.vertices.size(), nv = mesh.positions.size();
  d.positions = Kokkos::View<Vec3*, MS>("rtmini::scene::positions", nv);
  d.tris = Kokkos::View<Triangle*, MS>("rtmini::scene::tris", nt);
  d.tri_vertices = Kokkos::View<int* [3], MS>("rtmini::scene::tri_vertices", nt);
  d.tri_face = Kokkos::View<int*, MS>("rtmini::scene::tri_face", nt);
  d.tri_material = Kokkos::View<int*, MS>("rtmini::scene::tri_material", nt);
  d.tri_object = Kokkos::View<int*, MS>("rtmini::scene::tri_object", nt);
  d.materials =
      Kokkos::View<DeviceMaterial*, MS>("rtmini::scene::materials", mesh.materials.size());
  auto hp = Kokkos::create_mirror_view(d.positions);
  auto ht = Kokkos::create_mirror_view(d.tris);
  auto hv = Kokkos::create_mirror_view(d.tri_vertices);
  auto hf = Kokkos::create_mirror_view(d.tri_face);
  auto hm = Kokkos::create_mirror_view(d.tri_material);
  auto ho = Kokkos::create_mirror_view(d.tri_object);
  auto hmat = Kokkos::create_mirror_view(d.materials);
  // Moved in double, then rounded once.
  for (std::size_t i = 0; i < nv; ++i) hp(i) = Vec3(mesh.positions[i] - origin);
  d.origin = origin;
  d.coordinate_bound = Real(bounds_of(mesh.positions).bound_about(origin));
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = tl.vertices[t];
    const Face& f = mesh.faces[tl.face[t]];
    ht(t) = {hp(v[0]), hp(v[1]), hp(v[2])};
    for (int k = 0; k < 3; ++k) hv(t, k) = v[k];
    hf(t) = tl.face[t];
    hm(t) = f.material;
    ho(t) = f.object;
  }
  for (std::size_t m = 0; m < mesh.materials.size(); ++m) hmat(m) = to_device(mesh.materials[m]);
  Kokkos::deep_copy(d.positions, hp);
  Kokkos::deep_copy(d.tris, ht);
  Kokkos::deep_copy(d.tri_vertices, hv);
  Kokkos::deep_copy(d.tri_face, hf);
  Kokkos::deep_copy(d.tri_material, hm);
  Kokkos::deep_copy(d.tri_object, ho);
  Kokkos::deep_copy(d.materials, hmat);
  if (bvh_triangles >= nt) {
    d.accel = bvh::build<ExecSpace, MS>(space, d.tris, quality);
  } else {
    Kokkos::View<Triangle*, MS> prefix("rtmini::scene::bvh_tris", bvh_triangles);
    Kokkos::deep_copy(space, prefix,
                      Kokkos::subview(d.tris, std::make_pair(std::size_t(0), bvh_triangles)));
    space.fence();
    d.accel = bvh::build<ExecSpace, MS>(space, prefix, quality);
  }
  return d;
}

}  // namespace rtmini
