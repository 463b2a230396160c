// The glTF reader (io/gltf_reader.hpp) on small files written here: node transforms composed to
// world space, instances, primitive modes, materials and texture paths, and the refusals.
#include "rtmini/io/gltf_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "../optional_features.hpp"
#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/scene_file.hpp"

namespace rtmini {
namespace {

using nlohmann::json;

// A glTF written into a scratch directory: `buffer` holds the bytes of buffer 0 (written as
// model.bin), the JSON gets the buffer entry added.
class GltfFile {
 public:
  template <class T>
  int add_view(const std::vector<T>& values) {
    const std::size_t offset = bin_.size();
    bin_.resize(offset + values.size() * sizeof(T));
    std::memcpy(bin_.data() + offset, values.data(), values.size() * sizeof(T));
    while (bin_.size() % 4 != 0) bin_.push_back('\0');
    views_.push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * sizeof(T)}});
    return static_cast<int>(views_.size()) - 1;
  }
  int add_accessor(int view, int component_type, std::size_t count, const char* type) {
    accessors_.push_back({{"bufferView", view},
                          {"componentType", component_type},
                          {"count", count},
                          {"type", type}});
    return static_cast<int>(accessors_.size()) - 1;
  }
  int add_positions(const std::vector<float>& xyz) {
    return add_accessor(add_view(xyz), 5126, xyz.size() / 3, "VEC3");
  }
  std::string write(json doc, const std::string& name = "model.gltf") {
    doc["asset"] = {{"version", "2.0"}};
    doc["accessors"] = accessors_;
    doc["bufferViews"] = views_;
    doc["buffers"] = {{{"uri", "model.bin"}, {"byteLength", bin_.size()}}};
    test::write_file(dir_.file("model.bin"), bin_);
    test::write_file(dir_.file(name), doc.dump());
    return dir_.file(name);
  }
  const test::TempDir& dir() const { return dir_; }

 private:
  test::TempDir dir_;
  std::string bin_;
  json views_ = json::array(), accessors_ = json::array();
};

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

json one_mesh(int positions) {
  return json::array({{{"primitives", {{{"attributes", {{"POSITION", positions}}}}}}}});
}

void expect_near(const Vec3d& a, const Vec3d& b) {
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}

// An InputError whose message is one line naming the file and containing `part`.
template <class Fn>
void expect_input_error(Fn fn, const std::string& path, const std::string& part) {
  try {
    fn();
    ADD_FAILURE() << "accepted; expected an error containing '" << part << "'";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(part), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(GltfReader, NodeTransformsComposeFromTheRootDown) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const double h = std::sqrt(0.5);
  // parent: T(1,2,3) S(2); child: T(0,0,1) R(90 deg about z); a matrix node (column-major)
  // equal to the parent's transform, holding the same child transform as a sibling check.
  const std::string path = f.write(
      {{"scene", 0},
       {"scenes", {{{"nodes", {0, 2}}}}},
       {"nodes",
        {{{"translation", {1, 2, 3}}, {"scale", {2, 2, 2}}, {"children", {1}}},
         {{"translation", {0, 0, 1}}, {"rotation", {0, 0, h, h}}, {"mesh", 0}, {"name", "child"}},
         {{"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1}}, {"mesh", 0}}}},
       {"meshes", one_mesh(pos)}});
  const GltfScene scene = read_gltf(path);
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.instances[0].name, "child");
  EXPECT_EQ(scene.instances[1].name, "node 2");
  const Mesh world = flatten_gltf(scene);
  ASSERT_EQ(world.positions.size(), 6u);
  // child: p -> R p + (0,0,1) -> 2 (.) + (1,2,3). R maps x to y and y to -x.
  expect_near(world.positions[0], {1, 2, 5});
  expect_near(world.positions[1], {1, 4, 5});
  expect_near(world.positions[2], {-1, 2, 5});
  // matrix node: 2 p + (1,2,3).
  expect_near(world.positions[3], {1, 2, 3});
  expect_near(world.positions[4], {3, 2, 3});
  expect_near(world.positions[5], {1, 4, 3});
  ASSERT_EQ(world.objects.size(), 2u);
  EXPECT_EQ(world.faces[1].object, 1);
  EXPECT_EQ(world.faces[1].v[0], 3);
}

TEST(GltfReader, AMeshUsedByTwoNodesIsStoredOnce) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const std::string path =
      f.write({{"scenes", {{{"nodes", {0, 1}}}}},
               {"nodes", {{{"mesh", 0}}, {{"mesh", 0}, {"translation", {5, 0, 0}}}}},
               {"meshes", one_mesh(pos)}});
  const GltfScene scene = read_gltf(path);
  EXPECT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.instances[0].mesh, 0);
  EXPECT_EQ(scene.instances[1].mesh, 0);
  EXPECT_EQ(scene.instances[1].xform[0][3], 5.0);
  // read_mesh flattens: the apps that do not keep instances see both copies.
  const Mesh flat = read_mesh(path);
  EXPECT_EQ(flat.faces.size(), 2u);
  expect_near(flat.positions[4], {6, 0, 0});
}

// A TOML [[meshes]] entry naming a glTF (sketchtrace's scenes): the file's node transforms
// first, then the entry's own; the glTF's materials stay, named, for [[materials]] overrides.
TEST(GltfReader, TomlMeshEntryPlacesTheFlattenedGltf) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  json meshes =
      json::array({{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"material", 0}}}}}});
  f.write({{"scenes", {{{"nodes", {0}}}}},
           {"nodes", {{{"mesh", 0}, {"translation", {0, 0, 1}}}}},
           {"meshes", meshes},
           {"materials", {{{"name", "paint"}}}}});
  const std::string toml = f.dir().file("scene.toml");
  test::write_file(toml,
                   "[[materials]]\nname = \"paint\"\nkd = [0.1, 0.2, 0.3]\n"
                   "[[meshes]]\nfile = \"model.gltf\"\ntranslate = [10, 0, 0]\nscale = 2\n");
  const Mesh m = load_scene_meshes(read_scene_file(toml));
  ASSERT_EQ(m.positions.size(), 3u);
  expect_near(m.positions[0], {10, 0, 2});  // 2 * (p + (0,0,1)) + (10,0,0)
  expect_near(m.positions[1], {12, 0, 2});
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].diffuse.y, 0.2f);
}

TEST(GltfReader, MeshesOverTheSameAccessorsShareGeometry) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const int pos2 = f.add_positions(kTriangle);
  json meshes = one_mesh(pos);
  meshes.push_back(one_mesh(pos)[0]);
  meshes.push_back(one_mesh(pos2)[0]);
  const std::string path =
      f.write({{"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"mesh", 2}}}}, {"meshes", meshes}});
  EXPECT_EQ(read_gltf(path).same_geometry, (std::vector<int>{0, 0, 2}));
}

TEST(GltfReader, IndexedStripsAndFansFollowTheSpecificationsWinding) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  const int idx16 =
      f.add_accessor(f.add_view(std::vector<std::uint16_t>{0, 1, 2, 3}), 5123, 4, "SCALAR");
  const int idx8 =
      f.add_accessor(f.add_view(std::vector<std::uint8_t>{2, 1, 0, 1, 2, 3}), 5121, 6, "SCALAR");
  const json prims = {{{"attributes", {{"POSITION", pos}}}, {"indices", idx16}, {"mode", 5}},
                      {{"attributes", {{"POSITION", pos}}}, {"indices", idx16}, {"mode", 6}},
                      {{"attributes", {{"POSITION", pos}}}, {"indices", idx8}},
                      {{"attributes", {{"POSITION", pos}}}, {"mode", 1}}};  // lines: skipped
  const std::string path = f.write({{"scenes", {{{"nodes", {0}}}}},
                                    {"nodes", {{{"mesh", 0}}}},
                                    {"meshes", {{{"primitives", prims}}}}});
  const Mesh m = read_gltf(path).meshes[0];
  ASSERT_EQ(m.faces.size(), 6u);
  const auto tri = [&](int i) {
    const Face& face = m.faces[i];
    return std::array<int, 3>{face.v[0], face.v[1], face.v[2]};
  };
  EXPECT_EQ(tri(0), (std::array<int, 3>{0, 1, 2}));          // strip, even
  EXPECT_EQ(tri(1), (std::array<int, 3>{1, 3, 2}));          // strip, odd: (i, i+2, i+1)
  EXPECT_EQ(tri(2), (std::array<int, 3>{4 + 1, 4 + 2, 4}));  // fan: (i+1, i+2, 0)
  EXPECT_EQ(tri(3), (std::array<int, 3>{4 + 2, 4 + 3, 4}));
  EXPECT_EQ(tri(4), (std::array<int, 3>{8 + 2, 8 + 1, 8}));  // ubyte indices
  EXPECT_EQ(tri(5), (std::array<int, 3>{8 + 1, 8 + 2, 8 + 3}));
  EXPECT_EQ(m.positions.size(), 12u);  // each triangle primitive appends its vertices; lines none
  EXPECT_TRUE(m.texcoords.empty());
  EXPECT_EQ(m.faces[0].uv[0], -1);
  EXPECT_EQ(m.faces[0].material, -1);
}

TEST(GltfReader, MaterialsTexcoordsAndTexturePaths) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const int uv = f.add_accessor(f.add_view(std::vector<float>{0.f, 0.f, 1.f, 0.25f, 0.5f, 1.f}),
                                5126, 3, "VEC2");
  test::write_file(f.dir().file("base colour.png"), "not decoded by the reader");
  const json prim = {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 1}};
  const std::string path = f.write(
      {{"scenes", {{{"nodes", {0}}}}},
       {"nodes", {{{"mesh", 0}}}},
       {"meshes", {{{"primitives", {prim}}}}},
       {"images", {{{"uri", "base%20colour.png"}}}},
       {"textures", {{{"source", 0}}}},
       {"materials",
        {{{"name", "plain"}},
         {{"name", "painted"},
          {"pbrMetallicRoughness",
           {{"baseColorFactor", {0.5, 0.25, 0.125, 1.0}}, {"baseColorTexture", {{"index", 0}}}}},
          {"emissiveFactor", {1.0, 2.0, 0.0}}}}}});
  const Mesh m = read_gltf(path).meshes[0];
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].diffuse.x, 1.f);  // glTF's default base colour is white
  EXPECT_FALSE(m.materials[0].maps.any());
  const Material& painted = m.materials[1];
  EXPECT_EQ(painted.name, "painted");
  EXPECT_EQ(painted.diffuse.y, 0.25f);
  EXPECT_EQ(painted.emissive.y, 2.f);
  EXPECT_EQ(painted.maps.diffuse, f.dir().file("base colour.png"));
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].material, 1);
  ASSERT_EQ(m.texcoords.size(), 3u);
  EXPECT_EQ(m.faces[0].uv[1], 1);
  EXPECT_EQ(m.texcoords[1].u, 1.f);
  EXPECT_EQ(m.texcoords[1].v, 0.75f);  // v flipped: glTF's grows downwards
  // The restart signature lists the buffer and the image beside the glTF.
  EXPECT_EQ(mesh_files(path), (std::vector<std::string>{path, f.dir().file("model.bin"),
                                                        f.dir().file("base colour.png")}));
}

TEST(GltfReader, EmbeddedImagesAreRefusedUnlessTexturesAreIgnored) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const std::string path = f.write(
      {{"scenes", {{{"nodes", {0}}}}},
       {"nodes", {{{"mesh", 0}}}},
       {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"material", 0}}}}}}},
       {"images", {{{"uri", "data:image/png;base64,AAAA"}, {"name", "inline"}}}},
       {"textures", {{{"source", 0}}}},
       {"materials",
        {{{"name", "m"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}}}});
  expect_input_error([&] { read_gltf(path); }, path, "image 0 'inline' is embedded");
  EXPECT_EQ(read_gltf(path, GltfTextures::kIgnore).meshes[0].faces.size(), 1u);
}

TEST(GltfReader, MalformedFilesAreOneLineInputErrors) {
  RTMINI_REQUIRE_GLTF();
  GltfFile f;
  const int pos = f.add_positions(kTriangle);
  const int bad_idx =
      f.add_accessor(f.add_view(std::vector<std::uint32_t>{0, 1, 7}), 5125, 3, "SCALAR");
  const int long_acc = f.add_accessor(0, 5126, 4, "VEC3");  // 4 vertices in a 3-vertex view
  const auto scene_with = [&](json mesh_prims, json extra = json::object()) {
    json doc = {{"scenes", {{{"nodes", {0}}}}},
                {"nodes", {{{"mesh", 0}}}},
                {"meshes", {{{"primitives", mesh_prims}}}}};
    doc.update(extra);
    return doc;
  };
  std::string p =
      f.write(scene_with({{{"attributes", {{"POSITION", pos}}}, {"indices", bad_idx}}}), "a.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "index 7 past the 3 vertices");
  p = f.write(scene_with({{{"attributes", {{"POSITION", long_acc}}}}}), "b.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "reads past the end of its bufferView");
  p = f.write(scene_with({{{"attributes", {{"POSITION", pos}}}}},
                         {{"nodes", {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}}}}),
              "c.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "reached twice");
  p = f.write(scene_with({{{"attributes", {{"POSITION", pos}}}}},
                         {{"extensionsRequired", {"KHR_draco_mesh_compression"}},
                          {"extensionsUsed", {"KHR_draco_mesh_compression"}}}),
              "d.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "KHR_draco_mesh_compression");
  p = f.write(scene_with({{{"attributes", {{"POSITION", pos}}}}},
                         {{"nodes", {{{"mesh", 0}, {"rotation", {0, 0, 0, 2}}}}}}),
              "e.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "not a unit quaternion");
  p = f.dir().file("broken.gltf");
  test::write_file(p, "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  expect_input_error([&] { read_gltf(p); }, p, "glTF parse failed");
  p = f.dir().file("broken.glb");
  test::write_file(p, "glTF\x02");
  expect_input_error([&] { read_mesh(p); }, p, "glTF parse failed");
  p = f.dir().file("absent.gltf");
  expect_input_error([&] { read_gltf(p); }, p, "cannot open");
}

#ifndef RTMINI_HAVE_GLTF
// Without tinygltf a glTF input is bad input (exit 2) saying so, not an unknown format.
TEST(GltfReader, ABuildWithoutTinygltfSaysSo) {
  test::TempDir dir;
  const std::string p = dir.file("scene.gltf");
  test::write_file(p, "{}");
  expect_input_error([&] { read_mesh(p); }, p, "built without glTF support");
}
#endif

}  // namespace
}  // namespace rtmini
