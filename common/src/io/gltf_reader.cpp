#include "rtmini/io/gltf_reader.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>

#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"

#ifdef RTMINI_HAVE_GLTF
#include <tiny_gltf.h>
#endif

namespace rtmini {

Affine3x4 compose_affine(const Affine3x4& a, const Affine3x4& b) {
  Affine3x4 out{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? a[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) s += a[i][k] * b[k][j];
      out[i][j] = s;
    }
  }
  return out;
}

Vec3d apply_affine(const Affine3x4& a, const Vec3d& p) {
  return {a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
          a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
          a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]};
}

Mesh flatten_gltf(const GltfScene& scene) {
  // Face indices are int: a file whose instances repeat a mesh past that many vertices is
  // refused rather than wrapped (bake --mode ao keeps such scenes instanced instead).
  std::size_t total = 0;
  for (const GltfInstance& inst : scene.instances)
    total += scene.meshes[inst.mesh].positions.size();
  if (total > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InputError(scene.path, 0,
                     "its instances have " + std::to_string(total) +
                         " vertices, too many to flatten into one mesh");
  Mesh out;
  if (!scene.meshes.empty()) out.materials = scene.meshes.front().materials;
  for (const GltfInstance& inst : scene.instances) {
    const Mesh& mesh = scene.meshes[inst.mesh];
    const int vertex_base = static_cast<int>(out.positions.size());
    const int uv_base = static_cast<int>(out.texcoords.size());
    const int object = static_cast<int>(out.objects.size());
    out.objects.push_back(inst.name);
    for (const Vec3d& p : mesh.positions) out.positions.push_back(apply_affine(inst.xform, p));
    out.texcoords.insert(out.texcoords.end(), mesh.texcoords.begin(), mesh.texcoords.end());
    for (Face f : mesh.faces) {
      for (int k = 0; k < f.count; ++k) {
        f.v[k] += vertex_base;
        if (f.uv[k] >= 0) f.uv[k] += uv_base;
      }
      f.object = object;
      out.faces.push_back(f);
    }
  }
  return out;
}

#ifdef RTMINI_HAVE_GLTF

namespace {

// URIs in glTF are percent-encoded ("my%20texture.png"); the file on disk is not.
std::string percent_decoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  return out;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

std::string resolve_uri(const std::string& gltf_path, const std::string& uri) {
  const std::string file = percent_decoded(uri);
  return !file.empty() && file.front() == '/' ? file : directory_prefix(gltf_path) + file;
}

// tinygltf errors are several lines; ours are one ("file: reason").
std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (char& c : text)
    if (c == '\n') c = ';';
  return text;
}

// Images are never decoded here: sketchtrace reads textures itself, by path (maps.diffuse), and
// the geometry readers do not need pixels. tinygltf still reads an external image's bytes.
bool skip_image_decoding(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                         const unsigned char*, int, void*) {
  return true;
}

tinygltf::Model load_model(const std::string& path) {
  if (!std::ifstream(path)) throw InputError(path, 0, "cannot open the glTF file");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image_decoding, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const std::string ext = lower_extension(path);
  bool ok = false;
  if (ext == ".glb") {
    ok = loader.LoadBinaryFromFile(&model, &err, &warn, path);
  } else if (ext == ".gltf") {
    ok = loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } else {
    throw InputError(path, 0, "not a glTF file (expected .gltf or .glb)");
  }
  if (!ok) throw InputError(path, 0, "glTF parse failed: " + one_line(err.empty() ? warn : err));
  for (const std::string& ext_name : model.extensionsRequired)
    throw InputError(path, 0,
                     "requires the glTF extension " + ext_name + ", which rtmini does not read");
  return model;
}

// One accessor's elements, checked against its buffer view and buffer before anything is read:
// fuzzed or truncated files must fail here, not read past the end of a buffer.
class AccessorView {
 public:
  AccessorView(const tinygltf::Model& model, int index, const std::string& path,
               const std::string& what)
      : path_(path), what_(what + " (accessor " + std::to_string(index) + ")") {
    if (index < 0 || index >= static_cast<int>(model.accessors.size())) fail("does not exist");
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.sparse.isSparse) fail("is sparse, which rtmini does not read");
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model.bufferViews.size()))
      fail("has no valid bufferView");
    const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
      fail("names a buffer that does not exist");
    const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
    const int component =
        tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    if (component <= 0 || components <= 0) fail("has an unknown component type or type");
    component_type_ = a.componentType;
    components_ = components;
    normalized_ = a.normalized;
    count_ = a.count;
    element_size_ = static_cast<std::uint64_t>(component) * static_cast<std::uint64_t>(components);
    stride_ = view.byteStride != 0 ? view.byteStride : element_size_;
    if (stride_ < element_size_) fail("has a byteStride smaller than its element");
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      fail("has a bufferView past the end of its buffer");
    // Offset, stride and count each at most the view's length (itself at most the buffer's, in
    // memory), so the product below cannot overflow.
    if (a.byteOffset > view.byteLength || stride_ > view.byteLength || count_ > view.byteLength)
      fail("reads past the end of its bufferView");
    if (count_ > 0 && a.byteOffset + stride_ * (count_ - 1) + element_size_ > view.byteLength)
      fail("reads past the end of its bufferView");
    base_ = data.data() + view.byteOffset + a.byteOffset;
  }

  std::size_t count() const { return count_; }
  int component_type() const { return component_type_; }
  int components() const { return components_; }
  bool normalized() const { return normalized_; }

  // Component k of element i, converted to double (glTF data need not be aligned: memcpy).
  double component(std::size_t i, int k) const {
    const unsigned char* p = base_ + i * stride_;
    switch (component_type_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return read<float>(p, k);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return read<std::uint8_t>(p, k);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return read<std::uint16_t>(p, k);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return read<std::uint32_t>(p, k);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return read<std::int8_t>(p, k);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return read<std::int16_t>(p, k);
      default:
        fail("has an unsupported component type");
    }
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_, 0, what_ + " " + reason);
  }

 private:
  template <class T>
  static double read(const unsigned char* p, int k) {
    T v;
    std::memcpy(&v, p + k * sizeof(T), sizeof(T));
    return static_cast<double>(v);
  }

  std::string path_, what_;
  const unsigned char* base_ = nullptr;
  std::size_t count_ = 0;
  std::uint64_t element_size_ = 0, stride_ = 0;
  int component_type_ = 0, components_ = 0;
  bool normalized_ = false;
};

std::vector<Vec3d> read_positions(const AccessorView& a) {
  if (a.component_type() != TINYGLTF_COMPONENT_TYPE_FLOAT || a.components() != 3)
    a.fail("must be float VEC3 (POSITION)");
  std::vector<Vec3d> out(a.count());
  for (std::size_t i = 0; i < a.count(); ++i) {
    out[i] = {a.component(i, 0), a.component(i, 1), a.component(i, 2)};
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y) || !std::isfinite(out[i].z))
      a.fail("has a non-finite position (vertex " + std::to_string(i) + ")");
  }
  return out;
}

// TEXCOORD_0: float, or normalised unsigned byte/short (value / 255 or / 65535). glTF's v
// grows downwards from the image's top; TexCoord's upwards as in OBJ, hence 1 - v.
std::vector<TexCoord> read_texcoords(const AccessorView& a) {
  double scale = 1.0;
  if (a.component_type() == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && a.normalized()) {
    scale = 1.0 / 255.0;
  } else if (a.component_type() == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && a.normalized()) {
    scale = 1.0 / 65535.0;
  } else if (a.component_type() != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    a.fail("must be float or normalised unsigned byte/short (TEXCOORD_0)");
  }
  if (a.components() != 2) a.fail("must be VEC2 (TEXCOORD_0)");
  std::vector<TexCoord> out(a.count());
  for (std::size_t i = 0; i < a.count(); ++i) {
    const double u = a.component(i, 0) * scale, v = a.component(i, 1) * scale;
    if (!std::isfinite(u) || !std::isfinite(v)) a.fail("has a non-finite texture coordinate");
    out[i] = {static_cast<float>(u), static_cast<float>(1.0 - v)};
  }
  return out;
}

std::vector<std::uint32_t> read_indices(const AccessorView& a, std::size_t vertex_count) {
  const int t = a.component_type();
  if (a.components() != 1 ||
      (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    a.fail("must be unsigned byte/short/int SCALAR (indices)");
  std::vector<std::uint32_t> out(a.count());
  for (std::size_t i = 0; i < a.count(); ++i) {
    const double v = a.component(i, 0);
    if (v >= static_cast<double>(vertex_count))
      a.fail("has index " + std::to_string(static_cast<std::uint64_t>(v)) + " past the " +
             std::to_string(vertex_count) + " vertices");
    out[i] = static_cast<std::uint32_t>(v);
  }
  return out;
}

bool is_triangle_mode(int mode) {
  return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
         mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

// The triangles of one primitive as index triples into its own vertices, in the orders of the
// glTF specification (3.7.2.1): strips alternate their winding, fans pivot on the first vertex.
std::vector<std::array<std::uint32_t, 3>> primitive_triangles(
    int mode, const std::vector<std::uint32_t>& idx) {
  std::vector<std::array<std::uint32_t, 3>> out;
  const std::size_t n = idx.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (std::size_t i = 0; i + 2 < n; i += 3) out.push_back({idx[i], idx[i + 1], idx[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 0; i + 2 < n; ++i)
      out.push_back(i % 2 == 0 ? std::array<std::uint32_t, 3>{idx[i], idx[i + 1], idx[i + 2]}
                               : std::array<std::uint32_t, 3>{idx[i], idx[i + 2], idx[i + 1]});
  } else {
    for (std::size_t i = 1; i + 1 < n; ++i) out.push_back({idx[i], idx[i + 1], idx[0]});
  }
  return out;
}

Vec3f colour_factor(const std::vector<double>& factor, const Vec3f& fallback,
                    const std::string& path, const std::string& what) {
  if (factor.size() < 3) return fallback;
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(factor[k]) || factor[k] < 0.0 || factor[k] > 3.0e38)
      throw InputError(path, 0, what + " must be finite and non-negative");
  return {static_cast<float>(factor[0]), static_cast<float>(factor[1]),
          static_cast<float>(factor[2])};
}

// The base-colour image of a material as a file path; embedded images are refused (see the
// header: rtmini reads textures from files and writes no extracted copies).
std::string base_color_image(const tinygltf::Model& model, const tinygltf::Material& mat,
                             const std::string& mat_name, const std::string& path) {
  const tinygltf::TextureInfo& info = mat.pbrMetallicRoughness.baseColorTexture;
  if (info.index < 0) return {};
  const std::string where = "material '" + mat_name + "': baseColorTexture";
  if (info.index >= static_cast<int>(model.textures.size()))
    throw InputError(
        path, 0, where + " names texture " + std::to_string(info.index) + ", which does not exist");
  if (info.texCoord != 0)
    throw InputError(
        path, 0,
        where + " uses TEXCOORD_" + std::to_string(info.texCoord) + "; only TEXCOORD_0 is read");
  const int source = model.textures[info.index].source;
  if (source < 0 || source >= static_cast<int>(model.images.size()))
    throw InputError(path, 0, where + " has no valid image source");
  const tinygltf::Image& image = model.images[source];
  const std::string image_name =
      "image " + std::to_string(source) + (image.name.empty() ? "" : " '" + image.name + "'");
  if (image.uri.empty() || is_data_uri(image.uri))
    throw InputError(path, 0,
                     where + ": " + image_name +
                         " is embedded in the file (bufferView or data: URI); rtmini "
                         "reads textures from image files: export the images separately");
  const std::string file = resolve_uri(path, image.uri);
  if (!std::ifstream(file))
    throw InputError(path, 0,
                     where + ": " + image_name + " names a file that cannot be opened: " + file);
  return file;
}

std::vector<Material> read_materials(const tinygltf::Model& model, const std::string& path,
                                     GltfTextures textures) {
  std::vector<Material> out;
  for (std::size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& g = model.materials[i];
    Material m;
    m.name = g.name.empty() ? "material " + std::to_string(i) : g.name;
    const std::string where = "material '" + m.name + "': ";
    m.diffuse = colour_factor(g.pbrMetallicRoughness.baseColorFactor, Vec3f(1.f), path,
                              where + "baseColorFactor");
    m.emissive = colour_factor(g.emissiveFactor, Vec3f(0.f), path, where + "emissiveFactor");
    if (textures == GltfTextures::kResolve)
      m.maps.diffuse = base_color_image(model, g, m.name, path);
    out.push_back(m);
  }
  return out;
}

// A glTF mesh as one Mesh: each primitive's vertices appended, its triangles pointing at them.
Mesh read_mesh_primitives(const tinygltf::Model& model, int index, const std::string& path,
                          const std::vector<Material>& materials) {
  const tinygltf::Mesh& g = model.meshes[index];
  const std::string mesh_name = "mesh " + std::to_string(index);
  Mesh mesh;
  mesh.materials = materials;
  mesh.objects.push_back(g.name.empty() ? mesh_name : g.name);
  for (std::size_t p = 0; p < g.primitives.size(); ++p) {
    const tinygltf::Primitive& prim = g.primitives[p];
    if (!is_triangle_mode(prim.mode)) continue;  // points and lines have no surface
    const std::string what = mesh_name + " primitive " + std::to_string(p);
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) throw InputError(path, 0, what + " has no POSITION");
    const std::vector<Vec3d> positions =
        read_positions(AccessorView(model, pos->second, path, what + " POSITION"));
    std::vector<std::uint32_t> indices;
    if (prim.indices >= 0) {
      indices = read_indices(AccessorView(model, prim.indices, path, what + " indices"),
                             positions.size());
    } else {
      indices.resize(positions.size());
      for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<std::uint32_t>(i);
    }
    int uv_base = -1;
    if (const auto uv = prim.attributes.find("TEXCOORD_0"); uv != prim.attributes.end()) {
      const std::vector<TexCoord> tc =
          read_texcoords(AccessorView(model, uv->second, path, what + " TEXCOORD_0"));
      if (tc.size() != positions.size())
        throw InputError(path, 0,
                         what + " has " + std::to_string(tc.size()) + " TEXCOORD_0 for " +
                             std::to_string(positions.size()) + " positions");
      uv_base = static_cast<int>(mesh.texcoords.size());
      mesh.texcoords.insert(mesh.texcoords.end(), tc.begin(), tc.end());
    }
    if (prim.material >= static_cast<int>(materials.size()))
      throw InputError(
          path, 0,
          what + " names material " + std::to_string(prim.material) + ", which does not exist");
    const int vertex_base = static_cast<int>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), positions.begin(), positions.end());
    for (const auto& tri : primitive_triangles(prim.mode, indices)) {
      Face f;
      f.count = 3;
      f.material = prim.material < 0 ? -1 : prim.material;
      for (int k = 0; k < 3; ++k) {
        f.v[k] = vertex_base + static_cast<int>(tri[k]);
        if (uv_base >= 0) f.uv[k] = uv_base + static_cast<int>(tri[k]);
      }
      mesh.faces.push_back(f);
    }
  }
  return mesh;
}

// Meshes whose triangle primitives read the same accessors in the same modes are one geometry.
std::vector<int> shared_geometry(const tinygltf::Model& model) {
  std::map<std::vector<std::tuple<int, int, int>>, int> first;
  std::vector<int> out;
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    std::vector<std::tuple<int, int, int>> key;
    for (const tinygltf::Primitive& prim : model.meshes[m].primitives) {
      if (!is_triangle_mode(prim.mode)) continue;
      const auto pos = prim.attributes.find("POSITION");
      key.emplace_back(prim.mode, pos == prim.attributes.end() ? -1 : pos->second, prim.indices);
    }
    out.push_back(first.emplace(key, static_cast<int>(m)).first->second);
  }
  return out;
}

void require_finite(const std::vector<double>& values, const std::string& path,
                    const std::string& what) {
  for (double v : values)
    if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
      throw InputError(path, 0, what + " must be finite");
}

// A node's local transform: its matrix (column-major, affine), or translation * rotation *
// scale (glTF specification 3.5.3).
Affine3x4 local_transform(const tinygltf::Node& node, const std::string& path,
                          const std::string& what) {
  Affine3x4 out = identity_affine();
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) throw InputError(path, 0, what + " matrix must have 16 numbers");
    require_finite(node.matrix, path, what + " matrix");
    const auto& m = node.matrix;
    if (m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0)
      throw InputError(path, 0, what + " matrix is not affine (last row must be 0 0 0 1)");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) out[r][c] = m[c * 4 + r];
    return out;
  }
  const auto checked = [&](const std::vector<double>& v, std::size_t n, const char* key) {
    if (!v.empty() && v.size() != n)
      throw InputError(path, 0, what + " " + key + " must have " + std::to_string(n) + " numbers");
    require_finite(v, path, what + " " + key);
    return !v.empty();
  };
  double s[3] = {1.0, 1.0, 1.0};
  if (checked(node.scale, 3, "scale"))
    for (int k = 0; k < 3; ++k) s[k] = node.scale[k];
  double r[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  if (checked(node.rotation, 4, "rotation")) {
    const double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2],
                 w = node.rotation[3];
    // Unit quaternions only, as the specification requires: a rescaled rotation is an error in
    // the file, not something to guess at.
    if (std::fabs(x * x + y * y + z * z + w * w - 1.0) > 1e-6)
      throw InputError(path, 0, what + " rotation is not a unit quaternion");
    const double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    std::memcpy(r, m, sizeof r);
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[i][j] = r[i][j] * s[j];
  if (checked(node.translation, 3, "translation"))
    for (int i = 0; i < 3; ++i) out[i][3] = node.translation[i];
  return out;
}

// Depth first from the scene's roots, parents before children, children in file order. A node
// reached twice (two parents, or a cycle) is refused: glTF nodes form disjoint trees, and a
// shared subtree could multiply the instances exponentially.
std::vector<GltfInstance> scene_instances(const tinygltf::Model& model, const std::string& path) {
  if (model.scenes.empty()) throw InputError(path, 0, "has no scene");
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene >= static_cast<int>(model.scenes.size()))
    throw InputError(path, 0, "default scene " + std::to_string(scene) + " does not exist");
  const int node_count = static_cast<int>(model.nodes.size());
  std::vector<char> seen(model.nodes.size(), 0);
  std::vector<std::pair<int, Affine3x4>> stack;
  const auto push_children = [&](const std::vector<int>& children, const Affine3x4& parent,
                                 const std::string& owner) {
    for (auto it = children.rbegin(); it != children.rend(); ++it) {
      if (*it < 0 || *it >= node_count)
        throw InputError(path, 0,
                         owner + " names node " + std::to_string(*it) + ", which does not exist");
      if (seen[*it])
        throw InputError(
            path, 0, "node " + std::to_string(*it) + " is reached twice (nodes must form trees)");
      seen[*it] = 1;
      stack.emplace_back(*it, parent);
    }
  };
  push_children(model.scenes[scene].nodes, identity_affine(), "scene " + std::to_string(scene));
  std::vector<GltfInstance> out;
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    const tinygltf::Node& node = model.nodes[index];
    const std::string what = "node " + std::to_string(index);
    const Affine3x4 world = compose_affine(parent, local_transform(node, path, what));
    if (node.mesh >= static_cast<int>(model.meshes.size()))
      throw InputError(
          path, 0, what + " names mesh " + std::to_string(node.mesh) + ", which does not exist");
    if (node.mesh >= 0) out.push_back({node.mesh, world, node.name.empty() ? what : node.name});
    push_children(node.children, world, what);
  }
  return out;
}

}  // namespace

bool gltf_supported() { return true; }

GltfScene read_gltf(const std::string& path, GltfTextures textures) {
  const tinygltf::Model model = load_model(path);
  GltfScene scene;
  scene.path = path;
  const std::vector<Material> materials = read_materials(model, path, textures);
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    scene.meshes.push_back(read_mesh_primitives(model, static_cast<int>(m), path, materials));
  scene.same_geometry = shared_geometry(model);
  scene.instances = scene_instances(model, path);
  return scene;
}

std::vector<std::string> gltf_files(const std::string& path) {
  const tinygltf::Model model = load_model(path);
  std::vector<std::string> files{path};
  for (const tinygltf::Buffer& b : model.buffers)
    if (!b.uri.empty() && !is_data_uri(b.uri)) files.push_back(resolve_uri(path, b.uri));
  for (const tinygltf::Image& image : model.images)
    if (!image.uri.empty() && !is_data_uri(image.uri))
      files.push_back(resolve_uri(path, image.uri));
  return files;
}

#else  // built without tinygltf

namespace {
[[noreturn]] void no_gltf(const std::string& path) {
  throw InputError(path, 0,
                   "built without glTF support (libtinygltf-dev not found at configure time)");
}
}  // namespace

bool gltf_supported() { return false; }
GltfScene read_gltf(const std::string& path, GltfTextures) { no_gltf(path); }
std::vector<std::string> gltf_files(const std::string& path) { no_gltf(path); }

#endif

}  // namespace rtmini
