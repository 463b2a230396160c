#include "rtmini/io/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/scene_settings.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini {
namespace {

long line_of(const toml::node& node) { return static_cast<long>(node.source().begin.line); }

// Reads typed values out of one TOML table, reporting errors at the value's line. Every check
// happens here, at parse time, so a bad scene is one "file:line: reason" (exit 2) before any
// rank has read a mesh or built a BVH.
class TableReader {
 public:
  TableReader(const toml::table& table, const std::string& file, std::string where)
      : table_(table), file_(file), where_(std::move(where)) {}

  [[noreturn]] void fail(long line, const std::string& reason) const {
    throw InputError(file_, line, reason);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    const toml::node* node = table_.get(key);
    fail(node ? line_of(*node) : line_of(table_), "'" + key + "' in " + where_ + " " + reason);
  }

  void known(std::initializer_list<std::string_view> keys) const {
    check_known_keys(table_, keys, file_, where_);
  }

  bool has(const std::string& key) const { return table_.contains(key); }
  const toml::node* node(const std::string& key) const { return table_.get(key); }
  long line() const { return line_of(table_); }

  void require(const std::string& key) const {
    if (!has(key)) fail(line(), "missing required key '" + key + "' in " + where_);
  }

  double number(const std::string& key, double fallback) const {
    const toml::node* n = table_.get(key);
    if (!n) return fallback;
    return number_value(*n, key);
  }

  Vec3d vec3(const std::string& key, const Vec3d& fallback) const {
    const toml::node* n = table_.get(key);
    if (!n) return fallback;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) fail(key, "must be an array of 3 numbers");
    return {number_value((*a)[0], key), number_value((*a)[1], key), number_value((*a)[2], key)};
  }

  Vec3f vec3f(const std::string& key, const Vec3f& fallback) const {
    return Vec3f(vec3(key, Vec3d(fallback)));
  }

  std::string string(const std::string& key, const std::string& fallback) const {
    const toml::node* n = table_.get(key);
    if (!n) return fallback;
    const auto s = n->value<std::string>();
    if (!n->is_string() || !s) fail(key, "must be a string");
    return *s;
  }

  const toml::table& table() const { return table_; }
  const std::string& file() const { return file_; }

 private:
  // TOML integers are accepted where a number is expected ("fov_deg = 40"): value<double>()
  // converts them. Finite and within Real, so nothing turns into inf on the device.
  double number_value(const toml::node& n, const std::string& key) const {
    if (!n.is_number()) fail(line_of(n), "'" + key + "' in " + where_ + " must be a number");
    const double v = *n.value<double>();
    if (!std::isfinite(v)) fail(line_of(n), "'" + key + "' in " + where_ + " must be finite");
    if (!detail::fits_real(v))
      fail(line_of(n), "'" + key + "' in " + where_ + " is beyond the " +
                           detail::real_range_name() + " range (must be finite once converted)");
    return v;
  }

  const toml::table& table_;
  const std::string& file_;
  std::string where_;
};

const toml::table& as_table(const toml::node& node, const std::string& file,
                            const std::string& what) {
  const toml::table* t = node.as_table();
  if (!t) throw InputError(file, line_of(node), what + " must be a table");
  return *t;
}

// Each element of an array of tables ([[name]]), with its line for errors.
template <class Fn>
void for_each_table(const toml::table& root, const char* key, const std::string& file, Fn fn) {
  const toml::node* node = root.get(key);
  if (!node) return;
  const toml::array* array = node->as_array();
  if (!array)
    throw InputError(file, line_of(*node), std::string("'") + key + "' must be an array of tables");
  for (const toml::node& element : *array)
    fn(as_table(element, file, std::string("each [[") + key + "]] entry"));
}

void require_non_negative(const TableReader& r, const std::string& key, const Vec3f& v) {
  if (v.x < 0.f || v.y < 0.f || v.z < 0.f) r.fail(key, "must not be negative");
}

void read_material_fields(const TableReader& r, MaterialOverride& m) {
  if (r.has("kd")) m.kd = r.vec3f("kd", {});
  if (r.has("ks")) m.ks = r.vec3f("ks", {});
  if (r.has("ke")) m.ke = r.vec3f("ke", {});
  if (r.has("ns")) m.ns = static_cast<float>(r.number("ns", 0.0));
  if (r.has("ni")) m.ni = static_cast<float>(r.number("ni", 1.0));
  if (r.has("d")) m.d = static_cast<float>(r.number("d", 1.0));
  for (const char* key : {"kd", "ks", "ke"})
    if (r.has(key)) require_non_negative(r, key, r.vec3f(key, {}));
  if (m.ni && *m.ni <= 0.f) r.fail("ni", "must be positive");
  if (m.d && (*m.d < 0.f || *m.d > 1.f)) r.fail("d", "must be in [0, 1]");
}

// velocity / spin_axis / spin_deg of a [[meshes]] or [[spheres]] entry.
ObjectMotion read_motion(const TableReader& r) {
  ObjectMotion m;
  m.velocity = r.vec3("velocity", m.velocity);
  m.spin_axis = r.vec3("spin_axis", m.spin_axis);
  m.spin_deg = r.number("spin_deg", m.spin_deg);
  if (length_squared(m.spin_axis) == 0.0) r.fail("spin_axis", "must not be zero");
  return m;
}

CameraDesc read_camera(const TableReader& r) {
  r.known({"position", "look_at", "up", "fov_deg", "aperture", "focus_distance", "shutter_open",
           "shutter_close", "velocity"});
  CameraDesc c;
  c.position = r.vec3("position", c.position);
  c.look_at = r.vec3("look_at", c.look_at);
  c.up = r.vec3("up", c.up);
  c.fov_deg = r.number("fov_deg", c.fov_deg);
  c.aperture = r.number("aperture", c.aperture);
  c.focus_distance = r.number("focus_distance", c.focus_distance);
  c.shutter_open = r.number("shutter_open", c.shutter_open);
  c.shutter_close = r.number("shutter_close", c.shutter_close);
  c.velocity = r.vec3("velocity", c.velocity);
  if (!(c.fov_deg > 0.0 && c.fov_deg < 180.0)) r.fail("fov_deg", "must be in (0, 180)");
  if (c.aperture < 0.0) r.fail("aperture", "must not be negative");
  if (c.focus_distance < 0.0) r.fail("focus_distance", "must not be negative");
  if (c.shutter_close < c.shutter_open) r.fail("shutter_close", "must not precede shutter_open");
  if (length_squared(c.position - c.look_at) == 0.0) r.fail("look_at", "must differ from position");
  // Exactly parallel only: make_camera() can still pick a roll then, but a scene that says so
  // is almost always a typo, and the message names the key.
  if (length_squared(cross(c.look_at - c.position, c.up)) == 0.0)
    r.fail("up", "must not be parallel to the view direction");
  return c;
}

LightDesc read_light(const TableReader& r) {
  r.require("type");
  const std::string type = r.string("type", "");
  LightDesc l;
  l.line = r.line();
  if (type == "quad") {
    r.known({"type", "corner", "edge_u", "edge_v", "emission"});
    for (const char* key : {"corner", "edge_u", "edge_v", "emission"}) r.require(key);
    l.type = LightType::kQuad;
    l.corner = r.vec3("corner", {});
    l.edge_u = r.vec3("edge_u", {});
    l.edge_v = r.vec3("edge_v", {});
    l.emission = r.vec3f("emission", {});
    if (length_squared(cross(l.edge_u, l.edge_v)) == 0.0)
      r.fail("edge_v", "must not be parallel to edge_u (zero-area light)");
    require_non_negative(r, "emission", l.emission);
  } else if (type == "point") {
    r.known({"type", "position", "intensity"});
    for (const char* key : {"position", "intensity"}) r.require(key);
    l.type = LightType::kPoint;
    l.position = r.vec3("position", {});
    l.intensity = r.vec3f("intensity", {});
    require_non_negative(r, "intensity", l.intensity);
  } else if (type == "sphere") {
    r.known({"type", "center", "radius", "emission"});
    for (const char* key : {"center", "radius", "emission"}) r.require(key);
    l.type = LightType::kSphere;
    l.center = r.vec3("center", {});
    l.radius = r.number("radius", 0.0);
    l.emission = r.vec3f("emission", {});
    if (!(l.radius > 0.0)) r.fail("radius", "must be positive");
    require_non_negative(r, "emission", l.emission);
  } else {
    r.fail("type", "must be \"quad\", \"point\" or \"sphere\", got \"" + type + "\"");
  }
  return l;
}

MeshDesc read_mesh_desc(const TableReader& r, const std::set<std::string>& material_names) {
  r.known({"file", "translate", "rotate_deg", "scale", "material", "velocity", "spin_axis",
           "spin_deg"});
  r.require("file");
  MeshDesc m;
  m.line = r.line();
  const std::string file = r.string("file", "");
  // Relative to the scene file, not to the working directory: a scene and its meshes move
  // together. Opened once here so a wrong path fails at its own line in the scene.
  m.file = !file.empty() && file.front() == '/' ? file : directory_prefix(r.file()) + file;
  if (!std::ifstream(m.file)) r.fail("file", "names a mesh that cannot be opened: " + m.file);
  m.translate = r.vec3("translate", m.translate);
  m.rotate_deg = r.vec3("rotate_deg", m.rotate_deg);
  if (const toml::node* scale = r.node("scale"); scale && scale->is_number()) {
    m.scale = Vec3d(r.number("scale", 1.0));
  } else {
    m.scale = r.vec3("scale", m.scale);
  }
  if (m.scale.x == 0.0 || m.scale.y == 0.0 || m.scale.z == 0.0) r.fail("scale", "must be non-zero");
  m.material = r.string("material", "");
  if (!m.material.empty() && material_names.count(m.material) == 0)
    r.fail("material", "names no [[materials]] entry: '" + m.material + "'");
  m.motion = read_motion(r);
  return m;
}

SphereDesc read_sphere(const TableReader& r) {
  r.known({"center", "radius", "material", "velocity", "spin_axis", "spin_deg"});
  r.require("center");
  r.require("radius");
  SphereDesc s;
  s.line = r.line();
  s.center = r.vec3("center", {});
  s.radius = r.number("radius", 1.0);
  if (!(s.radius > 0.0)) r.fail("radius", "must be positive");
  s.motion = read_motion(r);
  if (const toml::node* node = r.node("material")) {
    const TableReader mr(as_table(*node, r.file(), "'material' in [[spheres]]"), r.file(),
                         "[[spheres]].material");
    mr.known({"kd", "ks", "ke", "ns", "ni", "d"});
    MaterialOverride fields;
    read_material_fields(mr, fields);
    s.material = make_material(fields);
  }
  return s;
}

}  // namespace

// An unknown key is an error, not ignored: a misspelt "fov_degs" would otherwise silently leave
// the default in place.
void check_known_keys(const toml::table& table, std::initializer_list<std::string_view> known,
                      const std::string& file, const std::string& where) {
  for (const auto& [key, value] : table) {
    if (std::find(known.begin(), known.end(), key.str()) == known.end()) {
      const long line =
          key.source().begin.line > 0 ? static_cast<long>(key.source().begin.line) : line_of(value);
      throw InputError(file, line, "unknown key '" + std::string(key.str()) + "' in " + where);
    }
  }
}

Material make_material(const MaterialOverride& fields) {
  Material m;
  m.name = fields.name;
  apply_material_override(fields, m);
  return m;
}

void apply_material_override(const MaterialOverride& fields, Material& m) {
  if (fields.kd) m.diffuse = *fields.kd;
  if (fields.ks) m.reflective = *fields.ks;
  if (fields.ke) m.emissive = *fields.ke;
  if (fields.ns) m.shininess = *fields.ns;
  if (fields.ni) m.ior = *fields.ni;
  if (fields.d) m.opacity = *fields.d;
}

SceneDescription read_scene_file(const std::string& path) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<long>(e.source().begin.line), std::string(e.description()));
  }
  SceneDescription scene;
  scene.path = path;
  check_known_keys(root,
                   {"camera", "lights", "materials", "meshes", "spheres", "ambient", "settings"},
                   path, "the top level");
  const TableReader top(root, path, "the top level");
  scene.ambient = top.vec3f("ambient", scene.ambient);
  require_non_negative(top, "ambient", scene.ambient);

  if (const toml::node* camera = root.get("camera")) {
    scene.has_camera = true;
    scene.camera = read_camera(TableReader(as_table(*camera, path, "[camera]"), path, "[camera]"));
  }
  for_each_table(root, "lights", path, [&](const toml::table& t) {
    scene.lights.push_back(read_light(TableReader(t, path, "[[lights]]")));
  });
  // [[materials]] before [[meshes]], whatever their order in the file: a mesh's `material`
  // names one, checked as the mesh is read.
  std::set<std::string> material_names;
  for_each_table(root, "materials", path, [&](const toml::table& t) {
    const TableReader r(t, path, "[[materials]]");
    r.known({"name", "kd", "ks", "ke", "ns", "ni", "d"});
    r.require("name");
    MaterialOverride m;
    m.name = r.string("name", "");
    m.line = r.line();
    if (!material_names.insert(m.name).second) r.fail("name", "repeats '" + m.name + "'");
    read_material_fields(r, m);
    scene.materials.push_back(m);
  });
  for_each_table(root, "meshes", path, [&](const toml::table& t) {
    scene.meshes.push_back(read_mesh_desc(TableReader(t, path, "[[meshes]]"), material_names));
  });
  for_each_table(root, "spheres", path, [&](const toml::table& t) {
    scene.spheres.push_back(read_sphere(TableReader(t, path, "[[spheres]]")));
  });
  // [settings] is kept as a TOML table and read later by each program with its own keys
  // (io/scene_settings.hpp): common/ does not know sketchtrace's or bake's options.
  auto settings = std::make_shared<SceneSettings>();
  if (const toml::node* node = root.get("settings"))
    settings->table = as_table(*node, path, "[settings]");
  scene.settings = std::move(settings);
  return scene;
}

}  // namespace rtmini
