// Double positions, as Mesh keeps them (and .bs files): far-off or large scenes lose nothing
// before the upload rounds them to Real. This file holds tinyobjloader's one implementation.
#define TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_IMPLEMENTATION
#include "rtmini/io/obj_reader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <utility>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/gltf_reader.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini {
namespace {

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

// tinyobjloader reports no line numbers, so this pass checks what it would
// otherwise accept silently or crash on: counts, numbers, finiteness, index ranges.
class ObjPrescan {
 public:
  explicit ObjPrescan(const std::string& path) : path_(path) {}

  void run(std::string_view text) {
    for_each_statement(text, [&](const std::vector<std::string_view>& f) {
      if (f[0] == "v") {
        if (f.size() != 4 && f.size() != 5 && f.size() != 7)
          fail("vertex needs 3 coordinates (optionally w, or r g b), got " +
               std::to_string(f.size() - 1) + " fields");
        check_numbers(f, "vertex");
        ++nv_;
      } else if (f[0] == "vt") {
        if (f.size() < 2 || f.size() > 4) fail("texture coordinate needs 1 to 3 fields");
        check_numbers(f, "texture coordinate");
        ++nvt_;
      } else if (f[0] == "vn") {
        if (f.size() != 4) fail("normal needs 3 fields, got " + std::to_string(f.size() - 1));
        check_numbers(f, "normal");
        ++nvn_;
      } else if (f[0] == "f") {
        if (f.size() < 4)
          fail("face needs at least 3 vertices, got " + std::to_string(f.size() - 1));
        for (std::size_t i = 1; i < f.size(); ++i) check_face_vertex(f[i]);
      } else if (f[0] == "mtllib") {
        if (f.size() < 2) fail("mtllib without a file name");
        for (std::size_t i = 1; i < f.size(); ++i) {
          const std::string mtl = directory_of(path_) + "/" + std::string(f[i]);
          if (std::ifstream(mtl)) {
            if (std::find(mtl_files_.begin(), mtl_files_.end(), mtl) == mtl_files_.end())
              mtl_files_.push_back(mtl);
          } else if (missing_mtl_line_ == 0) {
            missing_mtl_line_ = line_;
            missing_mtl_ = mtl;
          }
        }
      } else if (f[0] == "usemtl") {
        if (f.size() != 2) fail("usemtl needs exactly one material name");
        usemtl_.emplace_back(std::string(f[1]), line_);
      }
    });
    // A missing library matters only when a face asks for a material from it
    // (the shared dragon.obj names a dragon.mtl that does not exist and uses none).
    if (missing_mtl_line_ > 0 && !usemtl_.empty()) {
      line_ = missing_mtl_line_;
      fail("cannot open material library '" + missing_mtl_ + "'");
    }
  }

  const std::vector<std::pair<std::string, long>>& usemtl() const { return usemtl_; }
  const std::vector<std::string>& mtl_files() const { return mtl_files_; }
  const std::vector<std::string>& image_files() const { return image_files_; }

  // A material library: the numbers of the statements rtmini reads (colours Ka Kd Ks Ke Tf,
  // scalars Ns Ni d Tr), so that a bad value is reported at its own file and line, and the
  // image maps (map_Kd map_Ks map_bump bump norm disp), each decoded once here so that a
  // missing or broken image is reported at the line that names it.
  void run_mtl(std::string_view text) {
    for_each_statement(text, [&](const std::vector<std::string_view>& f) {
      if (is_image_map(f[0])) return check_image_map(f);
      const bool colour =
          f[0] == "Ka" || f[0] == "Kd" || f[0] == "Ks" || f[0] == "Ke" || f[0] == "Tf";
      const bool scalar = f[0] == "Ns" || f[0] == "Ni" || f[0] == "d" || f[0] == "Tr";
      if (!colour && !scalar) return;
      if (colour && f.size() > 1 && (f[1] == "spectral" || f[1] == "xyz")) return;
      if (f.size() < 2) fail(std::string(f[0]) + " needs a value");
      check_numbers(f, (std::string("material statement ") + std::string(f[0])).c_str());
    });
  }

 private:
  // Calls fn with the fields of every non-empty line (comments removed), line_ set.
  template <class Fn>
  void for_each_statement(std::string_view text, Fn&& fn) {
    detail::LineCursor cursor(text);
    std::string_view line;
    while (cursor.next(line)) {
      line_ = cursor.line_number();
      const std::size_t hash = line.find('#');
      if (hash != std::string_view::npos) line = line.substr(0, hash);
      const auto f = detail::split_fields(line);
      if (!f.empty()) fn(f);
    }
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_, line_, reason);
  }

  static bool is_image_map(std::string_view keyword) {
    return keyword == "map_Kd" || keyword == "map_Ks" || keyword == "map_bump" ||
           keyword == "map_Bump" || keyword == "bump" || keyword == "norm" || keyword == "disp";
  }

  // `keyword [-option values...] file`: tinyobjloader parses the options (-bm is kept as the
  // map's scale, the others are accepted and ignored); the file is the last field.
  void check_image_map(const std::vector<std::string_view>& f) {
    if (f.size() < 2) fail(std::string(f[0]) + " needs an image file");
    const std::string name(f.back());
    if (name[0] == '-') fail(std::string(f[0]) + " needs an image file after its options");
    const std::string file = directory_of(path_) + "/" + name;
    if (lower_extension(file) != ".png")
      fail("image map '" + name + "' is not a PNG file (only PNG maps are read)");
    if (std::find(image_files_.begin(), image_files_.end(), file) != image_files_.end()) return;
    try {
      (void)read_png_data(file);
    } catch (const std::exception& e) {
      fail("cannot read image map '" + name + "': " + e.what());
    }
    image_files_.push_back(file);
  }

  void check_numbers(const std::vector<std::string_view>& f, const char* what) const {
    for (std::size_t i = 1; i < f.size(); ++i) {
      const auto value = detail::parse_number<double>(f[i]);
      if (!value) fail("invalid number '" + std::string(f[i]) + "' in " + what);
      if (!std::isfinite(*value)) fail("non-finite value '" + std::string(f[i]) + "' in " + what);
      if (!detail::fits_real(*value))
        fail("value '" + std::string(f[i]) + "' in " + what + " is beyond the " +
             detail::real_range_name() + " range (non-finite once uploaded)");
    }
  }

  void check_index(std::string_view field, long count, const char* what) const {
    const auto value = detail::parse_number<long>(field);
    if (!value) fail("invalid " + std::string(what) + " index '" + std::string(field) + "'");
    if (*value == 0) fail(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
    if (*value > count || -*value > count)
      fail(std::string(what) + " index " + std::to_string(*value) + " out of range (" +
           std::to_string(count) + " defined so far)");
  }

  void check_face_vertex(std::string_view ref) const {
    const std::size_t s1 = ref.find('/');
    check_index(ref.substr(0, s1), nv_, "vertex");
    if (s1 == std::string_view::npos) return;
    const std::string_view rest = ref.substr(s1 + 1);
    const std::size_t s2 = rest.find('/');
    const std::string_view vt = rest.substr(0, s2);
    if (!vt.empty()) check_index(vt, nvt_, "texture coordinate");
    if (s2 == std::string_view::npos) return;
    const std::string_view vn = rest.substr(s2 + 1);
    if (vn.empty() || vn.find('/') != std::string_view::npos)
      fail("malformed face vertex '" + std::string(ref) + "'");
    check_index(vn, nvn_, "normal");
  }

  const std::string& path_;
  long line_ = 0;
  long nv_ = 0, nvt_ = 0, nvn_ = 0;
  std::vector<std::pair<std::string, long>> usemtl_;
  std::vector<std::string> mtl_files_;
  std::vector<std::string> image_files_;
  long missing_mtl_line_ = 0;
  std::string missing_mtl_;
};

// An MTL map name resolved against the library's folder (the OBJ's, where tinyobjloader
// looks for libraries); empty stays empty.
std::string map_path(const std::string& folder, const std::string& name) {
  return name.empty() ? name : folder + "/" + name;
}

Material to_material(const tinyobj::material_t& m, const std::string& folder) {
  const auto v = [](const tinyobj::real_t* c) {
    return Vec3f(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
  };
  Material out;
  out.name = m.name;
  out.diffuse = v(m.diffuse);
  out.reflective = v(m.specular);
  out.emissive = v(m.emission);
  out.shininess = static_cast<float>(m.shininess);
  out.ior = static_cast<float>(m.ior);
  out.opacity = static_cast<float>(m.dissolve);
  out.maps.diffuse = map_path(folder, m.diffuse_texname);
  out.maps.specular = map_path(folder, m.specular_texname);
  out.maps.normal = map_path(folder, m.normal_texname);
  out.maps.bump = map_path(folder, m.bump_texname);
  out.maps.displacement = map_path(folder, m.displacement_texname);
  out.maps.bump_scale = static_cast<float>(m.bump_texopt.bump_multiplier);
  out.maps.displacement_scale = static_cast<float>(m.displacement_texopt.bump_multiplier);
  return out;
}

bool material_is_finite(const Material& m) {
  return is_finite(m.diffuse) && is_finite(m.reflective) && is_finite(m.emissive) &&
         std::isfinite(m.shininess) && std::isfinite(m.ior) && std::isfinite(m.opacity) &&
         std::isfinite(m.maps.bump_scale) && std::isfinite(m.maps.displacement_scale);
}

}  // namespace

Mesh read_obj(const std::string& path) {
  const std::string text = detail::read_text_file(path);
  ObjPrescan prescan(path);
  prescan.run(text);
  for (const std::string& mtl : prescan.mtl_files()) {
    const std::string mtl_text = detail::read_text_file(mtl);
    ObjPrescan(mtl).run_mtl(mtl_text);
  }

  // Polygons come back as written: quads stay quads (a Face holds up to 4 vertices, as in .bs
  // files) and larger ones are fanned below by the same rule for every reader.
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;
  config.vertex_color = false;
  config.mtl_search_path = directory_of(path);
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config))
    throw InputError(path, 0, "OBJ parse failed: " + reader.Error());

  Mesh mesh;
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    mesh.materials.push_back(to_material(m, config.mtl_search_path));
    if (!material_is_finite(mesh.materials.back()))
      throw InputError(path, 0, "material '" + m.name + "' has a non-finite value");
  }
  for (const auto& [name, line] : prescan.usemtl()) {
    // C++17 lambdas cannot capture a structured binding (Clang refuses; GCC allows it).
    const std::string& wanted = name;
    const bool known = std::any_of(mesh.materials.begin(), mesh.materials.end(),
                                   [&wanted](const Material& m) { return m.name == wanted; });
    if (!known)
      throw InputError(path, line, "material '" + name + "' is not defined in any mtllib");
  }

  const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
  mesh.positions.reserve(v.size() / 3);
  for (std::size_t i = 0; i + 2 < v.size(); i += 3)
    mesh.positions.emplace_back(v[i], v[i + 1], v[i + 2]);
  const std::vector<tinyobj::real_t>& vt = reader.GetAttrib().texcoords;
  mesh.texcoords.reserve(vt.size() / 2);
  for (std::size_t i = 0; i + 1 < vt.size(); i += 2)
    mesh.texcoords.push_back({static_cast<float>(vt[i]), static_cast<float>(vt[i + 1])});

  // Objects by name: OBJ files may reopen a group ("g wall") later; its faces join the first.
  std::map<std::string, int> object_ids;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::string name = shape.name.empty() ? "default" : shape.name;
    const auto [it, inserted] = object_ids.emplace(name, static_cast<int>(mesh.objects.size()));
    if (inserted) mesh.objects.push_back(name);
    std::size_t base = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const int n = shape.mesh.num_face_vertices[f];
      const auto index = [&](int k) { return shape.mesh.indices[base + k].vertex_index; };
      const auto uv = [&](int k) { return shape.mesh.indices[base + k].texcoord_index; };
      Face face;
      face.material = shape.mesh.material_ids[f];
      face.object = it->second;
      if (n <= 4) {
        face.count = n;
        for (int k = 0; k < n; ++k) {
          face.v[k] = index(k);
          face.uv[k] = uv(k);
        }
        mesh.faces.push_back(face);
      } else {
        // A fan from the first vertex: exact for the convex polygons OBJ exporters write.
        face.count = 3;
        for (int k = 1; k + 1 < n; ++k) {
          face.v = {index(0), index(k), index(k + 1), -1};
          face.uv = {uv(0), uv(k), uv(k + 1), -1};
          mesh.faces.push_back(face);
        }
      }
      base += n;
    }
  }
  return mesh;
}

bool is_gltf_extension(const std::string& ext) { return ext == ".gltf" || ext == ".glb"; }

std::vector<std::string> mesh_files(const std::string& path) {
  if (is_gltf_extension(lower_extension(path))) return gltf_files(path);
  std::vector<std::string> files{path};
  if (lower_extension(path) != ".obj") return files;
  ObjPrescan prescan(path);
  prescan.run(detail::read_text_file(path));
  files.insert(files.end(), prescan.mtl_files().begin(), prescan.mtl_files().end());
  for (const std::string& mtl : prescan.mtl_files()) {
    ObjPrescan library(mtl);
    library.run_mtl(detail::read_text_file(mtl));
    files.insert(files.end(), library.image_files().begin(), library.image_files().end());
  }
  return files;
}

Mesh read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return read_obj(path);
  if (ext == ".bs") return read_bakeshop(path);
  if (is_gltf_extension(ext)) return flatten_gltf(read_gltf(path));
  throw InputError(path, 0,
                   "unknown mesh format '" + ext + "' (expected .obj, .bs, .gltf or .glb)");
}

}  // namespace rtmini
