// glTF 2.0 binary (.glb) output: 12-byte header, a JSON chunk padded with
// spaces and a BIN chunk padded with zeros to 4 bytes (glTF 2.0 spec, "GLB File
// Format Specification"). Instancing is kept: each stored mesh's positions and
// indices are written once and shared by the primitives of its instances.
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "ao_output.hpp"
#include "rtmini/io/atomic_file.hpp"

namespace rtmini::ao {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au;
constexpr std::uint32_t kChunkBin = 0x004E4942u;
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

template <class T>
void put(std::string& buf, const T& v) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  buf.append(bytes, sizeof(T));
}

void pad4(std::string& buf, char fill) {
  while (buf.size() % 4 != 0) buf.push_back(fill);
}

struct GltfBuilder {
  nlohmann::json views = nlohmann::json::array();
  nlohmann::json accessors = nlohmann::json::array();
  std::string bin;

  // Appends bytes as a new bufferView (4-byte aligned) and returns its index.
  int add_view(const std::string& bytes, int target) {
    pad4(bin, '\0');
    views.push_back({{"buffer", 0},
                     {"byteOffset", bin.size()},
                     {"byteLength", bytes.size()},
                     {"target", target}});
    bin += bytes;
    return static_cast<int>(views.size()) - 1;
  }
  int add_accessor(nlohmann::json acc) {
    accessors.push_back(std::move(acc));
    return static_cast<int>(accessors.size()) - 1;
  }
};

}  // namespace

void write_ao_glb(const std::string& path, const AoResult& res) {
  const SamplePlan& plan = *res.plan;
  const AoScene& scene = *res.scene;
  GltfBuilder g;
  std::map<int, std::pair<int, int>> shared;  // mesh -> (POSITION accessor, indices accessor)
  nlohmann::json meshes = nlohmann::json::array(), nodes = nlohmann::json::array();
  nlohmann::json roots = nlohmann::json::array();
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& inst = scene.instances[plan.receivers[r]];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    if (mesh.tris.empty() || mesh.positions.empty()) continue;  // glTF accessors need count >= 1
    auto it = shared.find(inst.mesh);
    if (it == shared.end()) {
      std::string pos, idx;
      float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
      for (const Vec3d& p : mesh.positions) {
        const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y),
                            static_cast<float>(p.z)};
        for (int k = 0; k < 3; ++k) {
          put(pos, f[k]);
          lo[k] = std::min(lo[k], f[k]);
          hi[k] = std::max(hi[k], f[k]);
        }
      }
      for (const auto& t : mesh.tris)
        for (int k = 0; k < 3; ++k) put(idx, static_cast<std::uint32_t>(t[k]));
      const int pv = g.add_view(pos, kArrayBuffer);
      const int iv = g.add_view(idx, kElementArrayBuffer);
      const int pa = g.add_accessor({{"bufferView", pv},
                                     {"componentType", kFloat},
                                     {"count", mesh.positions.size()},
                                     {"type", "VEC3"},
                                     {"min", {lo[0], lo[1], lo[2]}},
                                     {"max", {hi[0], hi[1], hi[2]}}});
      const int ia = g.add_accessor({{"bufferView", iv},
                                     {"componentType", kUnsignedInt},
                                     {"count", mesh.tris.size() * 3},
                                     {"type", "SCALAR"}});
      it = shared.emplace(inst.mesh, std::make_pair(pa, ia)).first;
    }
    std::string col;
    for (std::int64_t v = plan.vertex_base[r]; v < plan.vertex_base[r + 1]; ++v) {
      const float c = std::min(1.0f, std::max(0.0f, res.values[v]));
      put(col, c);
      put(col, c);
      put(col, c);
    }
    const int cv = g.add_view(col, kArrayBuffer);
    const int ca = g.add_accessor({{"bufferView", cv},
                                   {"componentType", kFloat},
                                   {"count", mesh.positions.size()},
                                   {"type", "VEC3"}});
    meshes.push_back({{"name", "receiver " + std::to_string(r)},
                      {"primitives",
                       {{{"attributes", {{"POSITION", it->second.first}, {"COLOR_0", ca}}},
                         {"indices", it->second.second},
                         {"mode", 4}}}}});
    nlohmann::json node = {{"mesh", meshes.size() - 1}};
    if (!is_identity(inst.xform)) {
      nlohmann::json m = nlohmann::json::array();  // column-major 4x4
      for (int c = 0; c < 4; ++c) {
        for (int row = 0; row < 3; ++row) m.push_back(inst.xform.m[row][c]);
        m.push_back(c == 3 ? 1.0 : 0.0);
      }
      node["matrix"] = m;
    }
    nodes.push_back(node);
    roots.push_back(nodes.size() - 1);
  }
  pad4(g.bin, '\0');
  nlohmann::json doc = {{"asset", {{"version", "2.0"}, {"generator", "rtmini bake --mode ao"}}},
                        {"scene", 0},
                        {"scenes", {{{"nodes", roots}}}},
                        {"nodes", nodes},
                        {"meshes", meshes},
                        {"accessors", g.accessors},
                        {"bufferViews", g.views},
                        {"buffers", {{{"byteLength", g.bin.size()}}}}};
  std::string json = doc.dump();
  pad4(json, ' ');
  std::string out;
  put(out, kGlbMagic);
  put(out, std::uint32_t{2});
  put(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + g.bin.size()));
  put(out, static_cast<std::uint32_t>(json.size()));
  put(out, kChunkJson);
  out += json;
  put(out, static_cast<std::uint32_t>(g.bin.size()));
  put(out, kChunkBin);
  out += g.bin;
  write_text_atomic(path, out);
}

}  // namespace rtmini::ao
