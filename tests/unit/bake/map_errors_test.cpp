// Map-against-reference errors (map_errors.hpp): the metrics of the stored colours on a
// hand-made map, a view-independent vertex compared at every viewpoint, and references that do
// not fit the scene.
#include "map_errors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini::bake {
namespace {

// Two vertices, N = 2: vertex 0 has one colour, vertex 1 two.
TEST(MapErrors, MetricsOverEveryVertexAndViewpoint) {
  const std::vector<Vec3f> map{{1, 1, 1}, {2, 2, 2}, {0, 0, 0}};
  const std::vector<std::int64_t> offset{0, 1, 3};
  const ReferenceMap ref{2, {{1, 1, 1}, {1, 1, 1}, {2, 2, 2}, {0, 0, 1}}};
  const MapErrors self =
      compare_stored(map, offset, {2, {{1, 1, 1}, {1, 1, 1}, {2, 2, 2}, {0, 0, 0}}});
  EXPECT_EQ(self.entries, 4);
  EXPECT_EQ(self.mean_abs, 0.0);
  EXPECT_EQ(self.max_abs, 0.0);
  const MapErrors e = compare_stored(map, offset, ref);
  // Differences: 0,0,0 | 0,0,0 | 0,0,0 | 0,0,-1 over 12 values.
  EXPECT_DOUBLE_EQ(e.mean_abs, 1.0 / 12);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(1.0 / 12));
  EXPECT_DOUBLE_EQ(e.rel_mse, 1.0 / 1.01 / 12);
  EXPECT_DOUBLE_EQ(e.max_abs, 1.0);
  EXPECT_DOUBLE_EQ(e.mean_reference, 13.0 / 12);
  EXPECT_EQ(e.view_dependent, 2);
  EXPECT_DOUBLE_EQ(e.view_dependent_rmse, std::sqrt(1.0 / 6));
  EXPECT_DOUBLE_EQ(e.view_independent_rmse, 0.0);
}

Mesh two_vertex_map(int n, double x1, int short_vertex = -1) {
  Mesh m;
  m.positions = {{0, 0, 0}, {x1, 0, 0}, {0, 1, 0}};
  Face f;
  f.v = {0, 1, 2, -1};
  m.faces = {f};
  m.viewpoints.offsets = {0};
  for (int v = 0; v < 3; ++v) {
    for (int i = 0; i < (v == short_vertex ? n - 1 : n); ++i) {
      m.viewpoints.dirs.push_back(Vec3f(fibonacci_point(i, n)));
      m.viewpoints.colors.push_back({float(v), float(i), 0.f});
    }
    m.viewpoints.offsets.push_back(m.viewpoints.dirs.size());
  }
  return m;
}

TEST(MapErrors, ReferenceMustFitTheScene) {
  const std::string path = ::testing::TempDir() + "rtmini_map_errors_ref.bs";
  write_bakeshop(path, two_vertex_map(5, 1.0));
  Mesh scene = two_vertex_map(5, 1.0);
  const ReferenceMap ref = read_reference_map(path, scene);
  EXPECT_EQ(ref.viewpoints, 5);
  ASSERT_EQ(ref.colors.size(), 15u);
  EXPECT_EQ(ref.colors[2 * 5 + 3].x, 2.f);
  EXPECT_EQ(ref.colors[2 * 5 + 3].y, 3.f);
  EXPECT_THROW(read_reference_map(path, two_vertex_map(5, 2.0)), InputError);  // moved vertex
  scene.positions.push_back({5, 5, 5});
  EXPECT_THROW(read_reference_map(path, scene), InputError);  // another vertex count
  write_bakeshop(path, two_vertex_map(5, 1.0, 1));
  EXPECT_THROW(read_reference_map(path, two_vertex_map(5, 1.0)), InputError);  // uneven N
  std::remove(path.c_str());
}

}  // namespace
}  // namespace rtmini::bake
