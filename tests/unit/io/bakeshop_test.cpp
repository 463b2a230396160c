#include "rtmini/io/bakeshop.hpp"

#include <gtest/gtest.h>

#include <cstring>

#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"

namespace rtmini {
namespace {

// Values chosen to need all 17 (9) significant digits, plus tiny, huge and -0.
Mesh make_baked_mesh() {
  Mesh m;
  m.positions = {{0.1, -1.0 / 3.0, 1e-300}, {2.5e10, -0.0, 7.0}, {1.0, 2.0, 3.0}, {-4.0, 0.3, 9.9}};
  m.materials.resize(2);
  m.materials[0].diffuse = {0.1f, 0.2f, 1.f / 3.f};
  m.materials[1].emissive = {17.f, 12.f, 4.f};
  m.materials[1].reflective = {0.725f, 0.71f, 0.68f};
  Face quad;
  quad.count = 4;
  quad.v = {0, 1, 2, 3};
  quad.material = 1;
  Face tri;
  tri.v = {3, 2, 0, -1};
  tri.material = -1;
  m.faces = {quad, tri};
  m.objects = {"baked"};
  // Vertex 1 has no viewpoints; the others one or two.
  m.viewpoints.offsets = {0, 2, 2, 3, 4};
  m.viewpoints.dirs = {{0.f, 0.f, -1.f},
                       {0.57735026f, -0.57735026f, 0.57735026f},
                       {1e-8f, 1.f, 0.f},
                       {0.f, -1.f, 0.f}};
  m.viewpoints.colors = {
      {0.5f, 0.25f, 0.125f}, {1.f / 7.f, 3.4028235e38f, 0.f}, {0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}};
  return m;
}

template <class T>
void expect_same_bits(const Vec3T<T>& a, const Vec3T<T>& b) {
  EXPECT_EQ(std::memcmp(&a, &b, sizeof(a)), 0)
      << a.x << " " << a.y << " " << a.z << " vs " << b.x << " " << b.y << " " << b.z;
}

TEST(Bakeshop, RoundTripValuesAndBytes) {
  test::TempDir dir;
  const Mesh mesh = make_baked_mesh();
  write_bakeshop(dir.file("a.bs"), mesh);
  EXPECT_EQ(test::count_files(dir.path()), 1);
  const Mesh back = read_bakeshop(dir.file("a.bs"));

  ASSERT_EQ(back.positions.size(), mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    expect_same_bits(back.positions[i], mesh.positions[i]);
  ASSERT_EQ(back.materials.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    expect_same_bits(back.materials[i].diffuse, mesh.materials[i].diffuse);
    expect_same_bits(back.materials[i].reflective, mesh.materials[i].reflective);
    expect_same_bits(back.materials[i].emissive, mesh.materials[i].emissive);
  }
  ASSERT_EQ(back.faces.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.faces[i].count, mesh.faces[i].count);
    EXPECT_EQ(back.faces[i].v, mesh.faces[i].v);
    EXPECT_EQ(back.faces[i].material, mesh.faces[i].material);
  }
  EXPECT_EQ(back.viewpoints.offsets, mesh.viewpoints.offsets);
  ASSERT_EQ(back.viewpoints.dirs.size(), mesh.viewpoints.dirs.size());
  for (std::size_t i = 0; i < mesh.viewpoints.dirs.size(); ++i) {
    expect_same_bits(back.viewpoints.dirs[i], mesh.viewpoints.dirs[i]);
    expect_same_bits(back.viewpoints.colors[i], mesh.viewpoints.colors[i]);
  }

  write_bakeshop(dir.file("b.bs"), back);
  EXPECT_EQ(test::read_file(dir.file("a.bs")), test::read_file(dir.file("b.bs")));
}

TEST(Bakeshop, ReadsHandWrittenFile) {
  test::TempDir dir;
  test::write_file(dir.file("seed.bs"),
                   "1.0 0.0 1.0\n| 0 0 -1 0.5 0.5 0.5\n-1.0 0.0 1.0\n-1.0 0.0 -1.0\n"
                   "1.0 0.0 -1.0\n\n: 0 0 1  0 0 0  0 0 0\n: 1 0 0 0 0 0 0.5 0.5 0.5\n\n"
                   "0 1 2 3 0\n0 3 2 1 1\n1 2 3 -1\n!\n");
  const Mesh m = read_mesh(dir.file("seed.bs"));
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[1].x, -1.0);
  EXPECT_EQ(m.positions[3].z, -1.0);
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].diffuse.z, 1.f);
  EXPECT_EQ(m.materials[1].emissive.y, 0.5f);
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.faces[1].v[1], 3);
  EXPECT_EQ(m.faces[1].material, 1);
  EXPECT_EQ(m.faces[2].count, 3);
  EXPECT_EQ(m.faces[2].material, -1);
  EXPECT_EQ(m.viewpoints.offsets, (std::vector<std::size_t>{0, 1, 1, 1, 1}));
  EXPECT_EQ(m.viewpoints.colors[0].y, 0.5f);
  EXPECT_EQ(m.objects, std::vector<std::string>{"seed"});
}

TEST(Bakeshop, EmptySectionsRoundTrip) {
  test::TempDir dir;
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Face f;
  f.v = {0, 1, 2, -1};
  m.faces = {f};
  const std::string text = format_bakeshop(m);
  EXPECT_EQ(text, "0 0 0\n1 0 0\n0 1 0\n\n\n0 1 2 -1\n!\n");
  test::write_file(dir.file("e.bs"), text);
  const Mesh back = read_bakeshop(dir.file("e.bs"));
  EXPECT_TRUE(back.materials.empty());
  EXPECT_TRUE(back.viewpoints.offsets.empty());
  EXPECT_EQ(format_bakeshop(back), text);

  test::write_file(dir.file("nothing.bs"), "\n\n!\n");
  const Mesh empty = read_bakeshop(dir.file("nothing.bs"));
  EXPECT_TRUE(empty.positions.empty() && empty.faces.empty());
}

TEST(Bakeshop, UniformVertexEqualsRepeatedColours) {
  const Vec3f dirs[3] = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}};
  const Vec3f color{0.25f, 0.5f, 0.75f};
  const Vec3f colors[3] = {color, color, color};
  const Vec3d p{1.5, -2.0, 0.1};
  EXPECT_EQ(format_bakeshop_vertex_uniform(p, dirs, 3, color),
            format_bakeshop_vertex(p, dirs, colors, 3));
  EXPECT_EQ(format_bakeshop_vertex(p, dirs, colors, 1), "1.5 -2 0.1\n| 1 0 0 0.25 0.5 0.75\n");
}

TEST(Bakeshop, AcceptsCrlfLineEndings) {
  test::TempDir dir;
  test::write_file(dir.file("crlf.bs"), "0 0 0\r\n1 0 0\r\n0 1 0\r\n\r\n\r\n0 1 2 -1\r\n!\r\n");
  EXPECT_EQ(read_bakeshop(dir.file("crlf.bs")).faces.size(), 1u);
}

}  // namespace
}  // namespace rtmini
