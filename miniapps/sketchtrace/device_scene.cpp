#include "device_scene.hpp"

#include <map>
#include <vector>

#include "crease_normals.hpp"
#include "moving_objects_host.hpp"
#include "shading.hpp"

namespace rtmini::sketch {
namespace {

// Texture-coordinate ids of each triangle's corners, in triangulate()'s order.
std::vector<std::array<int, 3>> corner_uv_ids(const Mesh& mesh) {
  std::vector<std::array<int, 3>> ids;
  ids.reserve(mesh.triangle_count());
  for (const Face& f : mesh.faces) {
    ids.push_back({f.uv[0], f.uv[1], f.uv[2]});
    if (f.count == 4) ids.push_back({f.uv[0], f.uv[2], f.uv[3]});
  }
  return ids;
}

}  // namespace

DeviceScene upload_scene(const HostScene& scene, bvh::BuildQuality quality, double cos_crease) {
  DeviceScene d;
  const TriangleList tl = triangulate(scene.mesh);
  d.triangles = tl.vertices.size();
  // Moving objects' faces come last (place_moving_objects_last): the still BVH stops there.
  std::size_t still = tl.vertices.size();
  if (!scene.movers.empty()) {
    std::vector<char> moving(scene.mesh.objects.size(), 0);
    for (const MoverDesc& m : scene.movers)
      for (int o = m.first_object; o < m.end_object; ++o) moving[o] = 1;
    still = 0;
    while (still < tl.vertices.size() && !moving[scene.mesh.faces[tl.face[still]].object]) ++still;
  }
  d.mesh = upload_mesh(scene.mesh, quality, Kokkos::DefaultExecutionSpace(), Vec3d(0.0), still);
  if (!scene.movers.empty()) d.motion = upload_motion(scene, tl, still, d.mesh.coordinate_bound);

  // Shading normals per triangle corner, split where faces meet at more than the crease angle.
  const CornerNormals corners = crease_split_normals(scene.mesh.positions, tl.vertices, cos_crease);
  std::vector<Vec3> normals(corners.normals.begin(), corners.normals.end());
  d.shading_normals = compat::upload<MemSpace>("rtmini::sketch::shading_normals", normals);
  d.corner_normal =
      Kokkos::View<int* [3], MemSpace>("rtmini::sketch::corner_normal", tl.vertices.size());
  auto corner_host = Kokkos::create_mirror_view(d.corner_normal);
  for (std::size_t t = 0; t < tl.vertices.size(); ++t)
    for (int k = 0; k < 3; ++k) corner_host(t, k) = corners.of_corner[t][k];
  Kokkos::deep_copy(d.corner_normal, corner_host);
  d.maps = upload_surface_maps(scene.mesh, scene.map_images, tl.vertices, corner_uv_ids(scene.mesh),
                               corners.of_corner, normals);
  d.objects = compat::upload<MemSpace>("rtmini::sketch::objects", scene.objects);
  d.quads = compat::upload<MemSpace>("rtmini::sketch::quad_lights", scene.quads);
  d.points = compat::upload<MemSpace>("rtmini::sketch::point_lights", scene.points);

  // Emissive triangles grouped by object (one mesh light per object), quad lights excluded.
  std::map<int, std::vector<int>> by_object;
  for (std::size_t t = 0; t < tl.vertices.size(); ++t) {
    const Face& f = scene.mesh.faces[tl.face[t]];
    if (f.material < 0 || !scene.mesh.materials[f.material].is_emissive()) continue;
    if (scene.object_is_quad_light[f.object]) continue;
    by_object[f.object].push_back(static_cast<int>(t));
  }
  std::vector<MeshLight> lights;
  std::vector<int> light_of_object(scene.object_is_quad_light.size(), -1);
  int quad = 0;
  for (std::size_t o = 0; o < light_of_object.size(); ++o)
    if (scene.object_is_quad_light[o]) light_of_object[o] = quad++;
  std::vector<int> tris;
  std::vector<Real> cdf;
  for (const auto& [object, ids] : by_object) {
    std::vector<double> areas;
    double total = 0;
    for (int t : ids) {
      const auto& v = tl.vertices[t];
      const Vec3d& a = scene.mesh.positions[v[0]];
      areas.push_back(
          0.5 * length(cross(scene.mesh.positions[v[1]] - a, scene.mesh.positions[v[2]] - a)));
      total += areas.back();
    }
    if (!(total > 0)) continue;
    light_of_object[object] = static_cast<int>(scene.quads.size() + lights.size());
    MeshLight l{static_cast<int>(tris.size()), static_cast<int>(ids.size()), Real(total)};
    double run = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      run += areas[i];
      tris.push_back(ids[i]);
      cdf.push_back(i + 1 == ids.size() ? Real(1) : Real(run / total));
    }
    lights.push_back(l);
  }
  d.mesh_lights = compat::upload<MemSpace>("rtmini::sketch::mesh_lights", lights);
  d.emissive_tris = compat::upload<MemSpace>("rtmini::sketch::emissive_tris", tris);
  d.emissive_cdf = compat::upload<MemSpace>("rtmini::sketch::emissive_cdf", cdf);
  d.solid_balls = compat::upload<MemSpace>("rtmini::sketch::solid_balls", scene.solid_balls);
  d.light_of_object = compat::upload<MemSpace>("rtmini::sketch::light_of_object", light_of_object);
  d.num_solid_balls = static_cast<int>(scene.solid_balls.size());
  d.num_quads = static_cast<int>(scene.quads.size());
  d.num_points = static_cast<int>(scene.points.size());
  d.num_mesh_lights = static_cast<int>(lights.size());
  for (const Material& m : scene.mesh.materials) {
    if (m.is_reflective() || m.opacity < 1.f) d.any_secondary = true;
    if (is_glossy(Real(m.shininess))) d.any_glossy = true;
  }
  const std::size_t nt = d.triangles, nv = scene.mesh.positions.size();
  d.bytes = (nv + normals.size()) * sizeof(Vec3) + nt * (sizeof(Triangle) * 2 + 9 * sizeof(int)) +
            d.mesh.accel.nodes.extent(0) * sizeof(bvh::BvhNode) +
            tris.size() * (sizeof(int) + sizeof(Real)) + d.maps.bytes +
            d.motion.nodes.extent(0) * sizeof(bvh::BvhNode) +
            d.motion.tris.extent(0) * (sizeof(Triangle) + sizeof(int));
  d.texture_bytes = d.maps.bytes;
  return d;
}

}  // namespace rtmini::sketch
