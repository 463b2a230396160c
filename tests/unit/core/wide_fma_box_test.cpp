// The wide traversal's FMA box test (traverse.hpp) against the robust test it stands in for and
// against exact slab intervals, on rays grazing box faces, edges and corners, at large and small
// coordinates: every box the robust test or exact arithmetic finds, the FMA test must find too
// (the widening that makes this so is proved in traverse.hpp; this checks the proof's
// arithmetic), and it must not find much more. Host only (the test needs AVX and FMA).
#include <fenv.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "rtmini/bvh/traverse.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

#if RTMINI_FMA_BOX_TEST

// Box k's exact slab interval along the ray, clipped to [tmin, tmax], in long double from the
// ray's own direction (not its rounded reciprocal): true if not empty (what the test must find).
bool exact_interval(const bvh::WideNode& nd, int k, const Ray& r, long double& near,
                    long double& far) {
  const Real lo[3] = {nd.lo_x[k], nd.lo_y[k], nd.lo_z[k]};
  const Real hi[3] = {nd.hi_x[k], nd.hi_y[k], nd.hi_z[k]};
  near = r.tmin;
  far = r.tmax;
  for (int a = 0; a < 3; ++a) {
    if (lo[a] > hi[a]) return false;  // an unused lane
    const long double o = r.org[a], d = r.dir[a];
    if (d == 0) {
      if (o < lo[a] || o > hi[a]) return false;
      continue;
    }
    long double t0 = (lo[a] - o) / d, t1 = (hi[a] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far;
}

// A point of box k: a corner, a point on an edge or on a face (coordinates exactly on its planes).
Vec3 point_on_box(const bvh::WideNode& nd, int k, int kind, const Rng& rng, int slot) {
  const auto b = rng.block(slot);
  const Real lo[3] = {nd.lo_x[k], nd.lo_y[k], nd.lo_z[k]};
  const Real hi[3] = {nd.hi_x[k], nd.hi_y[k], nd.hi_z[k]};
  Vec3 p;
  const int free_axis = int(b.v[3] % 3u);
  for (int a = 0; a < 3; ++a) {
    const bool on_plane =
        kind == 0 || (kind == 1 && a != free_axis) || (kind == 2 && a == free_axis);
    const Real s = Rng::to_unit(b.v[a]);
    p[a] = on_plane ? (s < Real(0.5) ? lo[a] : hi[a]) : lo[a] + (hi[a] - lo[a]) * s;
  }
  return p;
}

struct Tally {
  long long checked = 0, grazing = 0, fma_extra = 0, fma_hits = 0, robust_hits = 0, robust_only = 0,
            exact_only = 0, cull_only = 0, skipped = 0;
};

// One node of eight random boxes around `center` (size ~ scale; lane 7 unused on odd trials) and
// one ray aimed at a corner, edge or face point of one of them, from near or far, some with a
// direction nearly parallel to a face and tmax ending at that point.
void check_one(const Vec3& center, Real scale, int trial, Tally& tally) {
  const Rng rng(2211, std::uint64_t(trial), 0);
  bvh::WideNode nd;
  for (int k = 0; k < bvh::kWidth; ++k) {
    const auto b = rng.block(k);
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      const Real c = center[a] + scale * (2 * Rng::to_unit(b.v[a]) - 1);
      const Real half = scale * Real(0.3) * Rng::to_unit(b.v[3] >> (8 * a));
      lo[a] = c - half;
      hi[a] = c + half;
    }
    const bool unused = k == 7 && trial % 2 == 1;
    nd.lo_x[k] = unused ? Real(1e30) : lo.x;
    nd.lo_y[k] = unused ? Real(1e30) : lo.y;
    nd.lo_z[k] = unused ? Real(1e30) : lo.z;
    nd.hi_x[k] = unused ? Real(-1e30) : hi.x;
    nd.hi_y[k] = unused ? Real(-1e30) : hi.y;
    nd.hi_z[k] = unused ? Real(-1e30) : hi.z;
    nd.child[k] = unused ? bvh::kEmptyLeaf : std::uint32_t(k);
  }
  const auto c = rng.block(8);
  const int box = int(c.v[0] % 7u), kind = int(c.v[1] % 3u);
  const Vec3 target = point_on_box(nd, box, kind, rng, 9);
  Ray r;
  const Real dist = scale * (trial % 3 == 0 ? Real(100) : Real(2));
  Vec3 dir = uniform_sphere(Rng::to_unit(c.v[2]), Rng::to_unit(c.v[3]));
  if (trial % 4 == 1) {  // nearly in a face's plane: one component 1-2 thousandths of the others
    const int axis = trial / 4 % 3;
    dir[axis] = math::copysign(Real(0.001) + Real(0.001) * Rng::to_unit(c.v[2]), dir[axis]);
    dir = normalize(dir);
  }
  if (trial % 5 == 2) {  // origin on a face plane of the target's box
    r.org = point_on_box(nd, box, 2, rng, 10);
    dir = normalize(target - r.org);
    if (!(length(target - r.org) > 0)) dir = Vec3(0, 0, 1);
  } else {
    r.org = target - dir * dist;
    dir = normalize(target - r.org);
  }
  r.dir = dir;
  const Real to_target = length(target - r.org);
  r.tmin = trial % 7 == 3 ? to_target * Real(0.5) : Real(0);
  const int tkind = trial % 3;
  r.tmax = tkind == 0 ? Real(1e30) : to_target * (tkind == 1 ? Real(1) : Real(1 - 3e-7));

  const bvh::detail::WideRay wr(r);
  if (!bvh::detail::fma_box_test_pays(r, wr)) {
    ++tally.skipped;
    return;
  }
  alignas(32) Real tn_robust[bvh::kWidth], tn_fma[bvh::kWidth];
  const int robust = bvh::detail::box_test<false>(nd, wr, r.tmin, r.tmax, tn_robust);
  const int fma = bvh::detail::box_test<true>(nd, wr, r.tmin, r.tmax, tn_fma);
  int exact = 0, grazing = 0;
  for (int k = 0; k < bvh::kWidth; ++k) {
    long double near, far;
    if (!exact_interval(nd, k, r, near, far)) continue;
    exact |= 1 << k;
    // Grazing: the ray only touches the box (an edge, a corner, a face it runs along, or tmax
    // ending at the box).
    grazing += far - near <= 1e-5L * std::max(far, 1e-30L);
  }
  ++tally.checked;
  tally.robust_only += __builtin_popcount(robust & ~fma);
  tally.exact_only += __builtin_popcount(exact & ~fma);
  tally.fma_hits += __builtin_popcount(fma);
  tally.robust_hits += __builtin_popcount(robust);
  tally.fma_extra += __builtin_popcount(fma & ~robust);
  tally.grazing += grazing;
  // The closest-hit cull after a hit at the target's distance: what the robust limit keeps, the
  // FMA limit keeps.
  const Real t_hit = to_target;
  const int keep_robust =
      bvh::detail::lanes_not_after(tn_robust, bvh::detail::cull_limit<false>(t_hit, wr)) & robust;
  const int keep_fma =
      bvh::detail::lanes_not_after(tn_fma, bvh::detail::cull_limit<true>(t_hit, wr)) & fma;
  tally.cull_only += __builtin_popcount(keep_robust & ~keep_fma);
}

TEST(WideFmaBox, AcceptsEveryBoxTheRobustTestAndExactArithmeticAccept) {
  const Placement cases[] = {{"unit", 1, 0},           {"tiny", 1e-4, 0},
                             {"huge", 1e4, 0},         {"far", 1, 1e3},
                             {"far-huge", 1e3, 1e4},   {"off-center", 0.37, 11.3},
                             {"small-far", 1e-3, 1e3}, {"very-small-far", 1e-5, 1e2}};
  for (const Placement& cs : cases) {
    const Vec3 center(Real(cs.offset), Real(-0.5 * cs.offset), Real(0.25 * cs.offset));
    Tally t;
    for (int trial = 0; trial < 40000; ++trial) check_one(center, Real(cs.scale), trial, t);
    std::printf(
        "%-15s %lld rays (%lld skipped: a tiny direction component), %lld grazing boxes; hits: "
        "robust %lld, FMA %lld (%lld more)\n",
        cs.name, t.checked, t.skipped, t.grazing, t.robust_hits, t.fma_hits, t.fma_extra);
    EXPECT_EQ(t.robust_only, 0) << cs.name
                                << ": boxes the robust test finds and the FMA test loses";
    EXPECT_EQ(t.exact_only, 0) << cs.name << ": boxes the ray meets that the FMA test loses";
    EXPECT_EQ(t.cull_only, 0) << cs.name << ": children the FMA cull drops and the robust keeps";
    EXPECT_GT(t.checked, 20000) << cs.name;
    EXPECT_GT(t.grazing, 100) << cs.name << ": too few grazing rays for the test to mean much";
    // Conservative, but not by accepting everything: where the boxes are large against the
    // coordinates' rounding, few hits beyond the robust test's (measured: 0-5 %, the most where
    // rays from far away have a small direction component). Boxes of a few float ulps, as in the
    // last two placements, are widened by about their own size.
    if (cs.scale > 1e-5 * cs.offset) {
      EXPECT_LT(t.fma_extra, t.fma_hits / 10 + 10) << cs.name;
    }
  }
}

// Bit equality of two floats (NaNs included, +0 and -0 apart).
bool same_bits(Real a, Real b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Rays whose setup takes every branch of the scalar constructors: zero direction components of
// either sign, ties between the components' magnitudes (the dominant axis picks the first), all
// eight octants, components below 1/1024 of the largest (no FMA test), origins whose o/d passes
// 1e30, a NaN direction, negative tmin, tmax past 1e30, empty segments, and random rays.
std::vector<Ray> packet_setup_rays() {
  std::vector<Ray> rays;
  auto add = [&](Vec3 o, Vec3 d, Real tmin = 0, Real tmax = 100) {
    Ray r;
    r.org = o, r.dir = d, r.tmin = tmin, r.tmax = tmax;
    rays.push_back(r);
  };
  const Vec3 o(Real(0.5), Real(-2), Real(3));
  add(o, Vec3(1, 0, 0)), add(o, Vec3(-0.0f, 1, 0)), add(o, Vec3(0, -0.0f, -1));
  add(o, Vec3(1, 1, 0)), add(o, Vec3(-1, 1, 1)), add(o, Vec3(1, -1, -1)), add(o, Vec3(0.5f, 1, -1));
  add(o, Vec3(1, 2, -2)), add(o, Vec3(-3, 2, 3)), add(o, Vec3(1, 1e-4f, 0.5f));
  add(Vec3(1e35f, 0, 0), Vec3(1e-3f, 1, 1)), add(o, Vec3(std::nanf(""), 1, 0));
  add(o, Vec3(1, 2, 3), -1), add(o, Vec3(1, 2, 3), 0, 1e31f), add(o, Vec3(1, 2, 3), 5, 4);
  add(o, Vec3(0, 0, 0));
  const Rng rng(5, 0, 0);
  for (int i = 0; i < 800; ++i) {
    const auto a = rng.block(std::uint32_t(i));
    const Vec3 d = uniform_sphere(Rng::to_unit(a.v[0]), Rng::to_unit(a.v[1]));
    add(Vec3(Rng::to_unit(a.v[2]) * 50, -3, Rng::to_unit(a.v[3])), d, 0, Real(1 + i % 7));
  }
  return rays;
}

TEST(WidePackets, FullPacketSetupMatchesRayByRay) {
#if defined(__GLIBC__)
  // The zero and NaN directions make invalid operations in either setup (0 * inf, NaN
  // comparisons), which the test main traps: they are the point here.
  const int trapped = fedisableexcept(FE_INVALID);
#endif
  const std::vector<Ray> rays = packet_setup_rays();
  int packets = 0, fma_packets = 0;
  for (std::size_t at = 0; at + bvh::kPacketSize <= rays.size(); at += 3) {  // overlapping
    const Ray* in = rays.data() + at;
    bvh::detail::PacketRays p;
    p.rays = in;
    Hit hits[bvh::kPacketSize];
    bool found[bvh::kPacketSize];
    bool fma = false;
    const int live = bvh::detail::fill_full_packet(p, in, hits, found, fma);
    // The ray-by-ray setup (partial packets') as the reference.
    bvh::detail::PacketRays q;
    q.rays = in;
    Hit want_hits[bvh::kPacketSize];
    bool want_found[bvh::kPacketSize];
    bool want_fma = false;
    const int want_live = bvh::detail::fill_packet_ray_by_ray(q, in, bvh::kPacketSize, want_hits,
                                                              want_found, want_fma);
    ++packets;
    fma_packets += fma;
    ASSERT_EQ(live, want_live) << "packet at " << at;
    ASSERT_EQ(fma, want_fma) << "packet at " << at;
    if (fma) {  // (set with the lanes)
      ASSERT_EQ(p.one_octant, q.one_octant) << "packet at " << at;
    }
    for (int r = 0; r < bvh::kPacketSize; ++r) {
      const std::string what = "ray " + std::to_string(at + r);
      const bvh::detail::WideRay &a = p.box[r], &b = q.box[r];
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(same_bits(a.inv[k], b.inv[k])) << what << " inv " << k;
        EXPECT_TRUE(same_bits(a.org[k], b.org[k])) << what << " org " << k;
        EXPECT_TRUE(same_bits(a.org_inv[k], b.org_inv[k])) << what << " org_inv " << k;
      }
      // The FMA lanes: filled (and read) only where every ray of the packet takes that test.
      for (int k = 0; k < 3 && fma; ++k) {
        EXPECT_TRUE(same_bits(p.lanes.inv[k][r], q.lanes.inv[k][r])) << what;
        EXPECT_TRUE(same_bits(p.lanes.org_inv[k][r], q.lanes.org_inv[k][r])) << what;
        EXPECT_TRUE(same_bits(p.lanes.negative[k][r], q.lanes.negative[k][r])) << what;
      }
      EXPECT_TRUE(same_bits(a.slack, b.slack)) << what << " slack";
      if (fma) {
        EXPECT_TRUE(same_bits(p.lanes.slack[r], q.lanes.slack[r])) << what;
        EXPECT_TRUE(same_bits(p.lanes.tmin[r], q.lanes.tmin[r])) << what;
      }
      EXPECT_TRUE(same_bits(p.tmax[r], q.tmax[r])) << what;
      EXPECT_EQ(a.neg_x, b.neg_x) << what;
      EXPECT_EQ(a.neg_y, b.neg_y) << what;
      EXPECT_EQ(a.neg_z, b.neg_z) << what;
      const WatertightRay &w = p.wr[r], &v = q.wr[r];
      EXPECT_EQ(w.kx, v.kx) << what;
      EXPECT_EQ(w.ky, v.ky) << what;
      EXPECT_EQ(w.kz, v.kz) << what;
      EXPECT_TRUE(same_bits(w.sx, v.sx)) << what << " sx";
      EXPECT_TRUE(same_bits(w.sy, v.sy)) << what << " sy";
      EXPECT_TRUE(same_bits(w.sz, v.sz)) << what << " sz";
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(w.org[k], v.org[k])) << what;
      EXPECT_EQ(found[r], want_found[r]);
      EXPECT_EQ(hits[r].prim, want_hits[r].prim);
      EXPECT_TRUE(same_bits(hits[r].t, want_hits[r].t)) << what;
      EXPECT_FALSE(found[r]);
      EXPECT_TRUE(same_bits(hits[r].t, in[r].tmax)) << what;
    }
  }
  // Both kinds of packet were set up (the special rays' packets refuse the FMA test).
  EXPECT_GT(fma_packets, packets / 2);
  EXPECT_LT(fma_packets, packets);
#if defined(__GLIBC__)
  feenableexcept(trapped);
#endif
}

#else

TEST(WideFmaBox, AcceptsEveryBoxTheRobustTestAndExactArithmeticAccept) {
  GTEST_SKIP() << "no FMA box test on this target (it needs AVX and FMA on the host)";
}

#endif

}  // namespace
}  // namespace rtmini::test
