// bake's iterate-phase ETA (issue 16): which measured iteration stands in for which.
#include "iteration_eta.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace rtmini::bake {
namespace {

constexpr int kOff = 0, kFill = 1, kUse = 2;

TEST(IterationEta, NoEstimateWhileOnlyTheBaseMapIsKnown) {
  // The base map says nothing of the gather iterations after it.
  IterationEta eta;
  eta.batch_done(1.0);
  eta.batch_done(0.5);
  EXPECT_LT(eta.remaining(kOff, 4, {kFill, kUse}), 0.0);
  // A run of base-mode iterations only is linear in batches after the setup-laden first one.
  EXPECT_DOUBLE_EQ(eta.remaining(kOff, 4, {kOff}), 0.5 * 2 + (1.5 + 0.5 * 2));
}

TEST(IterationEta, AnotherGatherModeStandsInForOneNotSeenYet) {
  IterationEta eta;
  for (const double s : {1.0, 1.0}) eta.batch_done(s);
  eta.iteration_done(kOff);
  // The fill iteration: batches of unlike cost (the first one cheap).
  for (const double s : {1.0, 3.0, 2.0, 2.0}) eta.batch_done(s);
  eta.iteration_done(kFill);
  // The first use iteration, one batch in, at the fill iteration's pace: the rest follows the
  // fill iteration's profile (7 s), not the first batch's linear extrapolation (3 s); the
  // upcoming use iteration costs the fill one (8 s).
  eta.batch_done(1.0);
  EXPECT_DOUBLE_EQ(eta.remaining(kUse, 4, {kUse}), 7.0 + 8.0);
  // The base map never stands in for a gather mode.
  EXPECT_DOUBLE_EQ(eta.remaining(kUse, 4, {kOff}), 7.0 + 2.0);
}

}  // namespace
}  // namespace rtmini::bake
