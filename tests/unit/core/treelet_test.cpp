// Treelet restructuring (treelet.hpp) against an exhaustive search: on small random trees whose
// every node fits in one treelet, the rebuilt tree must be a valid tree over the same leaves
// whose SAH cost, recomputed from its structure, is the least over all topologies.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "rtmini/bvh/build_ploc.hpp"

namespace rtmini::test {
namespace {

using HostNodes = bvh::PlocNodes<Kokkos::HostSpace>;

Aabb random_box(std::mt19937& gen) {
  std::uniform_real_distribution<float> pos(0.0f, 10.0f), size(0.1f, 3.0f);
  Aabb b;
  b.lo = Vec3(pos(gen), pos(gen), pos(gen));
  b.hi = b.lo + Vec3(size(gen), size(gen), size(gen));
  return b;
}

// n triangle leaves (ids n - 1 .. 2n - 2) with random boxes under a chain of internal nodes
// 0 .. n - 2 (node i: leaf i and node i + 1; the last: the last two leaves), boxes, counts and
// costs filled bottom-up as the builders do.
HostNodes random_chain(int n, std::mt19937& gen) {
  const int ni = n - 1;
  HostNodes t;
  t.box = Kokkos::View<Aabb*, Kokkos::HostSpace>("box", ni + n);
  t.cost = Kokkos::View<Real*, Kokkos::HostSpace>("cost", ni + n);
  t.count = Kokkos::View<int*, Kokkos::HostSpace>("count", ni + n);
  t.parent = Kokkos::View<int*, Kokkos::HostSpace>("parent", ni + n);
  t.kids = Kokkos::View<int* [2], Kokkos::HostSpace>("kids", ni);
  for (int k = 0; k < n; ++k) {
    t.box(ni + k) = random_box(gen);
    t.cost(ni + k) = t.box(ni + k).surface_area();
    t.count(ni + k) = 1;
  }
  for (int i = ni - 1; i >= 0; --i) {
    const int l = ni + i, r = i == ni - 1 ? ni + n - 1 : i + 1;
    t.kids(i, 0) = l;
    t.kids(i, 1) = r;
    t.parent(l) = t.parent(r) = i;
    t.box(i) = t.box(l);
    t.box(i).expand(t.box(r));
    t.count(i) = t.count(l) + t.count(r);
    t.cost(i) = bvh::subtree_cost(t.box(i).surface_area(), t.count(i), t.cost(l), t.cost(r));
  }
  return t;
}

// The least signed cost of any binary tree over `leaves` (triangle boxes), by trying every split
// recursively (the first leaf always on the left, so each split once).
Real best_cost(const std::vector<Aabb>& leaves) {
  if (leaves.size() == 1) return leaves[0].surface_area();
  Aabb box;
  for (const Aabb& b : leaves) box.expand(b);
  const int n = static_cast<int>(leaves.size());
  Real best = -1, best_l = 0, best_r = 0;
  for (int mask = 0; mask < (1 << (n - 1)) - 1; ++mask) {  // leaves 1.. on the left
    std::vector<Aabb> l{leaves[0]}, r;
    for (int k = 1; k < n; ++k) (mask >> (k - 1) & 1 ? l : r).push_back(leaves[k]);
    const Real cl = best_cost(l), cr = best_cost(r);
    if (best < 0 || std::abs(cl) + std::abs(cr) < best) {
      best = std::abs(cl) + std::abs(cr);
      best_l = cl;
      best_r = cr;
    }
  }
  return bvh::subtree_cost(box.surface_area(), n, best_l, best_r);
}

// Cost of the subtree at `node` recomputed from its structure alone (children, leaf boxes), with
// its box and triangle count; checks parent links, stored boxes and counts, and counts the
// leaves reached.
Real recomputed_cost(const HostNodes& t, int node, int ni, std::vector<int>& reached, Aabb& box,
                     int& count) {
  if (node >= ni) {
    ++reached[node - ni];
    box = t.box(node);
    count = 1;
    return box.surface_area();
  }
  Aabb bl, br;
  int nl = 0, nr = 0;
  const int l = t.kids(node, 0), r = t.kids(node, 1);
  EXPECT_EQ(t.parent(l), node);
  EXPECT_EQ(t.parent(r), node);
  const Real cl = recomputed_cost(t, l, ni, reached, bl, nl);
  const Real cr = recomputed_cost(t, r, ni, reached, br, nr);
  box = bl;
  box.expand(br);
  count = nl + nr;
  EXPECT_EQ(t.box(node).surface_area(), box.surface_area());
  EXPECT_EQ(t.count(node), count);
  return bvh::subtree_cost(box.surface_area(), count, cl, cr);
}

TEST(Treelet, RebuildFindsTheCheapestTopology) {
  std::mt19937 gen(2013);
  int improved = 0;
  for (int trial = 0; trial < 40; ++trial) {
    for (int n = 3; n <= bvh::kTreeletLeaves; ++n) {
      const int ni = n - 1;
      const HostNodes t = random_chain(n, gen);
      std::vector<Aabb> leaves;
      for (int k = 0; k < n; ++k) leaves.push_back(t.box(ni + k));
      const Real before = t.cost(0), best = best_cost(leaves);
      bvh::restructure_treelet(t, 0, ni);
      std::vector<int> reached(n, 0);
      Aabb root_box;
      int root_count = 0;
      const Real after = recomputed_cost(t, 0, ni, reached, root_box, root_count);
      for (int k = 0; k < n; ++k) EXPECT_EQ(reached[k], 1) << "leaf " << k;
      EXPECT_FLOAT_EQ(after, t.cost(0)) << "stored cost matches the structure";
      EXPECT_NEAR(after, best, 1e-5 * std::abs(best)) << "n " << n << ", trial " << trial;
      EXPECT_LE(std::abs(after), std::abs(before));
      improved += std::abs(after) < std::abs(before);
    }
  }
  EXPECT_GT(improved, 0) << "random chains are never optimal";
}

}  // namespace
}  // namespace rtmini::test
