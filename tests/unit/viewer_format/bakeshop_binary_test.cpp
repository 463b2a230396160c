#include "rtmini/io/bakeshop_binary.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "io_test_util.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini {
namespace {

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Field-by-field, bit-exact comparison of two meshes (names included).
void expect_identical(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i)
    EXPECT_TRUE(same_bits(a.positions[i], b.positions[i])) << "position " << i;
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    const Material& x = a.materials[i];
    const Material& y = b.materials[i];
    EXPECT_TRUE(same_bits(x.diffuse, y.diffuse) && same_bits(x.reflective, y.reflective) &&
                same_bits(x.emissive, y.emissive) && same_bits(x.shininess, y.shininess) &&
                same_bits(x.ior, y.ior) && same_bits(x.opacity, y.opacity))
        << "material " << i;
  }
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t i = 0; i < a.faces.size(); ++i) {
    EXPECT_EQ(a.faces[i].count, b.faces[i].count) << "face " << i;
    EXPECT_EQ(a.faces[i].v, b.faces[i].v) << "face " << i;
    EXPECT_EQ(a.faces[i].material, b.faces[i].material) << "face " << i;
    EXPECT_EQ(a.faces[i].object, b.faces[i].object) << "face " << i;
  }
  EXPECT_EQ(a.objects, b.objects);
  EXPECT_EQ(a.viewpoints.offsets, b.viewpoints.offsets);
  ASSERT_EQ(a.viewpoints.dirs.size(), b.viewpoints.dirs.size());
  ASSERT_EQ(a.viewpoints.colors.size(), b.viewpoints.colors.size());
  for (std::size_t i = 0; i < a.viewpoints.dirs.size(); ++i) {
    EXPECT_TRUE(same_bits(a.viewpoints.dirs[i], b.viewpoints.dirs[i])) << "dir " << i;
    EXPECT_TRUE(same_bits(a.viewpoints.colors[i], b.viewpoints.colors[i])) << "colour " << i;
  }
}

// Irregular map: per-vertex direction sets of different sizes, a vertex without
// viewpoints, a uniform vertex, values needing every digit, a quad and a triangle.
const char* const kIrregularMap =
    "0.1 -0.3333333333333333 1e-300\n"
    "| 0 0 -1 0.5 0.25 0.125\n"
    "| 0.57735026 -0.57735026 0.57735026 0.14285715 3.4028235e+38 0\n"
    "2.5e+10 -0 7\n"
    "1 2 3\n"
    "| 1e-08 1 0 0.3 0.3 0.3\n"
    "| 0 -1 0 0.3 0.3 0.3\n"
    "| 1 0 0 0.3 0.3 0.3\n"
    "-4 0.3 9.9\n"
    "| 0 -1 0 1 1 1\n"
    "\n"
    ": 0.1 0.2 0.33333334  0 0 0  0 0 0\n"
    ": 0.8 0.8 0.8  0.725 0.71 0.68  17 12 4\n"
    "\n"
    "0 1 2 3 1\n"
    "3 2 0 -1\n"
    "!\n";

// The baker's layout: every vertex has the same N Fibonacci directions.
Mesh make_fibonacci_mesh(int n, bool uniform_first) {
  Mesh m;
  m.positions = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {1.0, 1.0, 0.0}, {0.0, 1.0, 0.0}};
  Face quad;
  quad.count = 4;
  quad.v = {0, 1, 2, 3};
  m.faces = {quad};
  m.objects = {"fib"};
  m.viewpoints.offsets.push_back(0);
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    for (int i = 0; i < n; ++i) {
      const Vec3 d = fibonacci_point(i, n);
      m.viewpoints.dirs.push_back({float(d.x), float(d.y), float(d.z)});
      const float c = (uniform_first && v == 0) ? 0.5f : 0.01f * float(i) + 0.1f * float(v);
      m.viewpoints.colors.push_back({c, 1.f - c, 0.25f});
    }
    m.viewpoints.offsets.push_back(m.viewpoints.dirs.size());
  }
  return m;
}

std::size_t file_size(const std::string& path) { return test::read_file(path).size(); }

TEST(BakeshopBinary, TextToBinaryRoundTripIsIdentical) {
  test::TempDir dir;
  test::write_file(dir.file("irregular.bs"), kIrregularMap);
  const Mesh text = read_bakeshop(dir.file("irregular.bs"));
  write_bakeshop_binary(dir.file("irregular.bsb"), text);
  EXPECT_EQ(test::count_files(dir.path()), 2);  // no temporary left behind
  const Mesh binary = read_bakeshop_binary(dir.file("irregular.bsb"));
  expect_identical(text, binary);
  // And back to text, byte for byte.
  EXPECT_EQ(format_bakeshop(binary), std::string(kIrregularMap));
}

TEST(BakeshopBinary, RawMapWithoutViewpoints) {
  test::TempDir dir;
  test::write_file(dir.file("raw.bs"), "0 0 0\n1 0 0\n0 1 0\n\n\n0 1 2 -1\n!\n");
  const Mesh text = read_bakeshop(dir.file("raw.bs"));
  ASSERT_TRUE(text.viewpoints.offsets.empty());
  write_bakeshop_binary(dir.file("raw.bsb"), text);
  expect_identical(text, read_bakeshop_binary(dir.file("raw.bsb")));
}

TEST(BakeshopBinary, SharedDirectionsAndUniformVerticesAreStoredOnce) {
  test::TempDir dir;
  const int n = 50;
  const Mesh varied = make_fibonacci_mesh(n, false);
  const Mesh one_uniform = make_fibonacci_mesh(n, true);
  write_bakeshop_binary(dir.file("varied.bsb"), varied);
  write_bakeshop_binary(dir.file("uniform.bsb"), one_uniform);
  expect_identical(varied, read_bakeshop_binary(dir.file("varied.bsb")));
  expect_identical(one_uniform, read_bakeshop_binary(dir.file("uniform.bsb")));

  // Expected sizes from the documented layout: header, 4 float32 positions, counts,
  // uniform flags, N shared directions, colours, one face, one object name.
  auto pad8 = [](std::size_t b) { return (b + 7) / 8 * 8; };
  auto expected = [&](std::size_t colors) {
    return 64 + pad8(4 * 12) + pad8(4 * 4) + pad8(4) + pad8(n * 12) + pad8(colors * 12) + pad8(24) +
           pad8(4 + 3);
  };
  EXPECT_EQ(file_size(dir.file("varied.bsb")), expected(4 * n));
  EXPECT_EQ(file_size(dir.file("uniform.bsb")), expected(3 * n + 1));

  // Break the sharing: one vertex gets a different direction -> stored per vertex.
  Mesh unshared = varied;
  unshared.viewpoints.dirs.back().x += 0.25f;
  write_bakeshop_binary(dir.file("unshared.bsb"), unshared);
  expect_identical(unshared, read_bakeshop_binary(dir.file("unshared.bsb")));
  EXPECT_EQ(file_size(dir.file("unshared.bsb")), expected(4 * n) + pad8(4 * n * 12) - pad8(n * 12));
}

TEST(BakeshopBinary, HalfColoursRoundToNearestAndClamp) {
  test::TempDir dir;
  Mesh m = make_fibonacci_mesh(4, false);
  const std::vector<Vec3f> values = {{1.f, 0.1f, 1e-7f},
                                     {-2.5f, 70000.f, 65504.f},
                                     {0.f, -0.f, 1.f / 3.f},
                                     {3e-5f, 6.1035156e-05f, 1e4f}};
  for (std::size_t k = 0; k < values.size(); ++k) m.viewpoints.colors[k] = values[k];
  write_bakeshop_binary(dir.file("full.bsb"), m);
  write_bakeshop_binary(dir.file("half.bsb"), m, BakeshopBinaryOptions{true});
  EXPECT_LT(file_size(dir.file("half.bsb")), file_size(dir.file("full.bsb")));
  const Mesh back = read_bakeshop_binary(dir.file("half.bsb"));
  const std::vector<Vec3f> expect = {{1.f, 0.0999755859375f, 1.1920929e-07f},
                                     {-2.5f, 65504.f, 65504.f},
                                     {0.f, -0.f, 0.333251953125f},
                                     {2.9981136e-05f, 6.1035156e-05f, 10000.f}};
  for (std::size_t k = 0; k < expect.size(); ++k)
    EXPECT_TRUE(same_bits(back.viewpoints.colors[k], expect[k]))
        << k << ": " << back.viewpoints.colors[k].x << " " << back.viewpoints.colors[k].y << " "
        << back.viewpoints.colors[k].z;
  for (std::size_t k = 0; k < m.viewpoints.colors.size(); ++k) {
    const Vec3f& a = m.viewpoints.colors[k];
    const Vec3f& b = back.viewpoints.colors[k];
    for (int c = 0; c < 3; ++c) {
      const float x = (&a.x)[c];
      const float y = (&b.x)[c];
      if (std::fabs(x) <= 65504.f && std::fabs(x) >= 6.1035156e-05f) {
        EXPECT_LE(std::fabs(x - y), std::fabs(x) * 0x1p-11f) << k;
      }
    }
  }
}

TEST(BakeshopBinary, Float64PositionsOnlyWhenNeeded) {
  test::TempDir dir;
  Mesh m = make_fibonacci_mesh(3, false);
  write_bakeshop_binary(dir.file("f32.bsb"), m);
  m.positions[2].x = 0.1;  // not a float
  write_bakeshop_binary(dir.file("f64.bsb"), m);
  EXPECT_EQ(file_size(dir.file("f64.bsb")), file_size(dir.file("f32.bsb")) + 4 * 12);
  expect_identical(m, read_bakeshop_binary(dir.file("f64.bsb")));
}

// Patches bytes of a valid file and expects an InputError naming the file and the reason.
class BadBinary : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_file(dir_.file("good.bs"), kIrregularMap);
    write_bakeshop_binary(dir_.file("good.bsb"), read_bakeshop(dir_.file("good.bs")));
    bytes_ = test::read_file(dir_.file("good.bsb"));
  }
  void expect_error(const std::string& bytes, const std::string& reason) {
    test::write_file(dir_.file("bad.bsb"), bytes);
    try {
      read_bakeshop_binary(dir_.file("bad.bsb"));
      FAIL() << "no error, expected: " << reason;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(dir_.file("bad.bsb") + ": ", 0), 0u) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
    }
  }
  template <class T>
  std::string patched(std::size_t at, T value) const {
    std::string b = bytes_;
    std::memcpy(b.data() + at, &value, sizeof(T));  // the test host is little-endian
    return b;
  }
  // Offsets in the irregular map's file: 4 float64 positions (0.1 is not a float).
  static constexpr std::size_t kCounts = 64 + 96;
  static constexpr std::size_t kUniform = kCounts + 16;
  static constexpr std::size_t kDirs = kUniform + 8;
  static constexpr std::size_t kColors = kDirs + 6 * 12;
  static constexpr std::size_t kMaterials = kColors + 4 * 12;
  static constexpr std::size_t kFaces = kMaterials + 2 * 48;

  test::TempDir dir_;
  std::string bytes_;
};

TEST_F(BadBinary, LayoutOffsetsMatchTheDocumentation) {
  // A check of the fixture itself, so the patches below hit the fields they name.
  std::uint32_t counts[4];
  std::memcpy(counts, bytes_.data() + kCounts, sizeof(counts));
  EXPECT_EQ(counts[0], 2u);
  EXPECT_EQ(counts[1], 0u);
  EXPECT_EQ(counts[2], 3u);
  EXPECT_EQ(counts[3], 1u);
  EXPECT_EQ(bytes_[kUniform + 2], 1);
  float f;
  std::memcpy(&f, bytes_.data() + kMaterials + 4, 4);
  EXPECT_EQ(f, 0.2f);
  std::int32_t v;
  std::memcpy(&v, bytes_.data() + kFaces + 4 * 6 + 12, 4);
  EXPECT_EQ(v, -1);
}

TEST_F(BadBinary, WrongMagic) { expect_error("BSB2" + bytes_.substr(4), "magic"); }

TEST_F(BadBinary, UnknownFlags) {
  expect_error(patched<std::uint32_t>(4, 0x104u), "unknown flags");
}

TEST_F(BadBinary, EveryTruncationIsAnError) {
  for (std::size_t n = 0; n < bytes_.size(); n += 7) {
    SCOPED_TRACE(n);
    expect_error(bytes_.substr(0, n), n < 64 ? "magic" : "truncated");
  }
}

TEST_F(BadBinary, NanColour) {
  expect_error(patched(kColors + 4, std::nanf("")), "non-finite value in a colour");
}

TEST_F(BadBinary, InfiniteDirection) {
  expect_error(patched(kDirs, HUGE_VALF), "non-finite value in a direction");
}

TEST_F(BadBinary, VertexIndexOutOfRange) {
  expect_error(patched<std::int32_t>(kFaces + 8, 4), "face 0: vertex index 4 out of range");
}

TEST_F(BadBinary, MaterialIndexOutOfRange) {
  expect_error(patched<std::int32_t>(kFaces + 24 + 16, 2), "face 1: material index 2");
}

TEST_F(BadBinary, CountsDisagreeWithHeader) {
  expect_error(patched<std::uint32_t>(kCounts + 4, 5), "directions");
}

TEST_F(BadBinary, UniformFlagOnVertexWithoutViewpoints) {
  expect_error(patched<std::uint8_t>(kUniform + 1, 1), "vertex 1: invalid uniform flag");
}

// The viewer's bundled test map is committed as text and binary; both must hold one mesh.
TEST(BakeshopBinary, ViewerTestMapTextAndBinaryAgree) {
  const std::string base = std::string(RTMINI_VIEWER_DATA_DIR) + "/quad_zsplit";
  Mesh text = read_bakeshop(base + ".bs");
  Mesh binary = read_bakeshop_binary(base + ".bsb");
  expect_identical(text, binary);
  // The committed .bsb was written by the viewer's JS generator: same bytes as C++ writes.
  test::TempDir dir;
  write_bakeshop_binary(dir.file("quad_zsplit.bsb"), text);
  EXPECT_EQ(test::read_file(dir.file("quad_zsplit.bsb")), test::read_file(base + ".bsb"));
}

// `bake -o X.bs` and `bake -o X.bsb` of one bake load to the identical mesh. The files come from
// the ctest bake.binary_output (tests/regression/bake/bake_checks.sh, case "binary"), which
// runs bake and then this test with RTMINI_BAKED_BS / RTMINI_BAKED_BSB set.
TEST(BakeshopBinary, BakedTextAndBinaryOutputsAgree) {
  const char* text_path = std::getenv("RTMINI_BAKED_BS");
  const char* binary_path = std::getenv("RTMINI_BAKED_BSB");
  if (!text_path || !binary_path) GTEST_SKIP() << "RTMINI_BAKED_BS / RTMINI_BAKED_BSB not set";
  Mesh text = read_bakeshop(text_path);
  const Mesh binary = read_bakeshop_binary(binary_path);
  EXPECT_FALSE(text.viewpoints.empty());
  // .bs has no object names: its reader names the one object after the file, the binary
  // form keeps the name bake was given. Everything else must match bit for bit.
  ASSERT_EQ(text.objects.size(), binary.objects.size());
  text.objects = binary.objects;
  expect_identical(text, binary);
}

// The viewer's malformed-map test expects the C++ reader's message for the same file.
TEST(BakeshopBinary, ViewerBadMapMessageMatchesTheCppReader) {
  const std::string path = std::string(RTMINI_VIEWER_DATA_DIR) + "/bad_face.bs";
  try {
    read_bakeshop(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":9: vertex index 7 out of range [0, 4)");
  }
}

}  // namespace
}  // namespace rtmini
