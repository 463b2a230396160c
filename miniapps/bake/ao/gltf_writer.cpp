// glTF 2.0 binary (.glb) output: 12-byte header, a JSON chunk padded with
// spaces and a BIN chunk padded with zeros to 4 bytes (glTF 2.0 spec, "GLB File
// Format Specification"). Instancing is kept: each stored mesh's positions and
// indices are written once and shared by the primitives of its instances.
#include <cstring>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "ao_output.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/raw_bytes.hpp"

namespace rtmini::ao {
namespace {

constexpr std::uint32_t kGlbMagic = 0x46546C67u;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au;
constexpr std::uint32_t kChunkBin = 0x004E4942u;
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

void pad4(std::string& buf, char fill) {
  while (buf.size() % 4 != 0) buf.push_back(fill);
}

std::size_t round_up4(std::size_t n) { return (n + 3) / 4 * 4; }

// The BIN chunk is laid out first (offsets and lengths go into the JSON, which precedes it in
// the file) and filled afterwards straight into the file's one buffer: no copy per view.
struct GltfBuilder {
  nlohmann::json views = nlohmann::json::array();
  nlohmann::json accessors = nlohmann::json::array();
  std::size_t bin_size = 0;
  // Per view: where it starts in the BIN chunk and what writes its bytes there.
  std::vector<std::pair<std::size_t, std::function<void(char*)>>> fills;

  // Reserves `bytes` bytes as a new bufferView (4-byte aligned) and returns its index.
  int add_view(std::size_t bytes, int target, std::function<void(char*)> fill) {
    bin_size = round_up4(bin_size);
    views.push_back(
        {{"buffer", 0}, {"byteOffset", bin_size}, {"byteLength", bytes}, {"target", target}});
    fills.emplace_back(bin_size, std::move(fill));
    bin_size += bytes;
    return static_cast<int>(views.size()) - 1;
  }

  int add_accessor(nlohmann::json acc) {
    accessors.push_back(std::move(acc));
    return static_cast<int>(accessors.size()) - 1;
  }
};

// Stores floats (or 32-bit indices) one after the other from `out`.
template <class T>
char* store(char* out, T v) {
  std::memcpy(out, &v, sizeof(T));
  return out + sizeof(T);
}

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
      float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
      for (const Vec3d& p : mesh.positions) {
        const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y),
                            static_cast<float>(p.z)};
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], f[k]);
          hi[k] = std::max(hi[k], f[k]);
        }
      }
      const int pv = g.add_view(mesh.positions.size() * 12, kArrayBuffer, [&mesh](char* out) {
        for (const Vec3d& p : mesh.positions) {
          out = store(out, static_cast<float>(p.x));
          out = store(out, static_cast<float>(p.y));
          out = store(out, static_cast<float>(p.z));
        }
      });
      const int iv = g.add_view(mesh.tris.size() * 12, kElementArrayBuffer, [&mesh](char* out) {
        for (const auto& t : mesh.tris)
          for (int k = 0; k < 3; ++k) out = store(out, static_cast<std::uint32_t>(t[k]));
      });
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
    const std::int64_t first = plan.vertex_base[r], last = plan.vertex_base[r + 1];
    const int cv = g.add_view(static_cast<std::size_t>(last - first) * 12, kArrayBuffer,
                              [&res, first, last](char* out) {
                                for (std::int64_t v = first; v < last; ++v) {
                                  const float c = std::min(1.0f, std::max(0.0f, res.values[v]));
                                  for (int k = 0; k < 3; ++k) out = store(out, c);
                                }
                              });
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
  const std::size_t bin_size = round_up4(g.bin_size);
  nlohmann::json doc = {{"asset", {{"version", "2.0"}, {"generator", "rtmini bake --mode ao"}}},
                        {"scene", 0},
                        {"scenes", {{{"nodes", roots}}}},
                        {"nodes", nodes},
                        {"meshes", meshes},
                        {"accessors", g.accessors},
                        {"bufferViews", g.views},
                        {"buffers", {{{"byteLength", bin_size}}}}};
  std::string json = doc.dump();
  pad4(json, ' ');
  std::string out;
  out.reserve(12 + 8 + json.size() + 8 + bin_size);
  append_raw(out, kGlbMagic);
  append_raw(out, std::uint32_t{2});
  append_raw(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin_size));
  append_raw(out, static_cast<std::uint32_t>(json.size()));
  append_raw(out, kChunkJson);
  out += json;
  append_raw(out, static_cast<std::uint32_t>(bin_size));
  append_raw(out, kChunkBin);
  const std::size_t bin_start = out.size();
  out.resize(bin_start + bin_size, '\0');  // the padding between views stays zero
  for (const auto& [offset, fill] : g.fills) fill(out.data() + bin_start + offset);
  write_text_atomic(path, out);
}

}  // namespace rtmini::ao
