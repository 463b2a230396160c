#pragma once
// TOML scene descriptions (toml++). Layout, every key optional unless noted:
//
//   ambient = [r, g, b]
//   [camera]    position, look_at, up ([3]), fov_deg, aperture, focus_distance (0 = distance
//               to look_at), shutter_open, shutter_close, velocity ([3], units per shutter time)
//   [[lights]]  type = "quad" (corner, edge_u, edge_v, emission) | "point" (position,
//               intensity) | "sphere" (center, radius, emission); all fields required
//   [[materials]] name (required) + any of kd, ks, ke ([3]), ns, ni, d: overrides the fields
//               of every mesh material of that name; also the target of a mesh `material`
//   [[meshes]]  file (required, relative to the TOML file's folder: .obj, .bs, .gltf, .glb; a
//               glTF is flattened through its node transforms first), translate [3],
//               rotate_deg [3] (XYZ Euler: about x, then y, then z), scale (number or [3]),
//               material (name of a [[materials]] entry, replaces all the mesh's materials)
//   [[spheres]] center, radius (required), material = { kd, ks, ke, ns, ni, d }
//   [[meshes]] and [[spheres]] may also move (object motion blur, sketchtrace): velocity [3]
//               (units per time, as the camera's), spin_axis [3] and spin_deg (degrees per
//               time about that axis through the object's centre: a sphere's centre, a mesh's
//               placed bounding-box centre). The file gives each object at time 0; a ray at
//               shutter time t sees it moved by velocity * t and turned by spin_deg * t.
//   [settings]  passed through; each app checks its own keys with check_known_keys
//
// Unknown keys, wrong types, bad values and missing mesh files are InputErrors
// "file:line: reason" pointing at the offending TOML line.
//
// This header does not include toml++ (nvcc cannot parse it), so device code may include
// it; the [settings] table is reached through io/scene_settings.hpp in host-only files.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini {

struct CameraDesc {
  Vec3d position{0.0, 0.0, 1.0};
  Vec3d look_at{0.0, 0.0, 0.0};
  Vec3d up{0.0, 1.0, 0.0};
  double fov_deg = 45.0;  // vertical field of view
  double aperture = 0.0;  // lens diameter; 0 = pinhole
  double focus_distance = 0.0;
  double shutter_open = 0.0;
  double shutter_close = 0.0;
  Vec3d velocity{0.0, 0.0, 0.0};
};

enum class LightType { kQuad, kPoint, kSphere };

// Fields not used by a type keep their zero defaults.
struct LightDesc {
  LightType type = LightType::kPoint;
  Vec3d corner, edge_u, edge_v;  // quad
  Vec3d position;                // point
  Vec3f intensity;               // point
  Vec3d center;                  // sphere
  double radius = 0.0;           // sphere
  Vec3f emission;                // quad, sphere
  long line = 0;
};

struct MaterialOverride {
  std::string name;
  std::optional<Vec3f> kd, ks, ke;
  std::optional<float> ns, ni, d;
  long line = 0;
};

// Rigid motion of one object over time (see the layout above); zero = still.
struct ObjectMotion {
  Vec3d velocity{0.0, 0.0, 0.0};
  Vec3d spin_axis{0.0, 1.0, 0.0};
  double spin_deg = 0.0;  // per unit time
  bool moves() const { return spin_deg != 0.0 || length_squared(velocity) > 0.0; }
};

struct MeshDesc {
  std::string file;  // resolved against the TOML file's folder
  Vec3d translate{0.0, 0.0, 0.0};
  Vec3d rotate_deg{0.0, 0.0, 0.0};
  Vec3d scale{1.0, 1.0, 1.0};
  std::string material;  // empty = keep the file's materials
  ObjectMotion motion;
  long line = 0;
};

struct SphereDesc {
  Vec3d center;
  double radius = 1.0;
  Material material;
  ObjectMotion motion;
  long line = 0;
};

// The raw [settings] table (defined in io/scene_settings.hpp).
struct SceneSettings;

struct SceneDescription {
  std::string path;  // the TOML file, for error messages
  bool has_camera = false;
  CameraDesc camera;
  std::vector<LightDesc> lights;
  std::vector<MaterialOverride> materials;
  std::vector<MeshDesc> meshes;
  std::vector<SphereDesc> spheres;
  Vec3f ambient{0.f, 0.f, 0.f};
  std::shared_ptr<const SceneSettings> settings;  // never null after read_scene_file
};

// Parses and validates a scene file; InputError "file:line: reason" on any problem.
SceneDescription read_scene_file(const std::string& path);

// Material{} defaults with the override's fields applied.
Material make_material(const MaterialOverride& fields);
// Overwrites the fields the override sets.
void apply_material_override(const MaterialOverride& fields, Material& material);

// Reads every mesh (read_mesh), applies scale, rotation, translation (in that order),
// and appends them into one Mesh: object ids stay distinct, material indices are
// offset, [[materials]] overrides apply by name, a mesh `material` replaces its faces'
// materials. Viewpoint colours of .bs inputs are dropped (scenes carry geometry only).
// With first_object, also the id of each [[meshes]] entry's first object (its objects run
// up to the next entry's first).
Mesh load_scene_meshes(const SceneDescription& scene, std::vector<int>* first_object = nullptr);

}  // namespace rtmini
