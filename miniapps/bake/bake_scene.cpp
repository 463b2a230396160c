#include "bake_scene.hpp"

#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {

BakeSceneHost prepare_bake_scene(const Mesh& mesh, int viewpoints, bool all_view_dependent) {
  const std::size_t nv = mesh.positions.size();
  BakeSceneHost s;
  std::vector<Vec3d> normal(nv, Vec3d(0.0));
  std::vector<Vec3d> kd(nv, Vec3d(0.0)), kr(nv, Vec3d(0.0)), ke(nv, Vec3d(0.0));
  std::vector<int> faces_with_material(nv, 0);
  const TriangleList tl = triangulate(mesh);
  std::vector<int> first_tri(mesh.faces.size(), -1);
  for (std::size_t t = 0; t < tl.face.size(); ++t)
    if (first_tri[tl.face[t]] < 0) first_tri[tl.face[t]] = static_cast<int>(t);

  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Face& face = mesh.faces[f];
    const Vec3d& a = mesh.positions[face.v[0]];
    // Twice the area times the unit normal; a quad is the sum of its two triangles.
    Vec3d area_normal = cross(mesh.positions[face.v[1]] - a, mesh.positions[face.v[2]] - a);
    if (face.count == 4)
      area_normal += cross(mesh.positions[face.v[2]] - a, mesh.positions[face.v[3]] - a);
    const Material* m = face.material >= 0 ? &mesh.materials[face.material] : nullptr;
    for (int k = 0; k < face.count; ++k) {
      const int v = face.v[k];
      normal[v] += area_normal;
      if (!m) continue;
      kd[v] += Vec3d(m->diffuse);
      kr[v] += Vec3d(m->reflective);
      ke[v] += Vec3d(m->emissive);
      ++faces_with_material[v];
    }
    if (m && m->is_emissive()) {
      AreaLight light;
      const int t0 = first_tri[f];
      auto tri_area = [&](int t) {
        const auto& tv = tl.vertices[t];
        return 0.5 * length(cross(mesh.positions[tv[1]] - mesh.positions[tv[0]],
                                  mesh.positions[tv[2]] - mesh.positions[tv[0]]));
      };
      const double a0 = tri_area(t0);
      const double a1 = face.count == 4 ? tri_area(t0 + 1) : 0.0;
      if (a0 + a1 <= 0.0) continue;  // degenerate: emits nothing
      light.tri[0] = t0;
      light.tri[1] = face.count == 4 ? t0 + 1 : -1;
      light.first_fraction = Real(a0 / (a0 + a1));
      light.area = Real(a0 + a1);
      light.normal = Vec3(normalize(area_normal));
      light.emission = Vec3(m->emissive);
      s.lights.push_back(light);
    }
  }

  s.normal.resize(nv);
  s.diffuse.resize(nv);
  s.reflective.resize(nv);
  s.emissive.resize(nv);
  s.color_offset.assign(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    s.normal[v] = Vec3(normalize(normal[v]));
    const double inv = faces_with_material[v] > 0 ? 1.0 / faces_with_material[v] : 0.0;
    s.diffuse[v] = Vec3(kd[v] * inv);
    s.reflective[v] = Vec3(kr[v] * inv);
    s.emissive[v] = Vec3(ke[v] * inv);
    // A vertex with no usable normal cannot reflect anything: keep it view-independent.
    const bool reflective =
        max_component(s.reflective[v]) > Real(0) && length_squared(s.normal[v]) > Real(0);
    if (reflective) ++s.reflective_vertices;
    if (max_component(s.diffuse[v]) > Real(0)) s.any_diffuse = true;
    s.color_offset[v + 1] = s.color_offset[v] + (reflective || all_view_dependent ? viewpoints : 1);
  }
  return s;
}

namespace {
template <class T>
Kokkos::View<T*, MemSpace> upload(const char* label, const std::vector<T>& host) {
  return compat::upload<MemSpace>(label, host);
}
}  // namespace

BakeSceneDevice upload_bake_scene(const Mesh& mesh, const BakeSceneHost& host, int viewpoints,
                                  bvh::BuildQuality quality) {
  BakeSceneDevice d;
  // The kernels' frame is centred on the mesh (geometry/offset.hpp); the output keeps the
  // host mesh's world positions.
  d.mesh = upload_mesh(mesh, quality, Kokkos::DefaultExecutionSpace(),
                       bounds_of(mesh.positions).centre());
  d.normal = upload("rtmini::bake::normal", host.normal);
  d.diffuse = upload("rtmini::bake::diffuse", host.diffuse);
  d.reflective = upload("rtmini::bake::reflective", host.reflective);
  d.emissive = upload("rtmini::bake::emissive", host.emissive);
  d.color_offset = upload("rtmini::bake::color_offset", host.color_offset);
  d.lights = upload("rtmini::bake::lights", host.lights);
  d.viewpoints = fibonacci_points<MemSpace>(viewpoints);
  return d;
}

}  // namespace rtmini::bake
