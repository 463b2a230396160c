// The Kitchen's vertex batches: any batch size, every vertex in exactly one batch, and cost
// balance giving batches of about equal work.
#include <gtest/gtest.h>

#include "kitchen.hpp"

namespace rtmini::bake {
namespace {

BakeSceneHost scene_with(int vertices, int reflective_from, int n) {
  BakeSceneHost s;
  s.normal.assign(vertices, Vec3(0, 0, 1));
  s.color_offset.assign(vertices + 1, 0);
  for (int v = 0; v < vertices; ++v)
    s.color_offset[v + 1] = s.color_offset[v] + (v >= reflective_from ? n : 1);
  return s;
}

void expect_tiling(const std::vector<Batch>& b, std::int64_t vertices, int ranks) {
  ASSERT_FALSE(b.empty());
  EXPECT_EQ(b.front().begin, 0);
  EXPECT_EQ(b.back().end, vertices);
  for (std::size_t i = 0; i < b.size(); ++i) {
    EXPECT_LT(b[i].begin, b[i].end);
    EXPECT_GE(b[i].rank, 0);
    EXPECT_LT(b[i].rank, ranks);
    if (i > 0) {
      EXPECT_EQ(b[i].begin, b[i - 1].end);
    }
  }
}

// Every rank's counted cost within 2 % of the mean and its colours within `cap` x the mean, over
// the (possibly several) ranges each rank owns.
void expect_cost_and_colours_balanced(const BakeSceneHost& s, const std::vector<Batch>& b,
                                      const std::vector<double>& cost, int ranks, double cap) {
  std::vector<double> rank_cost(ranks, 0.0), rank_colors(ranks, 0.0);
  double total = 0;
  for (const Batch& x : b)
    for (std::int64_t v = x.begin; v < x.end; ++v) {
      rank_cost[x.rank] += cost[v];
      rank_colors[x.rank] += double(s.color_count(v));
      total += cost[v];
    }
  for (int r = 0; r < ranks; ++r) {
    EXPECT_LE(rank_cost[r], 1.02 * total / ranks) << r;
    EXPECT_LE(rank_colors[r], cap * double(s.colors()) / ranks) << r;
  }
}

TEST(BakeBatches, AnyBatchSizeTilesTheVertices) {
  const BakeSceneHost s = scene_with(1924, 1454, 100);
  for (int ranks : {1, 2, 3, 4, 7})
    for (std::int64_t size : {0, 1, 157, 1000, 5000})
      for (Balance bal : {Balance::kStatic, Balance::kCost})
        for (double cap : {0.0, 1.0, 1.1})
          expect_tiling(make_batches(s, ranks, bal, size, {}, cap), 1924, ranks);
}

TEST(BakeBatches, CostBalanceEqualisesWork) {
  const BakeSceneHost s = scene_with(1924, 1454, 1000);  // reflective vertices at the end
  const auto b = make_batches(s, 4, Balance::kCost, 0);
  ASSERT_EQ(b.size(), 4u);
  const double total = static_cast<double>(s.colors());
  for (const Batch& x : b) {
    const double cost = static_cast<double>(s.color_offset[x.end] - s.color_offset[x.begin]);
    EXPECT_NEAR(cost / total, 0.25, 0.01);
  }
  const auto st = make_batches(s, 4, Balance::kStatic, 0);
  EXPECT_EQ(st[0].end - st[0].begin, 481);  // 1924 / 4
}

// Lookup hits weigh in: 1000 vertices of 10 colours each, the first half hitting view-dependent
// surfaces with every ray, so 4 ranks cut at equal colours + kLookupHitCost x hits, not at equal
// colours.
TEST(BakeBatches, LookupHitsShiftTheCuts) {
  const BakeSceneHost s = scene_with(1000, 0, 10);
  std::vector<float> hits(1000, 0.f);
  for (int v = 0; v < 500; ++v) hits[v] = 10.f;
  const std::vector<double> cost = lookup_hit_cost(s, hits);
  EXPECT_DOUBLE_EQ(cost[0], 10.0 + 10.0 * kLookupHitCost);
  EXPECT_DOUBLE_EQ(cost[999], 10.0);
  const auto b = make_batches(s, 4, Balance::kCost, 0, cost);
  expect_tiling(b, 1000, 4);
  ASSERT_EQ(b.size(), 4u);
  double total = 0;
  for (double c : cost) total += c;
  for (const Batch& x : b) {
    double part = 0;
    for (std::int64_t v = x.begin; v < x.end; ++v) part += cost[v];
    EXPECT_NEAR(part / total, 0.25, 0.01);
  }
  EXPECT_LT(b[2].end, 500);  // three of the four ranks share the expensive half
}

// The colour cap: the same cost as LookupHitsShiftTheCuts, where the cheap half would go to one
// rank (2x the mean colours); capped at 1.1x the mean, no rank owns more than 1.1 x 2500 colours,
// and a cap of 0 keeps the uncapped cut.
TEST(BakeBatches, ColorCapBoundsTheColoursPerRank) {
  const BakeSceneHost s = scene_with(1000, 0, 10);
  std::vector<float> hits(1000, 0.f);
  for (int v = 0; v < 500; ++v) hits[v] = 10.f;
  const std::vector<double> cost = lookup_hit_cost(s, hits);
  const auto uncapped = make_batches(s, 4, Balance::kCost, 0, cost);
  const auto zero = make_batches(s, 4, Balance::kCost, 0, cost, 0.0);
  ASSERT_EQ(zero.size(), uncapped.size());
  for (std::size_t i = 0; i < zero.size(); ++i) EXPECT_EQ(zero[i].end, uncapped[i].end);
  EXPECT_GT(s.color_offset[uncapped[3].end] - s.color_offset[uncapped[3].begin], 4000);
  const auto b = make_batches(s, 4, Balance::kCost, 0, cost, 1.1);
  expect_tiling(b, 1000, 4);
  ASSERT_EQ(b.size(), 4u);
  for (const Batch& x : b) EXPECT_LE(s.color_offset[x.end] - s.color_offset[x.begin], 2750);
  // Where the cap does not bind (equal colours per vertex, cut by colours) nothing changes.
  const BakeSceneHost even = scene_with(1000, 0, 10);
  const auto free_cut = make_batches(even, 4, Balance::kCost, 0, {}, 1.1);
  for (const Batch& x : free_cut) EXPECT_EQ(x.end - x.begin, 250);
}

// Both balanced under the cap: expensive vertices (2 lookup hits each) in the first and
// third quarters, cheap ones between. The capped contiguous cut gives a cheap quarter's rank its
// colour quota at a fraction of the mean cost (1.6x the mean cost on the largest); ranks that
// take several ranges (pieces of equal cost swapped between them) hold the mean cost to 2 % and
// at most 1.1x the mean colours.
TEST(BakeBatches, SwappedPiecesBalanceCostAndColours) {
  const BakeSceneHost s = scene_with(1000, 0, 10);
  std::vector<float> hits(1000, 0.f);
  for (int v = 0; v < 1000; ++v)
    if (v < 250 || (v >= 500 && v < 750)) hits[v] = 2.f;
  const std::vector<double> cost = lookup_hit_cost(s, hits);
  const auto b = make_batches(s, 4, Balance::kCost, 0, cost, 1.1);
  expect_tiling(b, 1000, 4);
  EXPECT_GT(b.size(), 4u);
  EXPECT_EQ(s.colors(), 10000);
  expect_cost_and_colours_balanced(s, b, cost, 4, 1.1);
  for (std::size_t i = 1; i < b.size(); ++i) EXPECT_NE(b[i].rank, b[i - 1].rank);  // merged
  // Without the cap: one range per rank, cut by cost.
  EXPECT_EQ(make_batches(s, 4, Balance::kCost, 0, cost, 0.0).size(), 4u);
}

// The same at 300 ranks, where the swaps' search skips the ranks it cannot gain from
// (kitchen.cpp, swap_under_cap): bands of 3,000 vertices alternate between 9 and 1.5 lookup
// hits per vertex, so a capped contiguous cut leaves some ranks cheap, and the swapped pieces
// still hold every rank to the cap and to 2 % of the mean cost.
TEST(BakeBatches, SwappedPiecesAtManyRanks) {
  constexpr int kRanks = 300, kVertices = 300 * 400;
  const BakeSceneHost s = scene_with(kVertices, 0, 30);
  std::vector<float> hits(kVertices);
  for (int v = 0; v < kVertices; ++v) hits[v] = (v / 3000) % 2 == 0 ? 9.f : 1.5f;
  const std::vector<double> cost = lookup_hit_cost(s, hits);
  const auto b = make_batches(s, kRanks, Balance::kCost, 0, cost, 1.1);
  expect_tiling(b, kVertices, kRanks);
  EXPECT_GT(b.size(), std::size_t(kRanks));  // pieces were swapped
  expect_cost_and_colours_balanced(s, b, cost, kRanks, 1.1);
}

// The mirror trace's cut weighs the BVH nodes the rays visit: with the first quarter of the
// vertices tracing into a deep part of the tree (86 % of the nodes), three of four ranks share
// that quarter.
TEST(BakeBatches, TraceNodesCutTheTraceRanges) {
  const BakeSceneHost s = scene_with(1000, 0, 10);
  std::vector<float> nodes(1000, 100.f);
  for (int v = 0; v < 250; ++v) nodes[v] = 2000.f;
  const std::vector<double> cost = mirror_trace_cost(s, nodes);
  EXPECT_DOUBLE_EQ(cost[0], 10.0 + 2000.0);
  EXPECT_DOUBLE_EQ(cost[999], 10.0 + 100.0);
  const auto b = make_batches(s, 4, Balance::kCost, 0, cost);
  expect_tiling(b, 1000, 4);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_LT(b[2].end, 250);
  EXPECT_GT(b[2].end, 200);  // at 3/4 of the cost: 219 vertices of 2010
}

}  // namespace
}  // namespace rtmini::bake
