#pragma once
// What the bake needs beyond the mesh, prepared once on the host and uploaded once: per-vertex
// normal and material (the seed's averages over adjacent faces), the area lights (emissive
// faces), and the layout of the colour map (N colours for a reflective vertex, 1 otherwise).
#include <cstdint>
#include <vector>

#include "rtmini/scene/device_mesh.hpp"

namespace rtmini::bake {

using MemSpace = Kokkos::DefaultExecutionSpace::memory_space;

// An emissive face: one or two triangles (a quad), picked in proportion to their areas.
struct AreaLight {
  int tri[2] = {-1, -1};
  Real first_fraction = 1;  // area of tri[0] / total area
  Real area = 0;
  Vec3 normal;  // emitting side (the face's winding normal)
  Vec3 emission;
};

struct BakeSceneHost {
  std::vector<Vec3> normal;  // zero for a vertex on no face
  std::vector<Vec3> diffuse, reflective, emissive;
  std::vector<std::int64_t> color_offset;  // vertices + 1 entries
  std::vector<AreaLight> lights;
  std::int64_t reflective_vertices = 0;
  bool any_diffuse = false;

  std::int64_t vertices() const { return static_cast<std::int64_t>(normal.size()); }
  std::int64_t colors() const { return color_offset.back(); }
  std::int64_t color_count(std::int64_t v) const { return color_offset[v + 1] - color_offset[v]; }
};

// Area-weighted normals (each face adds its area-scaled normal to its corners) and plain
// averages of the adjacent faces' materials (faces without a material are skipped).
// all_view_dependent (measurement only) gives every vertex N colours, as if none could keep one.
BakeSceneHost prepare_bake_scene(const Mesh& mesh, int viewpoints, bool all_view_dependent = false);

struct BakeSceneDevice {
  DeviceMesh<MemSpace> mesh;
  Kokkos::View<Vec3*, MemSpace> normal, diffuse, reflective, emissive;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<AreaLight*, MemSpace> lights;
  Kokkos::View<Vec3*, MemSpace> viewpoints;  // the N Fibonacci directions
};

BakeSceneDevice upload_bake_scene(const Mesh& mesh, const BakeSceneHost& host, int viewpoints,
                                  bvh::BuildQuality quality);

// Bytes the device and host buffers will take (printed before anything large is allocated).
struct MemoryEstimate {
  std::int64_t scene = 0, maps = 0, hit_cache = 0, host = 0;
  std::int64_t total() const { return scene + maps + hit_cache + host; }
};

}  // namespace rtmini::bake
