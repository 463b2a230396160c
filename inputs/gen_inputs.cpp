// rtmini-gen-inputs: regenerates the bake inputs (inputs/README.md): the seed's "cube" and
// "cornell_big_raw" cases, the furnace box of the correctness tests, the bundled Cornell box
// (inputs/meshes) converted to .bs, and two bunny bake scenes built around
// inputs/meshes/stanford-bunny.obj; and the sliver fan that measures the SAH build's pre-splitting
// (results/bvh/slivers.md); the image maps of the textured cube (inputs/textured_cube); and the
// glTF instance scene of bake --mode ao (inputs/ao/spot_three.gltf) from a TOML instance scene.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "affine.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/raw_bytes.hpp"
#include "rtmini/io/scene_file.hpp"
#include "rtmini/io/srgb.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini {
namespace {

int add_material(Mesh& m, Vec3f diffuse, Vec3f reflective, Vec3f emissive) {
  Material mat;
  mat.diffuse = diffuse;
  mat.reflective = reflective;
  mat.emissive = emissive;
  m.materials.push_back(mat);
  return static_cast<int>(m.materials.size()) - 1;
}

Vec3d rotate_y(const Vec3d& p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}

// A box of per-face grids (cells[a] cells along axis a), rotated about y through its centre.
// Each face has its own vertices, so every vertex normal is its face's normal.
void append_grid_box(Mesh& m, const Vec3d& centre, const Vec3d& size, double angle,
                     const int cells[3], bool with_bottom, int material) {
  const Vec3d lo = size * -0.5;
  const Vec3d ax[3] = {{size.x, 0, 0}, {0, size.y, 0}, {0, 0, size.z}};
  struct FaceSpec {
    Vec3d corner;
    int a, b;  // u along axis a, v along axis b, outward normal = u x v
  };
  const FaceSpec faces[6] = {{lo + ax[0], 1, 2}, {lo, 2, 1},         {lo + ax[1], 2, 0},
                             {lo, 0, 2},         {lo + ax[2], 0, 1}, {lo, 1, 0}};
  for (int f = 0; f < 6; ++f) {
    if (f == 3 && !with_bottom) continue;
    const FaceSpec& s = faces[f];
    append_grid(m, centre + rotate_y(s.corner, angle), rotate_y(ax[s.a], angle),
                rotate_y(ax[s.b], angle), cells[s.a], cells[s.b], material, 0);
  }
}

// The seed's "cube" (8 vertices, 6 quads): a closed room whose ceiling is the light and whose
// other faces are semi-reflective; every corner averages light and wall materials (the seed's
// corner model).
Mesh make_cube() {
  Mesh m;
  const int wall = add_material(m, {0.6f, 0.6f, 0.6f}, {0.3f, 0.3f, 0.3f}, {0.f, 0.f, 0.f});
  const int light = add_material(m, {0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});
  append_box(m, {-1, -1, -1}, {1, 1, 1}, wall, 0, true);
  m.faces[3].material = light;  // the y = +1 face
  return m;
}

// cornell_big_raw: 1,924 vertices. Floor, ceiling and side walls of 16x16 cells (4 x 289), a
// back wall of 20x13 cells (294), one emissive quad (4), a short box (5 faces, 4x7x4 cells: 185)
// and a tall box (4x12x4 cells: 285), both semi-reflective.
Mesh make_cornell_big() {
  Mesh m;
  const int white = add_material(m, {0.725f, 0.71f, 0.68f}, {0, 0, 0}, {0, 0, 0});
  const int red = add_material(m, {0.63f, 0.065f, 0.05f}, {0, 0, 0}, {0, 0, 0});
  const int green = add_material(m, {0.14f, 0.45f, 0.091f}, {0, 0, 0}, {0, 0, 0});
  const int light = add_material(m, {0.78f, 0.78f, 0.78f}, {0, 0, 0}, {17.f, 12.f, 4.f});
  const int box = add_material(m, {0.3f, 0.3f, 0.3f}, {0.5f, 0.5f, 0.5f}, {0, 0, 0});
  const int g = 16;
  append_grid(m, {-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, g, g, white, 0);         // floor, normal +y
  append_grid(m, {-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, g, g, white, 0);         // ceiling, -y
  append_grid(m, {-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, 20, 13, white, 0);       // back, +z
  append_grid(m, {-1, 0, -1}, {0, 2, 0}, {0, 0, 2}, g, g, red, 0);           // left, +x
  append_grid(m, {1, 0, -1}, {0, 0, 2}, {0, 2, 0}, g, g, green, 0);          // right, -x
  append_quad(m, {-0.25, 1.98, -0.25}, {0.5, 0, 0}, {0, 0, 0.5}, light, 0);  // light, -y
  const int short_cells[3] = {4, 7, 4}, tall_cells[3] = {4, 12, 4};
  append_grid_box(m, {0.35, 0.3, 0.35}, {0.6, 0.6, 0.6}, -0.3, short_cells, false, box);
  append_grid_box(m, {-0.35, 0.6, -0.3}, {0.6, 1.2, 0.6}, 0.3, tall_cells, false, box);
  return m;
}

// Merges vertices with bit-identical positions (the grids of adjacent faces share their edges).
void weld(Mesh& m) {
  std::map<std::array<double, 3>, int> index;
  std::vector<Vec3d> kept;
  std::vector<int> remap(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3d& p = m.positions[i];
    const auto ins =
        index.emplace(std::array<double, 3>{p.x, p.y, p.z}, static_cast<int>(kept.size()));
    if (ins.second) kept.push_back(p);
    remap[i] = ins.first->second;
  }
  for (Face& f : m.faces)
    for (int k = 0; k < f.count; ++k) f.v[k] = remap[f.v[k]];
  m.positions = kept;
}

// Furnace: a closed box, every face emissive E with mirror reflectance rho and no diffuse part;
// after K iterations every colour is E (1 - rho^(K+1)) / (1 - rho). The faces' grids are
// welded, so the box is one closed surface (a vertex on an edge has the averaged normal and
// its rays start inside); cells = 0: the plain 8-corner box.
Mesh make_furnace(double rho, double emission, int cells) {
  Mesh m;
  const float r = static_cast<float>(rho), e = static_cast<float>(emission);
  const int mat = add_material(m, {0, 0, 0}, {r, r, r}, {e, e, e});
  if (cells == 0) {
    append_box(m, {-1, -1, -1}, {1, 1, 1}, mat, 0, true);
  } else {
    const int c[3] = {cells, cells, cells};
    append_grid_box(m, {0, 0, 0}, {2, 2, 2}, 0.0, c, true, mat);
    for (Face& f : m.faces) std::swap(f.v[1], f.v[3]);  // inward: the inside of the box is seen
    weld(m);
  }
  return m;
}

// The stanford bunny as the seed's reflective grey bunny, lit by a red panel above and a blue
// panel below, with a grey diffuse backdrop behind it to reflect.
Mesh make_bunny(const std::string& scene) {
  Mesh m = read_obj(scene);
  m.materials.clear();
  const int bunny = add_material(m, {0.3f, 0.3f, 0.3f}, {0.6f, 0.6f, 0.6f}, {0, 0, 0});
  const int red = add_material(m, {0, 0, 0}, {0, 0, 0}, {8.f, 1.f, 1.f});
  const int blue = add_material(m, {0, 0, 0}, {0, 0, 0}, {1.f, 1.f, 8.f});
  const int grey = add_material(m, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, {0, 0, 0});
  for (Face& f : m.faces) f.material = bunny;
  Vec3d lo(1e300), hi(-1e300);
  for (const Vec3d& p : m.positions) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  const Vec3d c = (lo + hi) * 0.5, e = hi - lo;
  const double s = max_component(e);
  append_quad(m, {c.x - 0.3 * s, hi.y + 0.4 * s, c.z - 0.3 * s}, {0.6 * s, 0, 0}, {0, 0, 0.6 * s},
              red, 0);  // normal -y
  append_quad(m, {c.x - 0.3 * s, lo.y - 0.2 * s, c.z - 0.3 * s}, {0, 0, 0.6 * s}, {0.6 * s, 0, 0},
              blue, 0);  // normal +y
  append_quad(m, {c.x - 1.5 * s, lo.y - 0.3 * s, lo.z - 0.5 * s}, {3.0 * s, 0, 0}, {0, 2.0 * s, 0},
              grey, 0);  // backdrop, normal +z
  return m;
}

// The baking paper's figure 4.g: a very reflective grey bunny in a room, a red light at the
// top and a blue light at the bottom. Here the room is a gridded, semi-reflective grey floor
// (the bunny stands on it and is mirrored in it) and a gridded diffuse back wall; the red panel
// hangs above the bunny facing down, the blue panel lies on the floor in front of it facing up.
// Floor and wall are grids so the baked light varies across them (colours live on vertices).
Mesh make_bunny_room(const std::string& scene) {
  Mesh m = read_obj(scene);
  m.materials.clear();
  const int bunny = add_material(m, {0.3f, 0.3f, 0.3f}, {0.6f, 0.6f, 0.6f}, {0, 0, 0});
  const int red = add_material(m, {0, 0, 0}, {0, 0, 0}, {8.f, 1.f, 1.f});
  const int blue = add_material(m, {0, 0, 0}, {0, 0, 0}, {1.f, 1.f, 8.f});
  const int floor = add_material(m, {0.45f, 0.45f, 0.45f}, {0.25f, 0.25f, 0.25f}, {0, 0, 0});
  const int wall = add_material(m, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, {0, 0, 0});
  for (Face& f : m.faces) f.material = bunny;
  Vec3d lo(1e300), hi(-1e300);
  for (const Vec3d& p : m.positions) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  const Vec3d c = (lo + hi) * 0.5;
  const double s = max_component(hi - lo);
  const double x0 = c.x - 1.5 * s, z0 = lo.z - 0.8 * s, z1 = hi.z + 1.6 * s;
  append_grid(m, {x0, lo.y, z0}, {0, 0, z1 - z0}, {3.0 * s, 0, 0}, 20, 24, floor, 0);  // +y
  append_grid(m, {x0, lo.y, z0}, {3.0 * s, 0, 0}, {0, 1.6 * s, 0}, 24, 12, wall, 0);   // +z
  append_quad(m, {c.x - 0.3 * s, hi.y + 0.6 * s, c.z - 0.3 * s}, {0.6 * s, 0, 0}, {0, 0, 0.6 * s},
              red, 0);  // normal -y
  append_quad(m, {c.x - 0.4 * s, lo.y + 0.002 * s, hi.z + 0.3 * s}, {0, 0, 0.4 * s},
              {0.8 * s, 0, 0}, blue, 0);  // normal +y
  return m;
}

}  // namespace
}  // namespace rtmini

namespace rtmini {
namespace {

// Order-independent hash of the written mesh: vertex positions and face corner indices.
// Image maps of the textured cube, 128 x 128, 8 x 8 tiles with grout between them.
constexpr int kMapSize = 128, kTiles = 8;

// Height of the tile pattern at texel centre (x, y): 1 on a tile, 0 in the grout, with a
// bevel ramp of 2 texels between them (the height field of the POM/displacement tests).
float tile_height(int x, int y) {
  const double cell = double(kMapSize) / kTiles;
  const auto edge = [&](int i) {
    const double f = std::fmod(i + 0.5, cell);
    return std::min(f, cell - f);  // distance to the nearest tile border, texels
  };
  const double d = std::min(edge(x), edge(y));
  return static_cast<float>(std::clamp((d - 1.0) / 2.0, 0.0, 1.0));
}

// Data maps (normals, heights) hold their 8-bit code as the value: write_png sRGB-encodes, so
// the value is handed over decoded and comes back as the code.
Image as_png_data(const Image& data) {
  Image out = data;
  for (float& v : out.data) v = srgb_decode(std::round(std::clamp(v, 0.f, 1.f) * 255.f) / 255.f);
  return out;
}

// tiles_albedo.png (colour: two-tone tiles, dark grout), tiles_height.png (tile_height),
// tiles_normal.png (tangent-space normals of that height field at 1/16 of the tile's
// size in depth, from central differences), dimples_height.png (a bump map: cosine dimples).
void write_texture_maps(const std::string& folder) {
  Image albedo(kMapSize, kMapSize), height(kMapSize, kMapSize, 1), normal(kMapSize, kMapSize);
  Image dimples(kMapSize, kMapSize, 1);
  const auto h = [](int x, int y) {
    return tile_height((x + kMapSize) % kMapSize, (y + kMapSize) % kMapSize);
  };
  const double depth_texels = double(kMapSize) / kTiles / 16.0;
  for (int y = 0; y < kMapSize; ++y)
    for (int x = 0; x < kMapSize; ++x) {
      const int tile = x / (kMapSize / kTiles) + y / (kMapSize / kTiles);
      const float hh = h(x, y);
      const Vec3f tone = tile % 2 ? Vec3f(0.75f, 0.35f, 0.2f) : Vec3f(0.85f, 0.8f, 0.65f);
      const Vec3f c = tone * hh + Vec3f(0.15f) * (1.f - hh);
      albedo.at(x, y, 0) = c.x;
      albedo.at(x, y, 1) = c.y;
      albedo.at(x, y, 2) = c.z;
      height.at(x, y, 0) = hh;
      // Image rows grow downwards, v upwards: dh/dv = -(h(y+1) - h(y-1)) / 2.
      const double dhdu = (h(x + 1, y) - h(x - 1, y)) * 0.5 * depth_texels;
      const double dhdv = -(h(x, y + 1) - h(x, y - 1)) * 0.5 * depth_texels;
      const Vec3d n = normalize(Vec3d(-dhdu, -dhdv, 1.0));
      normal.at(x, y, 0) = static_cast<float>(0.5 * n.x + 0.5);
      normal.at(x, y, 1) = static_cast<float>(0.5 * n.y + 0.5);
      normal.at(x, y, 2) = static_cast<float>(0.5 * n.z + 0.5);
      const double cell = double(kMapSize) / kTiles;
      const double fx = std::fmod(x + 0.5, cell) / cell - 0.5,
                   fy = std::fmod(y + 0.5, cell) / cell - 0.5;
      const double r = std::sqrt(fx * fx + fy * fy);
      dimples.at(x, y, 0) =
          static_cast<float>(r < 0.4 ? 0.5 + 0.5 * std::cos(math::kPi * r / 0.4) : 0.0);
    }
  write_png(folder + "/tiles_albedo.png", albedo);
  write_png(folder + "/tiles_height.png", as_png_data(height));
  write_png(folder + "/tiles_normal.png", as_png_data(normal));
  write_png(folder + "/dimples_height.png", as_png_data(dimples));
}

std::uint64_t mesh_hash(const Mesh& m) {
  std::uint64_t h = 0, k = 0;
  for (const Vec3d& p : m.positions)
    for (const double c : {p.x, p.y, p.z}) h += hash_term(k++, compat::bit_cast<std::uint64_t>(c));
  for (const Face& f : m.faces)
    for (int i = 0; i < f.count; ++i) h += hash_term(k++, static_cast<std::uint64_t>(f.v[i]));
  return h;
}

// The glTF counterpart of a TOML instance scene: the mesh of the first [[meshes]] entry stored
// once (float positions, uint32 triangle indices in scene/mesh.hpp's triangulation order) and
// one node per entry naming that file, whose matrix is the entry's transform as bake --mode ao
// builds it (make_trs), under one root node without a transform. Positions of an OBJ are floats
// already, and the matrices are written with 17 digits, so a reader gets the TOML scene's
// geometry and transforms bit for bit. Writes `out` (.gltf) and the .bin beside it; returns the
// mesh for the report.
Mesh write_gltf_instances(const std::string& toml, const std::string& out) {
  const SceneDescription scene = read_scene_file(toml);
  if (scene.meshes.empty()) throw InputError(toml, 0, "has no [[meshes]]");
  const std::string file = scene.meshes.front().file;
  const Mesh mesh = read_mesh(file);
  const TriangleList tris = triangulate(mesh);
  std::string bin;
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (const Vec3d& p : mesh.positions) {
    const float f[3] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    for (int k = 0; k < 3; ++k) {
      append_raw(bin, f[k]);
      lo[k] = std::min(lo[k], f[k]);
      hi[k] = std::max(hi[k], f[k]);
    }
  }
  const std::size_t index_offset = bin.size();
  for (const auto& t : tris.vertices)
    for (int k = 0; k < 3; ++k) append_raw(bin, static_cast<std::uint32_t>(t[k]));

  nlohmann::json nodes = nlohmann::json::array(), children = nlohmann::json::array();
  nodes.push_back({{"name", "instances"}});
  for (const MeshDesc& md : scene.meshes) {
    if (md.file != file) continue;
    const ao::AffineD x = ao::make_trs(md.translate, md.rotate_deg, md.scale);
    nlohmann::json matrix = nlohmann::json::array();  // column-major 4x4
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 3; ++r) matrix.push_back(x.m[r][c]);
      matrix.push_back(c == 3 ? 1.0 : 0.0);
    }
    children.push_back(nodes.size());
    nodes.push_back({{"name", "instance " + std::to_string(children.size() - 1) + " (" +
                                  scene.path.substr(scene.path.find_last_of('/') + 1) + " line " +
                                  std::to_string(md.line) + ")"},
                     {"mesh", 0},
                     {"matrix", matrix}});
  }
  nodes[0]["children"] = children;
  const std::size_t slash = out.find_last_of('/');
  const std::string stem = out.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::string bin_name = stem.substr(0, stem.rfind('.')) + ".bin";
  const std::string name = file.substr(file.find_last_of('/') + 1);
  const nlohmann::json doc = {
      {"asset", {{"version", "2.0"}, {"generator", "rtmini-gen-inputs gltf_instances"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", nodes},
      {"meshes",
       {{{"name", name},
         {"primitives",
          {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}, {"mode", 4}}}}}}},
      {"materials",
       {{{"name", "default"},
         {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}}}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", mesh.positions.size()},
         {"type", "VEC3"},
         {"min", {lo[0], lo[1], lo[2]}},
         {"max", {hi[0], hi[1], hi[2]}}},
        {{"bufferView", 1},
         {"componentType", 5125},
         {"count", tris.vertices.size() * 3},
         {"type", "SCALAR"}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", index_offset}, {"target", 34962}},
        {{"buffer", 0},
         {"byteOffset", index_offset},
         {"byteLength", bin.size() - index_offset},
         {"target", 34963}}}},
      {"buffers", {{{"uri", bin_name}, {"byteLength", bin.size()}}}}};
  write_text_atomic(out.substr(0, out.size() - stem.size()) + bin_name, bin);
  write_text_atomic(out, doc.dump(1) + "\n");
  return mesh;
}

int gen_inputs(Communicator& comm, int argc, char** argv) {
  CLI::App app{"rtmini-gen-inputs: regenerate the bake inputs (see inputs/README.md)",
               "rtmini-gen-inputs"};
  CommonOptions common;
  add_common_options(app, common);
  std::string out, scene;
  double rho = 0.5, emission = 1.0;
  int cells = 3;
  auto* cube = app.add_subcommand("cube", "the seed's 8-vertex cube");
  auto* big = app.add_subcommand("cornell_big", "cornell_big_raw (1,924 vertices)");
  auto* furnace = app.add_subcommand("furnace", "all-emissive mirror box for the furnace test");
  auto* cornell = app.add_subcommand("cornell", "an OBJ/MTL converted to .bs");
  auto* bunny = app.add_subcommand("bunny", "the bunny bake scene");
  auto* bunny_room = app.add_subcommand("bunny_room", "the bunny on a floor, the paper's fig. 4.g");
  auto* fan = app.add_subcommand("sliver_fan", "a flat fan of slivers sharing one apex (BVH test)");
  auto* maps = app.add_subcommand("texture_maps", "the textured cube's PNG maps (-o: a folder)");
  auto* gltf = app.add_subcommand(
      "gltf_instances", "a TOML instance scene's first mesh and its instances as glTF nodes");
  int fan_count = 100000;
  double fan_angle = 1.0;
  for (auto* sub : {cube, big, furnace, cornell, bunny, bunny_room, fan, maps, gltf}) {
    add_common_options(*sub, common);
    sub->add_option("-o,--output", out,
                    sub == gltf ? "output .gltf (and .bin beside it)" : "output .bs")
        ->required();
  }
  gltf->add_option("--scene", scene, "TOML scene with [[meshes]] instances")->required();
  furnace->add_option("--rho", rho, "mirror reflectance");
  furnace->add_option("--emission", emission, "emission of every face");
  furnace->add_option("--cells", cells, "grid cells per face edge (0: 8 shared corners)");
  cornell->add_option("--scene", scene, "OBJ file")->required();
  bunny->add_option("--scene", scene, "stanford-bunny.obj")->required();
  bunny_room->add_option("--scene", scene, "stanford-bunny.obj")->required();
  fan->add_option("--count", fan_count, "triangles (aspect = count / angle)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  fan->add_option("--angle", fan_angle, "angle the fan spans, radians")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 6.283));
  app.require_subcommand(1);
  if (const auto done = parse_command_line(app, argc, argv, common, comm.is_root())) return *done;
  if (*maps) {
    if (comm.is_root()) write_texture_maps(out);
    return kExitOk;
  }
  // The generated meshes are small but for those read from a file: its text, the OBJ reader's
  // arrays, the Mesh and the .bs text written take about 6 times the file's size (measured on
  // the bunny, results/reliability/memory_estimates.md).
  MemoryNeed need;
  if (!scene.empty()) {
    std::ifstream in(scene, std::ios::binary | std::ios::ate);
    if (in) need.host = 6.0 * static_cast<double>(in.tellg());
  }
  const MemoryPeak peak = require_memory(comm, need, common.memory_limit());
  RunReport report;
  report.app = "rtmini-gen-inputs";
  report.scene["memory_estimate_bytes"] = comm.max(peak.host + peak.device);
  report.timer.start("generate");
  Mesh m;
  if (*cube) m = make_cube();
  if (*big) m = make_cornell_big();
  if (*furnace) m = make_furnace(rho, emission, cells);
  if (*cornell) m = read_obj(scene);
  if (*bunny) m = make_bunny(scene);
  if (*bunny_room) m = make_bunny_room(scene);
  if (*fan) {
    m.materials.push_back(Material{});
    append_fan(m, {0, 0, 0}, 1.0, fan_angle, fan_count, 0, 0);
  }
  report.timer.stop();
  report.timer.start("write");
  if (*gltf) {
    if (comm.is_root()) m = write_gltf_instances(scene, out);
  } else if (comm.is_root()) {
    write_bakeshop(out, m);
  }
  report.timer.stop();
  if (comm.is_root())
    std::cout << out << ": " << m.positions.size() << " vertices, " << m.faces.size() << " faces, "
              << m.materials.size() << " materials\n";
  report.parameters = {{"subcommand", app.get_subcommands().front()->get_name()}, {"output", out}};
  report.fom_name = "faces written";
  report.fom_unit = "faces";
  report.fom_value = static_cast<double>(m.faces.size());
  report.verification_hash = mesh_hash(m);
  // Phases only: the program has no dispatch loop of its own to record.
  if (!common.timings.empty())
    write_rank_timings(common.timings, comm, report.timer, RankTimings{},
                       {"rtmini-gen-inputs", "", scene, report.parameters.dump(), {}});
  report.finish(comm, common.summary);
  return kExitOk;
}

}  // namespace
}  // namespace rtmini

int main(int argc, char** argv) {
  return rtmini::app_main("rtmini-gen-inputs", argc, argv, rtmini::gen_inputs);
}
