#include "rtmini/io/scene_file.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/scene_settings.hpp"

namespace rtmini {
namespace {

constexpr const char* kScene = R"(ambient = [0.1, 0.1, 0.1]

[camera]
position = [0, 1, 5]
look_at = [0, 1, 0]
fov_deg = 40
aperture = 0.05
shutter_open = 0.0
shutter_close = 0.5
velocity = [1, 0, 0]

[[lights]]
type = "quad"
corner = [-0.5, 1.98, -0.5]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
emission = [17, 12, 4]

[[lights]]
type = "point"
position = [0, 3, 0]
intensity = [5, 5, 5]

[[lights]]
type = "sphere"
center = [1, 2, 3]
radius = 0.25
emission = [2, 2, 2]

[[materials]]
name = "red"
kd = [0.9, 0.1, 0.1]

[[materials]]
name = "chrome"
ks = [0.95, 0.95, 0.95]
ns = 1000

[[meshes]]
file = "sub/tri.obj"
translate = [10, 0, 0]
rotate_deg = [0, 0, 90]
scale = 2

[[meshes]]
file = "sub/tri.obj"
material = "chrome"
scale = [1, 1, 3]

[[spheres]]
center = [0, 0.5, 0]
radius = 0.5
material = { kd = [0.2, 0.4, 0.6], ks = [0.5, 0.5, 0.5], ns = 50 }

[settings]
spp = 16
edges = { thickness = 2 }
)";

void write_scene(const test::TempDir& dir) {
  std::filesystem::create_directories(dir.file("sub"));
  test::write_file(dir.file("sub/tri.mtl"), "newmtl red\nKd 0.5 0.5 0.5\nKs 0.25 0 0\n");
  test::write_file(dir.file("sub/tri.obj"),
                   "mtllib tri.mtl\nv 1 0 0\nv 0 1 0\nv 0 0 1\no tri\nusemtl red\nf 1 2 3\n");
  test::write_file(dir.file("scene.toml"), kScene);
}

TEST(SceneFile, ParsesEverySection) {
  test::TempDir dir;
  write_scene(dir);
  const SceneDescription s = read_scene_file(dir.file("scene.toml"));
  EXPECT_TRUE(s.has_camera);
  EXPECT_EQ(s.camera.position.z, 5.0);
  EXPECT_EQ(s.camera.fov_deg, 40.0);
  EXPECT_EQ(s.camera.aperture, 0.05);
  EXPECT_EQ(s.camera.shutter_close, 0.5);
  EXPECT_EQ(s.camera.velocity.x, 1.0);
  EXPECT_EQ(s.camera.up.y, 1.0);  // default
  EXPECT_FLOAT_EQ(s.ambient.y, 0.1f);

  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, LightType::kQuad);
  EXPECT_EQ(s.lights[0].corner.y, 1.98);
  EXPECT_EQ(s.lights[0].emission.y, 12.f);
  EXPECT_EQ(s.lights[0].line, 12);
  EXPECT_EQ(s.lights[1].type, LightType::kPoint);
  EXPECT_EQ(s.lights[1].intensity.x, 5.f);
  EXPECT_EQ(s.lights[2].type, LightType::kSphere);
  EXPECT_EQ(s.lights[2].radius, 0.25);

  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.materials[0].kd.has_value());
  EXPECT_FALSE(s.materials[0].ks.has_value());
  EXPECT_EQ(*s.materials[1].ns, 1000.f);

  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].file, dir.file("sub/tri.obj"));
  EXPECT_EQ(s.meshes[0].scale.y, 2.0);
  EXPECT_EQ(s.meshes[0].rotate_deg.z, 90.0);
  EXPECT_EQ(s.meshes[1].scale.z, 3.0);
  EXPECT_EQ(s.meshes[1].material, "chrome");

  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(s.spheres[0].radius, 0.5);
  EXPECT_FLOAT_EQ(s.spheres[0].material.diffuse.z, 0.6f);
  EXPECT_FLOAT_EQ(s.spheres[0].material.shininess, 50.f);
  EXPECT_FLOAT_EQ(s.spheres[0].material.ior, 1.f);  // default kept

  EXPECT_EQ(s.settings->table["spp"].value<int>(), 16);
  EXPECT_NO_THROW(check_known_keys(s.settings->table, {"spp", "edges"}, s.path, "[settings]"));
  try {
    check_known_keys(s.settings->table, {"spp"}, s.path, "[settings]");
    FAIL() << "expected an unknown-key error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), s.path + ":57: unknown key 'edges' in [settings]");
  }
}

TEST(SceneFile, LoadsTransformedMeshesWithOverrides) {
  test::TempDir dir;
  write_scene(dir);
  const Mesh m = load_scene_meshes(read_scene_file(dir.file("scene.toml")));
  ASSERT_EQ(m.positions.size(), 6u);
  ASSERT_EQ(m.faces.size(), 2u);
  // Mesh 0: scale 2, then 90 deg about z maps (2,0,0) to (0,2,0), then +10 in x.
  EXPECT_NEAR(m.positions[0].x, 10.0, 1e-12);
  EXPECT_NEAR(m.positions[0].y, 2.0, 1e-12);
  EXPECT_NEAR(m.positions[1].x, 8.0, 1e-12);
  EXPECT_NEAR(m.positions[2].z, 2.0, 1e-12);
  // Mesh 1: non-uniform scale only, indices offset by 3.
  EXPECT_EQ(m.positions[5].z, 3.0);
  EXPECT_EQ(m.faces[1].v[0], 3);
  EXPECT_NE(m.faces[0].object, m.faces[1].object);
  ASSERT_EQ(m.objects.size(), 2u);
  // [[materials]] "red" overrides kd of the file's red but keeps its Ks.
  const Material& red = m.materials[m.faces[0].material];
  EXPECT_EQ(red.name, "red");
  EXPECT_FLOAT_EQ(red.diffuse.x, 0.9f);
  EXPECT_FLOAT_EQ(red.reflective.x, 0.25f);
  // The second mesh's faces all use "chrome".
  const Material& chrome = m.materials[m.faces[1].material];
  EXPECT_EQ(chrome.name, "chrome");
  EXPECT_FLOAT_EQ(chrome.reflective.y, 0.95f);
}

TEST(SceneFile, ReadsObjectMotionAndFirstObjects) {
  test::TempDir dir;
  write_scene(dir);
  test::write_file(dir.file("moving.toml"), R"([[meshes]]
file = "sub/tri.obj"

[[meshes]]
file = "sub/tri.obj"
velocity = [1, 0, -2]
spin_axis = [0, 0, 3]
spin_deg = 45

[[spheres]]
center = [0, 0, 0]
radius = 1
velocity = [0, 2, 0]
)");
  const SceneDescription s = read_scene_file(dir.file("moving.toml"));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_FALSE(s.meshes[0].motion.moves());
  EXPECT_TRUE(s.meshes[1].motion.moves());
  EXPECT_EQ(s.meshes[1].motion.velocity.z, -2.0);
  EXPECT_EQ(s.meshes[1].motion.spin_axis.z, 3.0);
  EXPECT_EQ(s.meshes[1].motion.spin_deg, 45.0);
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_TRUE(s.spheres[0].motion.moves());
  EXPECT_EQ(s.spheres[0].motion.velocity.y, 2.0);
  std::vector<int> first_object;
  const Mesh m = load_scene_meshes(s, &first_object);
  ASSERT_EQ(first_object.size(), 2u);
  EXPECT_EQ(first_object[0], 0);
  EXPECT_EQ(first_object[1], 1);
  EXPECT_EQ(m.faces[1].object, 1);
}

TEST(SceneFile, MinimalSceneUsesDefaults) {
  test::TempDir dir;
  test::write_file(dir.file("empty.toml"), "# nothing\n");
  const SceneDescription s = read_scene_file(dir.file("empty.toml"));
  EXPECT_FALSE(s.has_camera);
  EXPECT_TRUE(s.lights.empty() && s.meshes.empty() && s.spheres.empty());
  ASSERT_NE(s.settings, nullptr);
  EXPECT_TRUE(s.settings->table.empty());
}

}  // namespace
}  // namespace rtmini
