#include "rtmini/io/obj_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini {
namespace {

constexpr const char* kMtl =
    "newmtl red\nKd 0.63 0.065 0.05\nKs 0.1 0.2 0.3\nNs 200\nNi 1.44\nd 0.5\nKe 0 0 0\n\n"
    "newmtl light\nKd 0.78 0.78 0.78\nKe 17 12 4\n";

constexpr const char* kObj =
    "# quads, a triangle, a pentagon, groups and materials\n"
    "mtllib box.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n"
    "vn 0 0 1\n"
    "o floor\n"
    "usemtl red\n"
    "f 1//1 2//1 3//1 4//1\n"
    "g lamp\n"
    "usemtl light\n"
    "f -5 -4 -3\n"
    "f 1 2 3 5 4\n"
    "o floor\n"
    "f 4 3 2 1\n";

TEST(ObjReader, QuadsGroupsAndMaterials) {
  test::TempDir dir;
  test::write_file(dir.file("box.mtl"), kMtl);
  test::write_file(dir.file("box.obj"), kObj);
  const Mesh m = read_mesh(dir.file("box.obj"));

  ASSERT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.positions[4].x, 0.5);
  EXPECT_EQ(m.positions[4].y, 1.5);

  ASSERT_EQ(m.materials.size(), 2u);
  const Material& red = m.materials[0];
  EXPECT_EQ(red.name, "red");
  EXPECT_FLOAT_EQ(red.diffuse.y, 0.065f);
  EXPECT_FLOAT_EQ(red.reflective.z, 0.3f);
  EXPECT_FLOAT_EQ(red.shininess, 200.f);
  EXPECT_FLOAT_EQ(red.ior, 1.44f);
  EXPECT_FLOAT_EQ(red.opacity, 0.5f);
  EXPECT_FLOAT_EQ(m.materials[1].emissive.x, 17.f);
  EXPECT_FLOAT_EQ(m.materials[1].emissive.z, 4.f);

  // quad, triangle, pentagon fanned into 3 triangles, quad again.
  ASSERT_EQ(m.faces.size(), 6u);
  EXPECT_EQ(m.faces[0].count, 4);
  EXPECT_EQ(m.faces[0].v, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.faces[0].material, 0);
  EXPECT_EQ(m.faces[1].count, 3);
  EXPECT_EQ(m.faces[1].v[0], 0);  // negative indices resolved
  EXPECT_EQ(m.faces[1].v[2], 2);
  EXPECT_EQ(m.faces[1].material, 1);
  EXPECT_EQ(m.faces[2].v, (std::array<int, 4>{0, 1, 2, -1}));
  EXPECT_EQ(m.faces[3].v, (std::array<int, 4>{0, 2, 4, -1}));
  EXPECT_EQ(m.faces[4].v, (std::array<int, 4>{0, 4, 3, -1}));
  EXPECT_EQ(m.faces[5].count, 4);

  ASSERT_EQ(m.objects.size(), 2u);
  EXPECT_EQ(m.objects[m.faces[0].object], "floor");
  EXPECT_EQ(m.objects[m.faces[1].object], "lamp");
  EXPECT_EQ(m.faces[2].object, m.faces[1].object);
  EXPECT_EQ(m.faces[5].object, m.faces[0].object);  // a repeated name shares its id
  EXPECT_EQ(m.triangle_count(), 1u * 2 + 1 + 3 + 2);
}

TEST(ObjReader, NoGroupsNoMaterials) {
  test::TempDir dir;
  test::write_file(dir.file("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Mesh m = read_obj(dir.file("t.obj"));
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].material, -1);
  EXPECT_EQ(m.objects, std::vector<std::string>{"default"});
}

TEST(ObjReader, MissingLibraryWithoutUsemtlIsHarmless) {
  test::TempDir dir;
  test::write_file(dir.file("d.obj"), "mtllib d.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Mesh m = read_obj(dir.file("d.obj"));
  EXPECT_EQ(m.faces.size(), 1u);
  EXPECT_TRUE(m.materials.empty());
}

// Object names as OBJ writers mean them: `g` joins its names with one space, `o` keeps the rest
// of its line as written, a bare `g`/`o` changes nothing, and a name gets its id at its first face
// (the same rules as tinyobjloader, which read_obj used before).
TEST(ObjReader, GroupAndObjectNames) {
  test::TempDir dir;
  test::write_file(dir.file("n.obj"),
                   "v 0 0 0\nv 1 0 0\nv 0 1 0\ng unused\ng\nf 1 2 3\ng a\tb  c\nf 1 2 3\n"
                   "o  spaced \nf 3 2 1\no\nf 1 3 2\ng a b c\nf 2 3 1\n");
  const Mesh m = read_obj(dir.file("n.obj"));
  ASSERT_EQ(m.faces.size(), 5u);
  EXPECT_EQ(m.objects, (std::vector<std::string>{"unused", "a b c", " spaced "}));
  const std::vector<int> expected{0, 1, 2, 2, 1};
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(m.faces[i].object, expected[i]);
}

// A face's material is the one its `usemtl` names if a library named before that statement
// defines it (-1 otherwise; a name defined in no library at all is an error). Of one `mtllib`
// statement's files the first not read before is read; a name keeps its first definition.
TEST(ObjReader, MaterialsKnownFromTheirLibraryOn) {
  test::TempDir dir;
  test::write_file(dir.file("l1.mtl"), "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n");
  test::write_file(dir.file("l2.mtl"), "newmtl b\nKd 0 0 1\nnewmtl c\nKd 1 1 0\n");
  test::write_file(dir.file("m.obj"),
                   "mtllib l1.mtl l2.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl c\nf 1 2 3\n"
                   "mtllib l1.mtl l2.mtl\nusemtl c\nf 1 2 3\nusemtl b\nf 1 2 3\n");
  const Mesh m = read_obj(dir.file("m.obj"));
  ASSERT_EQ(m.materials.size(), 4u);  // a b from l1, then b c from l2
  EXPECT_EQ(m.materials[3].name, "c");
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.faces[0].material, -1);  // l2 was not read yet
  EXPECT_EQ(m.faces[1].material, 3);
  EXPECT_EQ(m.faces[2].material, 1);  // l1's b
}

// CRLF line ends, a one-field `vt` (v = 0), negative texture-coordinate indices, `v//vn`.
TEST(ObjReader, TexcoordsAndCrlf) {
  test::TempDir dir;
  test::write_file(dir.file("t.obj"),
                   "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvt 0.25\r\nvt 0.5 0.75 1\r\nvn 0 0 1\r\n"
                   "f 1/-2 2/-1 3/1\r\nf 1//1 2//1 3//1\r\n");
  const Mesh m = read_obj(dir.file("t.obj"));
  ASSERT_EQ(m.texcoords.size(), 2u);
  EXPECT_EQ(m.texcoords[0].u, 0.25f);
  EXPECT_EQ(m.texcoords[0].v, 0.f);
  EXPECT_EQ(m.texcoords[1].v, 0.75f);
  ASSERT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(m.faces[0].uv, (std::array<int, 4>{0, 1, 0, -1}));
  EXPECT_EQ(m.faces[1].uv, (std::array<int, 4>{-1, -1, -1, -1}));
  EXPECT_EQ(m.faces[1].v, (std::array<int, 4>{0, 1, 2, -1}));
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    EXPECT_EQ(a.positions[i].x, b.positions[i].x);
    EXPECT_EQ(a.positions[i].y, b.positions[i].y);
    EXPECT_EQ(a.positions[i].z, b.positions[i].z);
  }
  ASSERT_EQ(a.texcoords.size(), b.texcoords.size());
  for (std::size_t i = 0; i < a.texcoords.size(); ++i) {
    EXPECT_EQ(a.texcoords[i].u, b.texcoords[i].u);
    EXPECT_EQ(a.texcoords[i].v, b.texcoords[i].v);
  }
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t i = 0; i < a.faces.size(); ++i) {
    EXPECT_EQ(a.faces[i].v, b.faces[i].v);
    EXPECT_EQ(a.faces[i].uv, b.faces[i].uv);
    EXPECT_EQ(a.faces[i].count, b.faces[i].count);
    EXPECT_EQ(a.faces[i].material, b.faces[i].material) << "face " << i;
    EXPECT_EQ(a.faces[i].object, b.faces[i].object) << "face " << i;
  }
  EXPECT_EQ(a.objects, b.objects);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i)
    EXPECT_EQ(a.materials[i].name, b.materials[i].name);
}

// Large files are read in pieces on several threads: pieces of a few lines (every line end a
// boundary somewhere) give the one-pass Mesh, with objects, materials, negative indices and
// libraries that span pieces, and the same first error.
TEST(ObjReader, PiecesReadLikeOnePass) {
  test::TempDir dir;
  test::write_file(dir.file("box.mtl"), kMtl);
  test::write_file(dir.file("box.obj"), kObj);
  test::write_file(dir.file("late.obj"),
                   std::string(kObj) +
                       "g\nf 1 2 3\nusemtl red\nv 2 2 2\nf -1 -2 -3\nmtllib box.mtl\n" +
                       "o other\nvt 0.5 0.5\nf 1/1 2/1 -1/-1\n");
  test::write_file(dir.file("bad.obj"), std::string(kObj) + "f 1 2 7\nv 1 2\n");
  const std::vector<std::string> files = {
      dir.file("box.obj"), dir.file("late.obj"),
      std::string(RTMINI_SCENES_DIR) + "/CornellBox-Original.obj",
      std::string(RTMINI_SCENES_DIR) + "/spot.obj"};
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const Mesh whole = detail::read_obj(file, 1u << 30, 1);
    for (const std::size_t piece : {8, 100, 4096})
      expect_same_mesh(detail::read_obj(file, piece, 64), whole);
  }
  std::string one_pass, pieces;
  try {
    (void)detail::read_obj(dir.file("bad.obj"), 1u << 30, 1);
  } catch (const InputError& e) {
    one_pass = e.what();
  }
  try {
    (void)detail::read_obj(dir.file("bad.obj"), 8, 64);
  } catch (const InputError& e) {
    pieces = e.what();
  }
  EXPECT_NE(one_pass.find("vertex index 7 out of range (5 defined so far)"), std::string::npos)
      << one_pass;
  EXPECT_EQ(pieces, one_pass);
}

TEST(ObjReader, UnknownExtensionAndMissingFile) {
  test::TempDir dir;
  EXPECT_THROW(read_mesh(dir.file("mesh.ply")), InputError);
  EXPECT_THROW(read_mesh(dir.file("absent.obj")), InputError);
}

// The bundled Cornell box (inputs/meshes): 72 vertices, 18 quads and the light's Ke.
TEST(ObjReader, CornellBoxBundled) {
  const std::string path = std::string(RTMINI_SCENES_DIR) + "/CornellBox-Original.obj";
  const Mesh m = read_obj(path);
  EXPECT_EQ(m.positions.size(), 72u);  // `grep -c "^\s*v\s"`; the README says 24
  EXPECT_EQ(m.faces.size(), 18u);
  bool has_light = false;
  for (const Material& mat : m.materials)
    has_light |= mat.name == "light" && mat.emissive.x == 17.f;
  EXPECT_TRUE(has_light);
  for (const Face& f : m.faces) EXPECT_EQ(f.count, 4);
}

}  // namespace
}  // namespace rtmini
