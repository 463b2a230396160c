// The progress ETA's helpers (issue 16): the least-squares cost fit of sketchtrace's probe-weighted
// ETA, and the spread order that makes each dispatch of bake render and bake ao a fair sample.
#include "rtmini/report/progress.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "rtmini/parallel/spread_order.hpp"

namespace rtmini {
namespace {

TEST(CostFit, RecoversAConstantAndAPerProbeCost) {
  // Seconds = 0.002 per item + 0.0005 per probe unit, over pieces of unlike probe cost.
  CostFit fit;
  const double items[] = {100, 200, 150, 300}, probes[] = {1000, 9000, 300, 4000};
  for (int i = 0; i < 4; ++i) fit.add(0.002 * items[i] + 0.0005 * probes[i], items[i], probes[i]);
  EXPECT_NEAR(fit.cost(50, 700), 0.002 * 50 + 0.0005 * 700, 1e-9);
  EXPECT_NEAR(fit.cost(1000, 0), 2.0, 1e-9);
}

TEST(CostFit, OnePieceFallsBackToTheProbeCostAlone) {
  // One piece cannot separate the two terms: seconds in proportion to the probe cost.
  CostFit fit;
  fit.add(3.0, 100, 600);
  EXPECT_NEAR(fit.cost(100, 1200), 6.0, 1e-12);
  EXPECT_NEAR(fit.cost(5, 0), 0.0, 1e-12);
}

TEST(CostFit, NegativeTermFallsBackToTheProbeCostAlone) {
  // Cheap pieces with high probe costs would make the per-item term negative: a cost model
  // with a negative part can give a negative ETA, so the fit keeps the probe term only.
  CostFit fit;
  fit.add(1.0, 100, 1000);
  fit.add(1.5, 1000, 2000);
  const double b = (1.0 * 1000 + 1.5 * 2000) / (1000.0 * 1000 + 2000.0 * 2000);
  EXPECT_NEAR(fit.cost(10, 500), b * 500, 1e-12);
}

TEST(CostFit, NothingMeasuredCostsNothing) { EXPECT_EQ(CostFit().cost(10, 10), 0.0); }

TEST(SpreadOrder, IsAPermutationThatKeepsBlocksTogether) {
  for (const std::int64_t total : {0, 1, 5, 255, 256, 1000, 1280 * 97, 300001})
    for (const std::int64_t block : {1, 7, 256, 1280}) {
      const SpreadOrder order(total, block);
      std::vector<char> seen(static_cast<std::size_t>(total), 0);
      for (std::int64_t pos = 0; pos < total; ++pos) {
        const std::int64_t item = order.item(pos);
        ASSERT_GE(item, 0);
        ASSERT_LT(item, total);
        ASSERT_EQ(seen[static_cast<std::size_t>(item)]++, 0) << total << " " << block;
        // Within a whole block, neighbouring positions are neighbouring items.
        if (pos % block != 0 && pos / block < total / block) {
          ASSERT_EQ(item, order.item(pos - 1) + 1);
        }
      }
      // The items after the last whole block stay at the end, in order.
      for (std::int64_t pos = total / block * block; pos < total; ++pos)
        ASSERT_EQ(order.item(pos), pos);
    }
}

TEST(SpreadOrder, DefaultIsTheIdentity) {
  const SpreadOrder order;
  for (std::int64_t pos = 0; pos < 1000; ++pos) ASSERT_EQ(order.item(pos), pos);
}

TEST(SpreadOrder, EveryRunOfPositionsCoversTheWholeRange) {
  // Any L consecutive blocks (one dispatch) leave no gap wider than 2.5 N / L blocks between
  // them, cyclically: the three-distance theorem of a golden-ratio stride (storage order
  // would leave a gap of N - L).
  for (const std::int64_t n : {97, 480, 960, 1171}) {
    const SpreadOrder order(n, 1);
    for (const std::int64_t run : {4, 8, 20, 50})
      for (std::int64_t first = 0; first + run <= n; ++first) {
        std::vector<std::int64_t> items;
        for (std::int64_t pos = first; pos < first + run; ++pos) items.push_back(order.item(pos));
        std::sort(items.begin(), items.end());
        std::int64_t gap = items.front() + n - items.back();
        for (std::size_t k = 1; k < items.size(); ++k) gap = std::max(gap, items[k] - items[k - 1]);
        ASSERT_LE(static_cast<double>(gap), 2.5 * static_cast<double>(n) / run) << n << " " << run;
      }
  }
}

}  // namespace
}  // namespace rtmini
