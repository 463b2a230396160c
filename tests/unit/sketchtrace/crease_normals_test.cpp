// Smoothing groups by face-to-face angle (crease_normals.hpp): a cube's 90 degree edges are
// creases at the default 60 degrees (every corner keeps its face's normal), a fine icosphere is
// one group per vertex, and two triangles folded along their shared edge join below the crease
// angle and split above it.
#include "crease_normals.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "rtmini/scene/primitives.hpp"

namespace rtmini::sketch {
namespace {

CornerNormals split(const Mesh& m, double crease_deg) {
  return crease_split_normals(m.positions, triangulate(m).vertices,
                              std::cos(crease_deg * math::kPi / 180.0));
}

Vec3d face_normal(const Mesh& m, const std::array<int, 3>& t) {
  return normalize(
      cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
}

TEST(CreaseNormals, CubeEdgesAreCreasesAtSixtyDegrees) {
  Mesh m;
  append_box(m, Vec3d(-1.0), Vec3d(1.0), -1, 0, /*inward=*/true);
  ASSERT_EQ(m.positions.size(), 8u);  // shared corners: the old per-vertex test smoothed them
  const auto tris = triangulate(m).vertices;
  const CornerNormals c = split(m, 60);
  EXPECT_EQ(c.normals.size(), 24u);  // 8 corners x 3 faces
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3d n = c.normals[c.of_corner[t][k]];
      EXPECT_NEAR(length(n - face_normal(m, tris[t])), 0.0, 1e-12) << "triangle " << t;
    }
  // Above 90 degrees the cube is smooth: one normal per corner, leaning into all three faces
  // (area-weighted by triangles: a face split through the corner counts twice).
  const CornerNormals smooth = split(m, 100);
  EXPECT_EQ(smooth.normals.size(), 8u);
  for (const Vec3d& n : smooth.normals)
    for (int a = 0; a < 3; ++a) EXPECT_GE(std::fabs(n[a]), 1.0 / std::sqrt(6.0) - 1e-12);
}

TEST(CreaseNormals, FineSphereIsOneGroupPerVertex) {
  Mesh m;
  append_icosphere(m, Vec3d(0.0), 1.0, 3, -1, 0);
  const CornerNormals c = split(m, 60);
  EXPECT_EQ(c.normals.size(), m.positions.size());
  double worst = 0;
  const auto tris = triangulate(m).vertices;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, length(c.normals[c.of_corner[t][k]] - m.positions[tris[t][k]]));
  EXPECT_LT(worst, 0.02);  // the area-weighted normal of a vertex is nearly its radius
}

// Two unit right triangles sharing the edge (0,0,0)-(0,1,0), the second turned by `fold_deg`.
Mesh folded_pair(double fold_deg) {
  const double a = fold_deg * math::kPi / 180.0;
  Mesh m;
  m.positions = {{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {std::cos(a), 0, std::sin(a)}};
  Face f0, f1;
  f0.v = {0, 1, 2, -1};
  f1.v = {0, 3, 1, -1};
  m.faces = {f0, f1};
  return m;
}

TEST(CreaseNormals, FoldJoinsBelowTheCreaseAngleAndSplitsAbove) {
  // Corners 0 and 1 are shared: one group each when the faces meet at 50 degrees, two at 70.
  EXPECT_EQ(split(folded_pair(50), 60).normals.size(), 4u);  // 2 shared + 2 unshared corners
  EXPECT_EQ(split(folded_pair(70), 60).normals.size(), 6u);
  EXPECT_EQ(split(folded_pair(70), 75).normals.size(), 4u);
  // Faces wound against each other point more than 90 degrees apart: never one group.
  Mesh flipped = folded_pair(10);
  std::swap(flipped.faces[1].v[1], flipped.faces[1].v[2]);
  EXPECT_EQ(split(flipped, 60).normals.size(), 6u);
}

}  // namespace
}  // namespace rtmini::sketch
