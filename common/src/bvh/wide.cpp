#include "rtmini/bvh/wide.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

namespace rtmini::bvh {

namespace {

struct Slot {
  Aabb box;
  std::uint32_t ref;
};

// The leaf-order triangle range under one binary child.
struct Range {
  std::uint32_t first = 0, count = 0;
  bool contiguous = true;
};

void set_lane(WideNode& n, int k, const Aabb& b, std::uint32_t ref) {
  n.lo_x[k] = b.lo.x;
  n.lo_y[k] = b.lo.y;
  n.lo_z[k] = b.lo.z;
  n.hi_x[k] = b.hi.x;
  n.hi_y[k] = b.hi.y;
  n.hi_z[k] = b.hi.z;
  n.child[k] = ref;
}

// The leaf-order triangle range of internal node `nd`'s subtree, from its children's (both
// builders store a subtree's triangles contiguously; `contiguous` guards the merge if one ever
// does not).
Range subtree_range(const BvhNode& nd, const std::vector<Range>& ranges) {
  Range r;
  r.first = ~0u;
  std::uint32_t end = 0;
  for (int k = 0; k < 2; ++k) {
    const std::uint32_t c = nd.child[k];
    if (c == kEmptyLeaf) continue;
    const Range sub = is_leaf(c) ? Range{leaf_first(c), leaf_count(c), true} : ranges[c];
    r.first = std::min(r.first, sub.first);
    end = std::max(end, sub.first + sub.count);
    r.count += sub.count;
    r.contiguous = r.contiguous && sub.contiguous;
  }
  r.contiguous = r.contiguous && end - r.first == r.count;
  return r;
}

// Writes triangles [first, first + count) as a leaf's rows of `lanes` lanes at `rows` (nine
// rows a.x .. c.z, then the prim ids). Unused lanes repeat the first triangle; the traversal
// masks them by the leaf's count.
void write_leaf_rows(const Triangle* tris, const int* prim, std::uint32_t first,
                     std::uint32_t count, int lanes, char* rows) {
  for (int k = 0; k < lanes; ++k) {
    const std::uint32_t i = first + (k < int(count) ? std::uint32_t(k) : 0u);
    const Triangle& t = tris[i];
    const Real v[9] = {t.a.x, t.a.y, t.a.z, t.b.x, t.b.y, t.b.z, t.c.x, t.c.y, t.c.z};
    for (int r = 0; r < 9; ++r)
      std::memcpy(rows + (r * lanes + k) * sizeof(Real), &v[r], sizeof(Real));
    std::memcpy(rows + (9 * lanes) * sizeof(Real) + k * sizeof(int), &prim[i], sizeof(int));
  }
}

// Places leaves in blocks: a full leaf takes a block, a compact one (at most kCompactLeafSize
// triangles) the free half of the last block that has one, so siblings' compact leaves share
// one. Returns the leaf's reference.
struct LeafPlacer {
  std::vector<TriangleLanes>& blocks;
  std::uint32_t free_half = ~0u;

  std::uint32_t place(const Triangle* tris, const int* prim, std::uint32_t first,
                      std::uint32_t count) {
    std::uint32_t half;
    const bool compact = count <= std::uint32_t(kCompactLeafSize);
    if (compact && free_half != ~0u) {
      half = free_half;
      free_half = ~0u;
    } else {
      half = 2 * static_cast<std::uint32_t>(blocks.size());
      blocks.emplace_back();
      if (compact) free_half = half + 1;
    }
    char* rows =
        reinterpret_cast<char*>(&blocks[half / 2]) + (half & 1u) * (sizeof(TriangleLanes) / 2);
    write_leaf_rows(tris, prim, first, count, compact ? kCompactLeafSize : kMaxLeafSize, rows);
    return make_leaf(half, count);
  }
};

// The cheapest ways to lay out one binary internal node's subtree in the wide tree, by the SAH
// (Ylitie et al. 2017's dynamic programme, with this traversal's costs: a wide node visit and a
// SIMD leaf test each cost the same whatever their count, so a leaf is costed as one block of
// eight lanes, not per triangle). Costs are expected work per unit of the root's area.
struct CollapsePlan {
  float cost[kWidth] = {};          // cost[i - 1]: cheapest using at most i slots of the parent
  std::uint8_t split[kWidth] = {};  // split[i - 1] = 0: one slot; k: k slots to child 0, i - k to 1
  std::uint8_t node_split = 1;      // the split of the eight slots when it is a wide node
  bool as_leaf = false;             // in one slot: a wide leaf (else a wide node)
};

float leaf_cost(const Aabb& box) { return float(kWideLeafCost) * box.surface_area(); }

// Costs of binary child `k` of `nd` given at most 1 .. kWidth slots.
void child_costs(const std::vector<CollapsePlan>& plans, const BvhNode& nd, int k,
                 float cost[kWidth]) {
  const std::uint32_t ref = nd.child[k];
  if (!is_leaf(ref)) {
    std::copy(plans[ref].cost, plans[ref].cost + kWidth, cost);
    return;
  }
  std::fill(cost, cost + kWidth, ref == kEmptyLeaf ? 0.0f : leaf_cost(nd.box(k)));
}

// Plans internal node `node` from its children's plans. A subtree may be a wide leaf when its
// triangles are contiguous and at most `merge`.
void plan_node(const std::vector<BvhNode>& binary, std::uint32_t node, const Range& r, int merge,
               std::vector<CollapsePlan>& plans) {
  const BvhNode& nd = binary[node];
  float c0[kWidth];
  // c1 after kWidth infinities: loading kWidth lanes from padded + kWidth - k gives lane j the
  // cost of child 1 in j + 1 - k slots, or infinity where that is less than one.
  float padded[2 * kWidth];
  std::fill(padded, padded + kWidth, std::numeric_limits<float>::infinity());
  child_costs(plans, nd, 0, c0);
  child_costs(plans, nd, 1, padded + kWidth);
  // The two children sharing i slots (i >= 2), the first best split: lane j for i = j + 1, all
  // i at once for each k slots of child 0 (the same sums and the same strict < in the same k
  // order as one i at a time; kept by selects: which split wins is data, not a pattern a branch
  // predictor learns).
  typedef float Costs __attribute__((vector_size(kWidth * sizeof(float))));
  typedef std::int32_t Ints __attribute__((vector_size(kWidth * sizeof(std::int32_t))));
  Costs best = Costs{} + std::numeric_limits<float>::infinity();
  Ints best_k = {};
  for (int k = 1; k < kWidth; ++k) {
    Costs rest;
    std::memcpy(&rest, padded + kWidth - k, sizeof rest);
    const Costs c = c0[k - 1] + rest;
    const Ints better = c < best;
    best = Costs((Ints(c) & better) | (Ints(best) & ~better));
    best_k = (k & better) | (best_k & ~better);
  }
  float shared[kWidth + 1];
  std::uint8_t shared_split[kWidth + 1] = {};
  for (int i = 2; i <= kWidth; ++i) {
    shared[i] = best[i - 1];
    shared_split[i] = std::uint8_t(best_k[i - 1]);
  }
  Aabb box = nd.box(0);
  box.expand(nd.box(1));
  CollapsePlan& p = plans[node];
  const float as_node = float(kWideNodeCost) * box.surface_area() + shared[kWidth];
  const float as_leaf = leaf_cost(box);
  p.as_leaf = r.contiguous && r.count <= std::uint32_t(merge) && as_leaf <= as_node;
  p.node_split = shared_split[kWidth];
  p.cost[0] = p.as_leaf ? as_leaf : as_node;
  for (int i = 2; i <= kWidth; ++i) {
    const bool open = shared[i] < p.cost[0];
    p.cost[i - 1] = open ? shared[i] : p.cost[0];
    p.split[i - 1] = open ? shared_split[i] : 0;
  }
}

// Triangle ranges and plans of every internal node, children before parents: in reverse id
// order where every internal child has a larger id than its parent, as in the SAH builder's
// depth-first order (a linear walk the hardware prefetches, without a stack: the plans are the
// same in any children-first order), else (the LBVH's and PLOC's trees) by a post-order walk.
void plan_collapse(const std::vector<BvhNode>& binary, int merge, std::vector<Range>& ranges,
                   std::vector<CollapsePlan>& plans) {
  ranges.assign(binary.size(), Range{});
  plans.assign(binary.size(), CollapsePlan{});
  const auto plan = [&](std::uint32_t node) {
    ranges[node] = subtree_range(binary[node], ranges);
    plan_node(binary, node, ranges[node], merge, plans);
  };
  const auto children_after = [&](std::uint32_t node) {
    for (const std::uint32_t c : binary[node].child)
      if (!is_leaf(c) && c <= node) return false;
    return true;
  };
  auto next = static_cast<std::uint32_t>(binary.size());
  while (next > 0 && children_after(next - 1)) plan(--next);
  if (next == 0) return;
  std::vector<std::pair<std::uint32_t, bool>> work{{0u, false}};
  while (!work.empty()) {
    const auto [node, children_done] = work.back();
    work.pop_back();
    const BvhNode& nd = binary[node];
    if (!children_done) {
      work.push_back({node, true});
      for (int k = 0; k < 2; ++k)
        if (!is_leaf(nd.child[k])) work.push_back({nd.child[k], false});
      continue;
    }
    plan(node);
  }
}

// Appends the wide children that binary child `ref` becomes when given `slots` slots.
void gather_slots(const std::vector<BvhNode>& binary, const std::vector<CollapsePlan>& plans,
                  std::uint32_t ref, const Aabb& box, int slots, Slot* out, int& n) {
  if (is_leaf(ref) || plans[ref].split[slots - 1] == 0) {
    out[n++] = {box, ref};
    return;
  }
  const BvhNode& nd = binary[ref];
  const int k = plans[ref].split[slots - 1];
  gather_slots(binary, plans, nd.child[0], nd.box(0), k, out, n);
  gather_slots(binary, plans, nd.child[1], nd.box(1), slots - k, out, n);
}

}  // namespace

WideBvh collapse_to_wide(const std::vector<BvhNode>& binary, const Triangle* tris, const int* prim,
                         int merge) {
  WideBvh out;
  if (binary.empty()) return out;
  merge = std::min(merge, kMaxLeafSize);
  std::vector<Range> ranges;
  std::vector<CollapsePlan> plans;
  plan_collapse(binary, merge, ranges, plans);
  // Each wide leaf holds one binary leaf or more (at most binary.size() + 1 of them): reserved
  // whole, untouched pages cost nothing, and the leaves are never copied by regrowth.
  out.nodes.reserve(binary.size() / 2 + 1);
  out.leaves.reserve(binary.size() + 1);
  LeafPlacer leaves{out.leaves};
  // Each work item: a binary node to turn into the wide node `dst`.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> work{{0u, 0u}};
  out.nodes.emplace_back();
  while (!work.empty()) {
    const auto [src, dst] = work.back();
    work.pop_back();
    Slot slots[kWidth];
    int n = 0;
    const BvhNode& nd = binary[src];
    const int split = plans[src].node_split;
    gather_slots(binary, plans, nd.child[0], nd.box(0), split, slots, n);
    gather_slots(binary, plans, nd.child[1], nd.box(1), kWidth - split, slots, n);
    for (int k = 0; k < kWidth; ++k) {
      if (k >= n || slots[k].ref == kEmptyLeaf) {
        Aabb empty;  // lo > hi on every axis: never hit by the wide slab test
        set_lane(out.nodes[dst], k, empty, kEmptyLeaf);
        continue;
      }
      std::uint32_t ref = slots[k].ref;
      if (is_leaf(ref) || plans[ref].as_leaf) {
        const Range r = is_leaf(ref) ? Range{leaf_first(ref), leaf_count(ref), true} : ranges[ref];
        ref = leaves.place(tris, prim, r.first, r.count);
      } else {
        const auto id = static_cast<std::uint32_t>(out.nodes.size());
        out.nodes.emplace_back();
        work.push_back({ref, id});
        ref = id;
      }
      set_lane(out.nodes[dst], k, slots[k].box, ref);
    }
  }
  return out;
}

void offset_leaf_prims(const WideNode* nodes, std::size_t count, TriangleLanes* blocks, int delta) {
  for (std::size_t i = 0; i < count; ++i)
    for (const std::uint32_t c : nodes[i].child) {
      if (!is_leaf(c) || c == kEmptyLeaf) continue;
      const int lanes =
          leaf_count(c) <= std::uint32_t(kCompactLeafSize) ? kCompactLeafSize : kMaxLeafSize;
      char* ids = reinterpret_cast<char*>(&blocks[leaf_first(c) / 2]) +
                  (leaf_first(c) & 1u) * (sizeof(TriangleLanes) / 2) + 9 * lanes * sizeof(Real);
      for (int k = 0; k < lanes; ++k) {
        int id;
        std::memcpy(&id, ids + k * sizeof(int), sizeof id);
        id += delta;
        std::memcpy(ids + k * sizeof(int), &id, sizeof id);
      }
    }
}

}  // namespace rtmini::bvh
