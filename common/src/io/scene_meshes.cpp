#include <cmath>
#include <map>

#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/scene_file.hpp"

namespace rtmini {
namespace {

// Row-major 3x3 rotation R = Rz * Ry * Rx: rotate about x first, then y, then z.
struct Rotation {
  double m[3][3];
  explicit Rotation(const Vec3d& deg) {
    constexpr double kDegToRad = math::kPi / 180.0;
    const double cx = std::cos(deg.x * kDegToRad), sx = std::sin(deg.x * kDegToRad);
    const double cy = std::cos(deg.y * kDegToRad), sy = std::sin(deg.y * kDegToRad);
    const double cz = std::cos(deg.z * kDegToRad), sz = std::sin(deg.z * kDegToRad);
    const double r[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                            {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                            {-sy, cy * sx, cy * cx}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = r[i][j];
  }
  Vec3d apply(const Vec3d& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z,
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z,
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z};
  }
};

}  // namespace

// Every [[meshes]] entry is appended to one Mesh: its vertex, object and material indices are
// offset by what came before, so faces keep pointing at their own mesh's entries.
Mesh load_scene_meshes(const SceneDescription& scene, std::vector<int>* first_object) {
  Mesh out;
  std::map<std::string, const MaterialOverride*> overrides;
  for (const MaterialOverride& m : scene.materials) overrides[m.name] = &m;

  for (const MeshDesc& desc : scene.meshes) {
    Mesh mesh = read_mesh(desc.file);
    const Rotation rotation(desc.rotate_deg);
    const int vertex_base = static_cast<int>(out.positions.size());
    const int object_base = static_cast<int>(out.objects.size());
    const int material_base = static_cast<int>(out.materials.size());
    const int texcoord_base = static_cast<int>(out.texcoords.size());
    out.texcoords.insert(out.texcoords.end(), mesh.texcoords.begin(), mesh.texcoords.end());
    if (first_object) first_object->push_back(object_base);
    // Scale, rotate, then translate: size and orientation in the mesh's own frame, then place it.
    for (const Vec3d& p : mesh.positions)
      out.positions.push_back(rotation.apply(p * desc.scale) + desc.translate);
    out.objects.insert(out.objects.end(), mesh.objects.begin(), mesh.objects.end());
    // A mesh without object names still gets one, so `f.object + object_base` below is valid.
    if (mesh.objects.empty()) out.objects.push_back("default");

    // `material = "name"` on the mesh replaces all of its materials by that one; otherwise the
    // mesh keeps its own, each patched by a [[materials]] entry of the same name if any. at():
    // scene_file.cpp has checked that the name exists.
    int replacement = -1;
    if (!desc.material.empty()) {
      replacement = material_base;
      out.materials.push_back(make_material(*overrides.at(desc.material)));
    } else {
      // A height field's height is in the mesh's units: it scales with the mesh (by the
      // geometric mean of a non-uniform scale).
      const double height_scale = std::cbrt(std::fabs(desc.scale.x * desc.scale.y * desc.scale.z));
      for (Material m : mesh.materials) {
        if (const auto it = overrides.find(m.name); it != overrides.end())
          apply_material_override(*it->second, m);
        m.maps.displacement_scale *= static_cast<float>(height_scale);
        out.materials.push_back(m);
      }
    }
    for (Face f : mesh.faces) {
      for (int k = 0; k < f.count; ++k) {
        f.v[k] += vertex_base;
        if (f.uv[k] >= 0) f.uv[k] += texcoord_base;
      }
      f.object += object_base;
      if (replacement >= 0) {
        f.material = replacement;
      } else if (f.material >= 0) {
        f.material += material_base;
      }
      out.faces.push_back(f);
    }
  }
  return out;
}

}  // namespace rtmini
