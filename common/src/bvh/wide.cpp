#include "rtmini/bvh/wide.hpp"

#include <algorithm>
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

// Triangle ranges of every internal node's subtree, children before parents (both builders
// store a subtree's triangles contiguously; `contiguous` guards the merge if one ever does not).
std::vector<Range> subtree_ranges(const std::vector<BvhNode>& binary) {
  std::vector<Range> out(binary.size());
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
    Range r;
    r.first = ~0u;
    std::uint32_t end = 0;
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t c = nd.child[k];
      if (c == kEmptyLeaf) continue;
      const Range sub = is_leaf(c) ? Range{leaf_first(c), leaf_count(c), true} : out[c];
      r.first = std::min(r.first, sub.first);
      end = std::max(end, sub.first + sub.count);
      r.count += sub.count;
      r.contiguous = r.contiguous && sub.contiguous;
    }
    r.contiguous = r.contiguous && end - r.first == r.count;
    out[node] = r;
  }
  return out;
}

// Unused lanes repeat the first triangle; the traversal masks them by the leaf's count.
TriangleLanes make_lanes(const Triangle* tris, const int* prim, std::uint32_t first,
                         std::uint32_t count) {
  TriangleLanes l;
  for (int k = 0; k < kMaxLeafSize; ++k) {
    const std::uint32_t i = first + (k < int(count) ? std::uint32_t(k) : 0u);
    const Triangle& t = tris[i];
    l.ax[k] = t.a.x, l.ay[k] = t.a.y, l.az[k] = t.a.z;
    l.bx[k] = t.b.x, l.by[k] = t.b.y, l.bz[k] = t.b.z;
    l.cx[k] = t.c.x, l.cy[k] = t.c.y, l.cz[k] = t.c.z;
    l.prim[k] = prim[i];
  }
  return l;
}

}  // namespace

WideBvh collapse_to_wide(const std::vector<BvhNode>& binary, const Triangle* tris, const int* prim,
                         int merge) {
  WideBvh out;
  if (binary.empty()) return out;
  merge = std::min(merge, kMaxLeafSize);
  const std::vector<Range> ranges = subtree_ranges(binary);
  // A child becomes a wide leaf when it is a binary leaf or a small enough subtree.
  auto leaf_range = [&](std::uint32_t ref, Range& r) {
    if (is_leaf(ref)) {
      r = {leaf_first(ref), leaf_count(ref), true};
      return true;
    }
    r = ranges[ref];
    return r.contiguous && r.count <= std::uint32_t(merge);
  };
  // Each wide leaf holds one binary leaf or more (at most binary.size() + 1 of them): reserved
  // whole, untouched pages cost nothing, and the leaves are never copied by regrowth.
  out.nodes.reserve(binary.size() / 2 + 1);
  out.leaves.reserve(binary.size() + 1);
  // Each work item: a binary node to turn into the wide node `dst`.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> work{{0u, 0u}};
  out.nodes.emplace_back();
  while (!work.empty()) {
    const auto [src, dst] = work.back();
    work.pop_back();
    Slot slots[kWidth];
    int n = 0;
    for (int k = 0; k < 2; ++k) slots[n++] = {binary[src].box(k), binary[src].child[k]};
    // Open the internal child with the largest surface area until kWidth children.
    while (n < kWidth) {
      int best = -1;
      Real best_area = -1;
      for (int k = 0; k < n; ++k) {
        Range r;
        if (leaf_range(slots[k].ref, r)) continue;
        const Real a = slots[k].box.surface_area();
        if (a > best_area) {
          best_area = a;
          best = k;
        }
      }
      if (best < 0) break;
      const BvhNode& open = binary[slots[best].ref];
      slots[best] = {open.box(0), open.child[0]};
      slots[n++] = {open.box(1), open.child[1]};
    }
    for (int k = 0; k < kWidth; ++k) {
      if (k >= n || slots[k].ref == kEmptyLeaf) {
        Aabb empty;  // lo > hi on every axis: never hit by the wide slab test
        set_lane(out.nodes[dst], k, empty, kEmptyLeaf);
        continue;
      }
      std::uint32_t ref = slots[k].ref;
      Range r;
      if (leaf_range(ref, r)) {
        ref = make_leaf(static_cast<std::uint32_t>(out.leaves.size()), r.count);
        out.leaves.push_back(make_lanes(tris, prim, r.first, r.count));
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

}  // namespace rtmini::bvh
