#pragma once
// The scene as the render kernels see it: the shared DeviceMesh (triangles, BVH,
// materials) plus sketchtrace's shading tables (vertex normals, analytic-sphere
// objects) and light lists, all Views in the default memory space.
#include "moving_objects.hpp"
#include "render_scene.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "textures.hpp"

namespace rtmini::sketch {

using MemSpace = Kokkos::DefaultExecutionSpace::memory_space;

struct DeviceScene {
  DeviceMesh<MemSpace> mesh;
  Kokkos::View<Vec3*, MemSpace> shading_normals;   // per smoothing group (crease_normals.hpp)
  Kokkos::View<int* [3], MemSpace> corner_normal;  // shading normal id of each triangle corner
  Kokkos::View<ObjectShading*, MemSpace> objects;
  Kokkos::View<QuadLight*, MemSpace> quads;
  Kokkos::View<PointLight*, MemSpace> points;
  Kokkos::View<MeshLight*, MemSpace> mesh_lights;
  Kokkos::View<int*, MemSpace> emissive_tris;  // triangle ids grouped by light
  Kokkos::View<Real*, MemSpace> emissive_cdf;  // cumulative area within each light, in (0, 1]
  Kokkos::View<SolidBall*, MemSpace> solid_balls;
  SurfaceMaps<MemSpace> maps;     // image maps; maps.any false (nothing allocated) without any
  DeviceMotion<MemSpace> motion;  // moving objects (empty: a still scene)
  // Per mesh object: the light that samples its emission (quad index, num_quads + mesh-light
  // index) or -1; a BSDF-sampled ray that hits emission weighs it against that light's sampling.
  Kokkos::View<int*, MemSpace> light_of_object;
  int num_quads = 0, num_points = 0, num_mesh_lights = 0, num_solid_balls = 0;
  bool any_secondary = false;  // some material reflects or transmits
  bool any_glossy = false;     // some material has a glossy Phong lobe (0 < Ns < mirror)
  std::size_t triangles = 0;
  std::size_t bytes = 0;          // device memory estimate, textures included
  std::size_t texture_bytes = 0;  // of which image maps and per-triangle texture records
};

// Uploads the mesh (building the BVH with `quality`), the shading normals split at creases
// sharper than acos(cos_crease), and the light tables.
DeviceScene upload_scene(const HostScene& scene, bvh::BuildQuality quality, double cos_crease);

}  // namespace rtmini::sketch
