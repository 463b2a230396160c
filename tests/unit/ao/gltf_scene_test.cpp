// glTF scenes in bake --mode ao: a glTF mesh placed by several nodes is stored once and bakes
// exactly like the TOML instance scene it stands for; the .glb writer's output reads back as
// the same geometry and transforms.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "../optional_features.hpp"
#include "ao_mode.hpp"
#include "ao_output.hpp"
#include "ao_scene.hpp"
#include "ao_test_util.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/gltf_reader.hpp"
#include "rtmini/io/scene_file.hpp"
#include "sample_plan.hpp"

namespace rtmini::ao {
namespace {

const std::string kInputs = RTMINI_AO_INPUTS_DIR;

std::string g17(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string vec3(const Vec3d& v) {
  return "[" + g17(v.x) + ", " + g17(v.y) + ", " + g17(v.z) + "]";
}

// A .bs of the mesh (shortest round-trip numbers, read back bit for bit; tinyobjloader's own
// number parser is not correctly rounded, so an OBJ would not do).
void write_mesh(const std::string& path, const AoMesh& mesh) {
  Mesh m;
  m.materials.push_back(Material{});
  m.positions = mesh.positions;
  for (const auto& t : mesh.tris) {
    Face f;
    f.v = {t[0], t[1], t[2], -1};
    f.material = 0;
    m.faces.push_back(f);
  }
  write_bakeshop(path, m);
}

bool same(const Vec3d& a, const Vec3d& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

void expect_same_affine(const AffineD& a, const AffineD& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(a.m[i][j], b.m[i][j]) << "entry " << i << "," << j;
}

std::string bake(const std::string& input, const std::string& output) {
  AoOptions o;
  o.input = input;
  o.output = output;
  o.rays = 4;  // equality, not accuracy: few rays keep the test quick
  o.batch = 5000;
  Communicator comm;
  EXPECT_EQ(run_ao_mode(comm, o), 0);
  return test::file_bytes(output);
}

// spot_three.gltf: one mesh, three nodes (rtmini-gen-inputs gltf_instances from
// spot_instances.toml). Its TOML counterpart: the same three [[meshes]] transforms over an OBJ
// (.bs) of the glTF's float positions. Same stored mesh, same transforms, same bytes out.
TEST(AoGltf, OneMeshThreeNodesBakesLikeTheTomlInstances) {
  RTMINI_REQUIRE_GLTF();
  const std::string gltf = kInputs + "/spot_three.gltf";
  const AoScene from_gltf = load_ao_scene(gltf);
  ASSERT_EQ(from_gltf.meshes.size(), 1u);
  ASSERT_EQ(from_gltf.instances.size(), 3u);

  const std::string dir = ::testing::TempDir();
  const std::string mesh = dir + "ao_gltf_spot.bs", toml = dir + "ao_gltf_spot.toml";
  write_mesh(mesh, from_gltf.meshes[0]);
  std::ofstream scene(toml);
  const SceneDescription source = read_scene_file(kInputs + "/spot_instances.toml");
  for (const MeshDesc& md : source.meshes) {
    if (md.file != source.meshes.front().file) continue;  // the spots, not the wall
    scene << "[[meshes]]\nfile = \"" << mesh << "\"\ntranslate = " << vec3(md.translate)
          << "\nrotate_deg = " << vec3(md.rotate_deg) << "\nscale = " << vec3(md.scale) << "\n";
  }
  scene.close();
  const AoScene from_toml = load_ao_scene(toml);
  ASSERT_EQ(from_toml.meshes.size(), 1u);
  ASSERT_EQ(from_toml.instances.size(), 3u);
  EXPECT_EQ(from_toml.meshes[0].positions.size(), from_gltf.meshes[0].positions.size());
  for (std::size_t i = 0; i < from_toml.meshes[0].positions.size(); ++i)
    ASSERT_TRUE(same(from_toml.meshes[0].positions[i], from_gltf.meshes[0].positions[i]))
        << "vertex " << i;
  EXPECT_EQ(from_toml.meshes[0].tris, from_gltf.meshes[0].tris);
  for (int i = 0; i < 3; ++i)
    expect_same_affine(from_toml.instances[i].xform, from_gltf.instances[i].xform);

  const std::string a = bake(gltf, dir + "ao_gltf_from_gltf.bin");
  const std::string b = bake(toml, dir + "ao_gltf_from_toml.bin");
  ASSERT_GT(a.size(), 16u + 3 * 24);
  EXPECT_TRUE(a == b) << "the glTF and the TOML instance scene bake differently";
}

// bake --mode ao's .glb (gltf_writer.cpp) read back: the receivers' stored mesh once (its
// glTF meshes differ only in COLOR_0), each receiver's transform bit for bit, the float
// positions and the triangles.
TEST(AoGltf, GlbOutputReadsBackAsTheSameGeometry) {
  RTMINI_REQUIRE_GLTF();
  const AoScene scene = load_ao_scene(kInputs + "/spot_instances.toml");
  const SamplePlan plan = plan_samples(scene, 0, 3);
  AoResult result;
  result.scene = &scene;
  result.plan = &plan;
  result.values.assign(static_cast<std::size_t>(plan.total_vertices()), 0.5f);
  const std::string path = ::testing::TempDir() + "ao_gltf_round_trip.glb";
  write_ao_glb(path, result);

  const GltfScene back = read_gltf(path, GltfTextures::kIgnore);
  ASSERT_EQ(back.instances.size(), plan.receivers.size());
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& want = scene.instances[plan.receivers[r]];
    const GltfInstance& got = back.instances[r];
    EXPECT_EQ(back.same_geometry[got.mesh], back.same_geometry[back.instances[0].mesh]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) EXPECT_EQ(got.xform[i][j], want.xform.m[i][j]);
    const AoMesh& mesh = scene.meshes[want.mesh];
    const Mesh& read = back.meshes[got.mesh];
    ASSERT_EQ(read.positions.size(), mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      ASSERT_TRUE(same(read.positions[v], Vec3d(Vec3f(mesh.positions[v])))) << "vertex " << v;
    ASSERT_EQ(read.faces.size(), mesh.tris.size());
    for (std::size_t t = 0; t < mesh.tris.size(); ++t)
      ASSERT_EQ((std::array<int, 3>{read.faces[t].v[0], read.faces[t].v[1], read.faces[t].v[2]}),
                mesh.tris[t]);
  }
  // Read back as an AO scene, the receivers share one stored mesh again.
  const AoScene again = load_ao_scene(path);
  EXPECT_EQ(again.meshes.size(), 1u);
  EXPECT_EQ(again.instances.size(), plan.receivers.size());
}

}  // namespace
}  // namespace rtmini::ao
