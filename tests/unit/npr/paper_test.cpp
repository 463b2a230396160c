// Paper texture (hand-drawn seed §6): seeded improved Perlin noise without the
// seed paper's visible repetition.
#include "paper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "npr.hpp"

namespace rtmini::npr {
namespace {

// Paper factor of every pixel of a w x h image (the pass applied to white).
Image paper_of_white(int w, int h, const NprConfig& c) {
  Image white(w, h, 3);
  for (float& v : white.data) v = 1.f;
  return paper_pass(white, c);
}

// Normalised autocorrelation of channel 0 at lag (dx, dy) over the overlap.
double autocorrelation(const Image& img, int dx, int dy) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0, n = 0;
  for (int y = 0; y + dy < img.height; ++y)
    for (int x = 0; x + dx < img.width; ++x) {
      const double a = img.at(x, y, 0), b = img.at(x + dx, y + dy, 0);
      sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b, n += 1;
    }
  const double cov = sab / n - (sa / n) * (sb / n);
  const double va = saa / n - (sa / n) * (sa / n), vb = sbb / n - (sb / n) * (sb / n);
  return cov / std::sqrt(va * vb);
}

TEST(NprPaper, PermutationsArePermutationsAndDependOnSeed) {
  NprConfig c;
  c.paper_octaves = 3;
  PaperParams p;
  PermutationView perm;
  make_paper(c, p, perm);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), perm);
  for (int o = 0; o < 3; ++o) {
    std::set<int> seen;
    for (int i = 0; i < kPermSize; ++i) {
      seen.insert(h(o, i));
      EXPECT_EQ(h(o, i), h(o, i + kPermSize));
    }
    EXPECT_EQ(seen.size(), std::size_t(kPermSize));
    EXPECT_EQ(*seen.begin(), 0);
    EXPECT_EQ(*seen.rbegin(), kPermSize - 1);
  }
  c.seed = 2;
  PermutationView perm2;
  make_paper(c, p, perm2);
  const auto h2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), perm2);
  int same = 0;
  for (int i = 0; i < kPermSize; ++i) same += h(0, i) == h2(0, i);
  EXPECT_LT(same, 16);
}

TEST(NprPaper, PlainLatticeRepeatsWithThePermutationPeriod) {
  // Control for the test below: one unrotated octave at 1 pixel per cell
  // repeats exactly every 256 pixels -- the seed paper's visible repetition.
  NprConfig c;
  PaperParams p;
  PermutationView perm;
  make_paper(c, p, perm);
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), perm);
  Image img(768, 768, 1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.at(x, y, 0) = improved_noise(h, 0, x + 0.37f, y + 0.61f, 0.5f);
  EXPECT_GT(autocorrelation(img, 256, 0), 0.99);
  EXPECT_GT(autocorrelation(img, 0, 256), 0.99);
}

TEST(NprPaper, NoRepetitionAtLatticePeriods) {
  // Scale 8 and 4 octaves: the finest octave runs at 1 pixel per cell, so a plain
  // lattice would repeat at 256 (finest) and 512 (next) pixels.
  NprConfig c;
  c.paper_scale = 8.f;
  c.paper_octaves = 4;
  const Image paper = paper_of_white(1280, 1280, c);
  for (int lag : {256, 512}) {
    EXPECT_LT(std::fabs(autocorrelation(paper, lag, 0)), 0.2) << "x lag " << lag;
    EXPECT_LT(std::fabs(autocorrelation(paper, 0, lag)), 0.2) << "y lag " << lag;
  }
  EXPECT_GT(autocorrelation(paper, 1, 0), 0.5);
  EXPECT_GT(autocorrelation(paper, 0, 1), 0.5);
}

TEST(NprPaper, DefaultGrainHasNoRepetitionEither) {
  NprConfig c;
  const Image paper = paper_of_white(1280, 1280, c);
  for (int lag : {256, 512, 768}) {
    EXPECT_LT(std::fabs(autocorrelation(paper, lag, 0)), 0.2) << "x lag " << lag;
    EXPECT_LT(std::fabs(autocorrelation(paper, 0, lag)), 0.2) << "y lag " << lag;
  }
  EXPECT_GT(autocorrelation(paper, 1, 0), 0.5);
}

TEST(NprPaper, DiscretisedToLevelsWithinStrength) {
  NprConfig c;
  c.paper_levels = 4;
  c.paper_strength = 0.2f;
  const Image paper = paper_of_white(512, 512, c);
  std::set<float> values;
  for (int y = 0; y < paper.height; ++y)
    for (int x = 0; x < paper.width; ++x) {
      const float v = paper.at(x, y, 0);
      ASSERT_EQ(v, paper.at(x, y, 1));
      ASSERT_GE(v, 1.f - c.paper_strength - 1e-6f);
      ASSERT_LE(v, 1.f);
      values.insert(v);
    }
  // Every level is used and there are no others.
  EXPECT_EQ(values.size(), std::size_t(c.paper_levels));
}

TEST(NprPaper, MultipliesTheImage) {
  NprConfig c;
  Image grey(128, 128, 3);
  for (float& v : grey.data) v = 0.5f;
  const Image a = paper_of_white(128, 128, c);
  const Image b = paper_pass(grey, c);
  for (std::size_t i = 0; i < a.data.size(); ++i) ASSERT_FLOAT_EQ(b.data[i], 0.5f * a.data[i]);
}

}  // namespace
}  // namespace rtmini::npr
