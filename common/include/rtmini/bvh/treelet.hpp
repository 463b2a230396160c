#pragma once
// Treelet restructuring (Karras & Aila, "Fast Parallel Construction of High-Quality Bounding
// Volume Hierarchies", HPG 2013): below a node, grow a treelet of up to kTreeletLeaves leaves by
// repeatedly opening the treelet leaf of largest surface area, then rebuild the treelet's
// internal nodes as the topology of least SAH cost over its leaves, found by dynamic
// programming over all subsets of the leaves. The leaves' subtrees are kept whole, so only
// the treelet's internal nodes (the root and the nodes opened) are rewritten. The cost model is
// the builders' (subtree_cost: Ct = Ci = 1, subtrees of at most kMaxLeafSize triangles may
// collapse into one leaf), so the DP also picks which subsets become leaves.
//
// One thread per treelet (the paper's warp-wide version is faster on a GPU but needs warp
// intrinsics Kokkos does not expose portably). Callers run it on a node only once all of the
// node's descendants are final, and on concurrent nodes whose subtrees are disjoint.
#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/traverse_gpu.hpp"  // detail::lowest_bit

namespace rtmini::bvh {

// Leaves per treelet: the paper's 7 (127 subsets, 966 splits to try per treelet).
inline constexpr int kTreeletLeaves = 7;

namespace detail {

inline constexpr int kTreeletSubsets = 1 << kTreeletLeaves;

KOKKOS_INLINE_FUNCTION bool single_bit(std::uint32_t mask) { return (mask & (mask - 1u)) == 0u; }

}  // namespace detail

// The treelet below `root`: its leaves (node ids whose subtrees stay whole) and its internal
// nodes (root first), which the rebuild reuses.
struct Treelet {
  int leaf[kTreeletLeaves];
  int inner[kTreeletLeaves - 1];
  int leaves = 0, inners = 0;
};

// Opens, while the treelet has fewer than kTreeletLeaves leaves, the internal leaf of largest
// surface area (ties: the first). Node ids below `ni` are internal; the others are triangles.
template <class Nodes>
KOKKOS_INLINE_FUNCTION Treelet form_treelet(const Nodes& nodes, int root, int ni) {
  Treelet t;
  t.inner[t.inners++] = root;
  t.leaf[t.leaves++] = nodes.kids(root, 0);
  t.leaf[t.leaves++] = nodes.kids(root, 1);
  while (t.leaves < kTreeletLeaves) {
    int open = -1;
    Real open_area = 0;
    for (int k = 0; k < t.leaves; ++k) {
      if (t.leaf[k] >= ni) continue;
      const Real a = nodes.box(t.leaf[k]).surface_area();
      if (open < 0 || a > open_area) {
        open = k;
        open_area = a;
      }
    }
    if (open < 0) break;
    const int u = t.leaf[open];
    t.inner[t.inners++] = u;
    t.leaf[open] = nodes.kids(u, 0);
    t.leaf[t.leaves++] = nodes.kids(u, 1);
  }
  return t;
}

// The box and triangle count of the treelet leaves in subset `s` (bit k: leaf k).
struct SubsetBound {
  Aabb box;
  int count = 0;
};

template <class Nodes>
KOKKOS_INLINE_FUNCTION SubsetBound subset_bound(const Nodes& nodes, const Treelet& t,
                                                std::uint32_t s) {
  SubsetBound b;
  for (int k = 0; k < t.leaves; ++k)
    if (s >> k & 1u) {
      b.box.expand(nodes.box(t.leaf[k]));
      b.count += nodes.count(t.leaf[k]);
    }
  return b;
}

// The least-cost topology of every subset of a treelet's leaves: for each subset, its signed
// cost (subtree_cost's convention: negative when one leaf is cheaper) and the part of the best
// split holding its lowest leaf.
struct TreeletPlan {
  Real cost[detail::kTreeletSubsets];
  std::uint8_t part[detail::kTreeletSubsets];
};

template <class Nodes>
KOKKOS_INLINE_FUNCTION void plan_treelet(const Nodes& nodes, const Treelet& t, TreeletPlan& plan) {
  const std::uint32_t full = (1u << t.leaves) - 1u;
  for (std::uint32_t s = 1; s <= full; ++s) {
    if (detail::single_bit(s)) {
      plan.cost[s] = nodes.cost(t.leaf[detail::lowest_bit(s)]);
      plan.part[s] = static_cast<std::uint8_t>(s);
      continue;
    }
    const SubsetBound sb = subset_bound(nodes, t, s);
    // Each split once: the part with the lowest leaf plus any proper subset of the rest. Every
    // proper subset is numerically smaller than s, so its plan is already there.
    const std::uint32_t low = s & (~s + 1u), rest = s ^ low;
    std::uint32_t best_part = low;
    Real best = math::fabs(plan.cost[low]) + math::fabs(plan.cost[rest]);
    for (std::uint32_t q = (rest - 1u) & rest; q != 0u; q = (q - 1u) & rest) {
      const std::uint32_t p = low | q;
      const Real c = math::fabs(plan.cost[p]) + math::fabs(plan.cost[s ^ p]);
      if (c < best) {
        best = c;
        best_part = p;
      }
    }
    plan.part[s] = static_cast<std::uint8_t>(best_part);
    plan.cost[s] = subtree_cost(sb.box.surface_area(), sb.count, plan.cost[best_part],
                                plan.cost[s ^ best_part]);
  }
}

// Rewrites the treelet's internal nodes as `plan` says: kids, parent links, boxes, counts and
// costs. Internal nodes are handed out in depth-first order, the root keeping its id.
template <class Nodes>
KOKKOS_INLINE_FUNCTION void rebuild_treelet(const Nodes& nodes, const Treelet& t,
                                            const TreeletPlan& plan) {
  std::uint32_t set_of[kTreeletLeaves - 1];  // the subset each internal node covers
  int pending[kTreeletLeaves - 1];           // internal nodes whose kids are not yet placed
  int used = 1, top = 0;
  set_of[0] = (1u << t.leaves) - 1u;
  pending[top++] = 0;
  while (top > 0) {
    const int slot = pending[--top];
    const int id = t.inner[slot];
    const std::uint32_t s = set_of[slot];
    const std::uint32_t sides[2] = {plan.part[s], s ^ plan.part[s]};
    const SubsetBound sb = subset_bound(nodes, t, s);
    for (int side = 0; side < 2; ++side) {
      int child;
      if (detail::single_bit(sides[side])) {
        child = t.leaf[detail::lowest_bit(sides[side])];
      } else {
        set_of[used] = sides[side];
        child = t.inner[used];
        pending[top++] = used++;
      }
      nodes.kids(id, side) = child;
      nodes.parent(child) = id;
    }
    nodes.box(id) = sb.box;
    nodes.count(id) = sb.count;
    nodes.cost(id) = plan.cost[s];
  }
}

// Restructures the treelet below `root` when the best topology is cheaper than the current one.
template <class Nodes>
KOKKOS_INLINE_FUNCTION void restructure_treelet(const Nodes& nodes, int root, int ni) {
  const Treelet t = form_treelet(nodes, root, ni);
  if (t.leaves < 3) return;  // two leaves: one topology
  TreeletPlan plan;
  plan_treelet(nodes, t, plan);
  const std::uint32_t full = (1u << t.leaves) - 1u;
  if (math::fabs(plan.cost[full]) < math::fabs(nodes.cost(root))) rebuild_treelet(nodes, t, plan);
}

}  // namespace rtmini::bvh
