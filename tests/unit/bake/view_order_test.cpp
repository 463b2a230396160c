// The storage order of a vertex's colours (view_order.hpp): a permutation of the stored
// viewpoints whose neighbouring slots are neighbouring directions, and the two conversions
// undo each other.
#include "view_order.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini::bake {
namespace {

// Mean angle between the directions of consecutive entries.
double mean_step(const std::vector<int>& views, int n) {
  double sum = 0;
  for (std::size_t s = 1; s < views.size(); ++s)
    sum += std::acos(
        std::min(1.0, double(dot(fibonacci_point(views[s - 1], n), fibonacci_point(views[s], n)))));
  return sum / double(views.size() - 1);
}

TEST(ViewOrder, IsAPermutationWithItsInverse) {
  for (const auto& [n, stored] : {std::pair{200, 200}, {300, 150}, {61, 61}, {2, 2}}) {
    const ViewOrder o = coherent_view_order(n, stored);
    ASSERT_EQ(o.order.size(), static_cast<std::size_t>(stored));
    std::vector<int> seen(stored, 0);
    for (int s = 0; s < stored; ++s) {
      ASSERT_GE(o.order[s], 0);
      ASSERT_LT(o.order[s], stored);
      ++seen[o.order[s]];
      EXPECT_EQ(o.slot[o.order[s]], s);
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), stored) << "n = " << n;
  }
}

TEST(ViewOrder, ConsecutiveSlotsAreCloseOnTheSphere) {
  for (int n : {200, 1000}) {
    std::vector<int> fibonacci(n);
    std::iota(fibonacci.begin(), fibonacci.end(), 0);
    const double coherent = mean_step(coherent_view_order(n, n).order, n);
    const double spacing = std::sqrt(4.0 * M_PI / n);  // about a viewpoint's spacing
    std::printf("N = %d: mean step %.3f rad coherent, %.3f Fibonacci, spacing %.3f\n", n, coherent,
                mean_step(fibonacci, n), spacing);
    EXPECT_LT(coherent, 1.5 * spacing);
    EXPECT_GT(mean_step(fibonacci, n), 5 * spacing);
  }
}

TEST(ViewOrder, ConversionsUndoEachOtherAndMoveOnlyViewDependentVertices) {
  const int n = 7;
  const ViewOrder o = coherent_view_order(n, n);
  // Vertices with 1, n, 1, n colours; colour x = the entry's index.
  const std::vector<std::int64_t> offset{0, 1, 1 + n, 2 + n, 2 + 2 * n};
  std::vector<Vec3f> colors(offset.back());
  for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = Vec3f(float(i), 0.f, 0.f);
  const std::vector<Vec3f> original = colors;
  to_storage_order(o, offset, colors);
  EXPECT_EQ(colors[0].x, 0.f);
  EXPECT_EQ(colors[1 + n].x, float(1 + n));
  for (int s = 0; s < n; ++s) EXPECT_EQ(colors[1 + s].x, float(1 + o.order[s])) << s;
  to_viewpoint_order(o, offset, colors);
  for (std::size_t i = 0; i < colors.size(); ++i) EXPECT_EQ(colors[i].x, original[i].x) << i;
}

}  // namespace
}  // namespace rtmini::bake
