#include "ao_scene.hpp"

#include <cmath>
#include <map>
#include <set>

#include "rtmini/io/error.hpp"
#include "rtmini/io/gltf_reader.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/scene_file.hpp"
#include "rtmini/io/scene_settings.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini::ao {
namespace {

bool has_suffix(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i])
      return false;
  return true;
}

// Line of [settings] blockers in the file (the parsed copy in SceneDescription
// carries no source positions, so re-read it, only for error messages).
long blockers_line(const std::string& path) {
  try {
    const toml::table t = toml::parse_file(path);
    if (const toml::node* n = t.at_path("settings.blockers").node())
      return static_cast<long>(n->source().begin.line);
  } catch (const std::exception&) {
  }
  return 0;
}

std::set<std::size_t> read_blockers(const SceneDescription& desc) {
  check_known_keys(desc.settings->table, {"blockers"}, desc.path, "settings");
  std::set<std::size_t> out;
  const toml::node* node = desc.settings->table.get("blockers");
  if (node == nullptr) return out;
  const long line = blockers_line(desc.path);
  const toml::array* list = node->as_array();
  if (list == nullptr)
    throw InputError(desc.path, line, "settings.blockers must be an array of [[meshes]] indices");
  for (const toml::node& item : *list) {
    const auto v = item.value<std::int64_t>();
    if (!v || *v < 0 || static_cast<std::size_t>(*v) >= desc.meshes.size())
      throw InputError(desc.path, line,
                       "settings.blockers entries must be [[meshes]] indices 0.." +
                           std::to_string(static_cast<long>(desc.meshes.size()) - 1));
    out.insert(static_cast<std::size_t>(*v));
  }
  return out;
}

AffineD to_affine(const Affine3x4& a) {
  AffineD out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) out.m[i][j] = a[i][j];
  return out;
}

// Stored meshes by (file, mesh of the file): a file named by several [[meshes]] entries, or a
// glTF mesh referenced by several nodes, is stored once. Whole-file meshes (OBJ, .bs) use -1.
using StoredMeshes = std::map<std::pair<std::string, int>, int>;

// Every node instance of a glTF file, placed by `placement` (the [[meshes]] entry's transform,
// identity for a glTF given directly) after its own node transforms. Meshes over the same
// accessors (GltfScene::same_geometry) share one stored copy.
void add_gltf_instances(AoScene& scene, StoredMeshes& stored, const std::string& file,
                        const AffineD& placement, bool blocker, const std::string& where,
                        long line) {
  const GltfScene gltf = read_gltf(file, GltfTextures::kIgnore);
  for (const GltfInstance& gi : gltf.instances) {
    const int geometry = gltf.same_geometry[gi.mesh];
    auto it = stored.find({file, geometry});
    if (it == stored.end()) {
      it = stored.emplace(std::make_pair(file, geometry), static_cast<int>(scene.meshes.size()))
               .first;
      scene.meshes.push_back(
          make_ao_mesh(gltf.meshes[geometry], file + " " + gltf.meshes[geometry].objects.front()));
    }
    AoInstance inst;
    inst.mesh = it->second;
    inst.xform = compose(placement, to_affine(gi.xform));
    inst.blocker = blocker;
    if (std::fabs(determinant(inst.xform)) < 1e-300)
      throw InputError(where, line,
                       "transform of glTF node '" + gi.name + "' in " + file + " is singular");
    scene.instances.push_back(inst);
  }
}

}  // namespace

std::vector<int> AoScene::receivers() const {
  std::vector<int> out;
  for (std::size_t i = 0; i < instances.size(); ++i)
    if (!instances[i].blocker) out.push_back(static_cast<int>(i));
  return out;
}

Bounds AoScene::instance_bounds(int instance) const {
  Bounds b;
  const AoInstance& inst = instances[instance];
  for (const Vec3d& p : meshes[inst.mesh].positions) b.expand(inst.xform.point(p));
  return b;
}

Bounds AoScene::receiver_bounds() const {
  Bounds b;
  for (int i : receivers()) {
    const Bounds ib = instance_bounds(i);
    if (!ib.empty()) {
      b.expand(ib.lo);
      b.expand(ib.hi);
    }
  }
  return b;
}

Bounds AoScene::scene_bounds() const {
  Bounds b;
  for (int i = 0; i < static_cast<int>(instances.size()); ++i) {
    const Bounds ib = instance_bounds(i);
    if (!ib.empty()) {
      b.expand(ib.lo);
      b.expand(ib.hi);
    }
  }
  return b;
}

AoScene recentred(const AoScene& scene, const Vec3d& world_origin) {
  AoScene out = scene;
  std::vector<Vec3d> centre(out.meshes.size(), Vec3d(0.0));
  for (std::size_t m = 0; m < out.meshes.size(); ++m) {
    Bounds b;
    for (const Vec3d& p : out.meshes[m].positions) b.expand(p);
    if (b.empty()) continue;
    centre[m] = (b.lo + b.hi) * 0.5;
    for (Vec3d& p : out.meshes[m].positions) p -= centre[m];
  }
  // world = L (p' + c) + t - o = L p' + (L c + t - o)
  for (AoInstance& in : out.instances) {
    const Vec3d t = in.xform.vector(centre[in.mesh]) +
                    Vec3d(in.xform.m[0][3], in.xform.m[1][3], in.xform.m[2][3]) - world_origin;
    for (int i = 0; i < 3; ++i) in.xform.m[i][3] = t[i];
  }
  return out;
}

AoMesh make_ao_mesh(const Mesh& mesh, const std::string& name) {
  AoMesh out;
  out.name = name;
  out.positions = mesh.positions;
  const TriangleList tl = triangulate(mesh);
  out.tris = tl.vertices;
  return out;
}

AoScene load_ao_scene(const std::string& path) {
  AoScene scene;
  StoredMeshes stored;
  if (is_gltf_extension(lower_extension(path))) {
    add_gltf_instances(scene, stored, path, AffineD{}, false, path, 0);
  } else if (!has_suffix(path, ".toml")) {
    scene.meshes.push_back(make_ao_mesh(read_mesh(path), path));
    scene.instances.push_back(AoInstance{});
  } else {
    const SceneDescription desc = read_scene_file(path);
    const std::set<std::size_t> blockers = read_blockers(desc);
    for (std::size_t i = 0; i < desc.meshes.size(); ++i) {
      const MeshDesc& md = desc.meshes[i];
      if (is_gltf_extension(lower_extension(md.file))) {
        add_gltf_instances(scene, stored, md.file, make_trs(md.translate, md.rotate_deg, md.scale),
                           blockers.count(i) != 0, desc.path, md.line);
        continue;
      }
      auto it = stored.find({md.file, -1});
      if (it == stored.end()) {
        it = stored.emplace(std::make_pair(md.file, -1), static_cast<int>(scene.meshes.size()))
                 .first;
        scene.meshes.push_back(make_ao_mesh(read_mesh(md.file), md.file));
      }
      AoInstance inst;
      inst.mesh = it->second;
      inst.xform = make_trs(md.translate, md.rotate_deg, md.scale);
      inst.blocker = blockers.count(i) != 0;
      if (std::fabs(determinant(inst.xform)) < 1e-300)
        throw InputError(desc.path, md.line, "mesh transform is singular (zero scale)");
      scene.instances.push_back(inst);
    }
    for (const SphereDesc& s : desc.spheres) {
      Mesh m;
      append_icosphere(m, s.center, s.radius, 4, -1, 0);
      scene.meshes.push_back(make_ao_mesh(m, "sphere"));
      AoInstance inst;
      inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
      scene.instances.push_back(inst);
    }
  }
  std::size_t receiving_tris = 0;
  for (int i : scene.receivers())
    receiving_tris += scene.meshes[scene.instances[i].mesh].tris.size();
  if (receiving_tris == 0)
    throw InputError(path, 0, "no receiving triangles (every mesh is empty or a blocker)");
  return scene;
}

void replicate_instances(AoScene& scene, int copies, int up_axis) {
  if (copies <= 1) return;
  const Bounds b = scene.receiver_bounds();
  const double step = 1.25 * b.max_extent();
  const int a1 = (up_axis + 1) % 3, a2 = (up_axis + 2) % 3;
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(copies))));
  const std::vector<AoInstance> originals = scene.instances;
  for (int k = 1; k < copies; ++k) {
    Vec3d shift(0.0);
    shift[a1] = step * (k % columns);
    shift[a2] = step * (k / columns);
    for (AoInstance inst : originals) {
      for (int r = 0; r < 3; ++r) inst.xform.m[r][3] += shift[r];
      scene.instances.push_back(inst);
    }
  }
}

}  // namespace rtmini::ao
