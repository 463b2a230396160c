#include "rtmini/bvh/build_sah.hpp"

#include <algorithm>

namespace rtmini::bvh {

namespace {

constexpr int kBins = 16;
constexpr Real kTraversalCost = 1;
constexpr Real kTriangleCost = 1;
constexpr int kMaxDepth = kStackSize - 2;

struct Item {
  Aabb box;
  Vec3 centroid;
  int index;
};

struct Task {
  int begin, end;  // item range
  int node;        // node to fill with this range's split (or -1 for the root)
  int slot;        // which child of `node`
  int depth;
  Aabb box;
};

Aabb range_box(const std::vector<Item>& items, int b, int e, Aabb* centroids) {
  Aabb box, cb;
  for (int i = b; i < e; ++i) {
    box.expand(items[i].box);
    cb.expand(items[i].centroid);
  }
  *centroids = cb;
  return box;
}

// Best binned split of items[b, e): returns the partition point or -1 for "make a leaf".
int split_range(std::vector<Item>& items, int b, int e, const Aabb& box, int depth) {
  const int count = e - b;
  Aabb cb;
  range_box(items, b, e, &cb);
  const Real leaf_cost = kTriangleCost * count * box.surface_area();
  Real best = leaf_cost;
  int best_axis = -1, best_bin = -1;
  const Vec3 ext = cb.extent();
  for (int axis = 0; axis < 3; ++axis) {
    if (!(ext[axis] > Real(0))) continue;
    Aabb bins[kBins];
    int counts[kBins] = {};
    const Real scale = Real(kBins) / ext[axis] * Real(0.999999);
    for (int i = b; i < e; ++i) {
      const int k =
          std::min(kBins - 1, static_cast<int>((items[i].centroid[axis] - cb.lo[axis]) * scale));
      bins[k].expand(items[i].box);
      ++counts[k];
    }
    Real right_area[kBins];
    int right_count[kBins];
    Aabb acc;
    int cnt = 0;
    for (int k = kBins - 1; k > 0; --k) {
      acc.expand(bins[k]);
      cnt += counts[k];
      right_area[k] = acc.surface_area();
      right_count[k] = cnt;
    }
    acc = Aabb();
    cnt = 0;
    for (int k = 0; k < kBins - 1; ++k) {
      acc.expand(bins[k]);
      cnt += counts[k];
      if (cnt == 0 || right_count[k + 1] == 0) continue;
      const Real c =
          kTraversalCost * box.surface_area() +
          kTriangleCost * (cnt * acc.surface_area() + right_count[k + 1] * right_area[k + 1]);
      if (c < best) {
        best = c;
        best_axis = axis;
        best_bin = k;
      }
    }
  }
  const bool must_split = count > kMaxLeafSize;
  if (best_axis < 0 || depth >= kMaxDepth) {
    if (!must_split) return -1;
    // No useful SAH split (e.g. identical centroids) or too deep: median split.
    const int axis = max_dimension(ext);
    const int mid = b + count / 2;
    std::nth_element(items.begin() + b, items.begin() + mid, items.begin() + e,
                     [axis](const Item& x, const Item& y) {
                       return x.centroid[axis] < y.centroid[axis] ||
                              (x.centroid[axis] == y.centroid[axis] && x.index < y.index);
                     });
    return mid;
  }
  const Real scale = Real(kBins) / ext[best_axis] * Real(0.999999);
  auto it = std::partition(items.begin() + b, items.begin() + e, [&](const Item& x) {
    return std::min(kBins - 1, static_cast<int>((x.centroid[best_axis] - cb.lo[best_axis]) *
                                                scale)) <= best_bin;
  });
  return static_cast<int>(it - items.begin());
}

}  // namespace

HostBvh build_sah_host(const std::vector<Triangle>& input) {
  HostBvh out;
  const int n = static_cast<int>(input.size());
  std::vector<Item> items(n);
  for (int i = 0; i < n; ++i) {
    Aabb b;
    b.expand(input[i].a);
    b.expand(input[i].b);
    b.expand(input[i].c);
    items[i] = {b, (input[i].a + input[i].b + input[i].c) * (Real(1) / Real(3)), i};
  }
  Aabb dummy;
  out.bounds = range_box(items, 0, n, &dummy);
  if (n == 0) return out;
  out.nodes.reserve(std::max(1, 2 * n / kMaxLeafSize + 1));
  out.nodes.emplace_back();
  out.tris.reserve(n);
  out.prim.reserve(n);

  auto emit_leaf = [&](int b, int e) {
    const auto first = static_cast<std::uint32_t>(out.tris.size());
    for (int i = b; i < e; ++i) {
      out.tris.push_back(input[items[i].index]);
      out.prim.push_back(items[i].index);
    }
    return make_leaf(first, static_cast<std::uint32_t>(e - b));
  };

  // The root is always an internal node; each task fills one child slot.
  std::vector<Task> stack;
  const int root_split = n > 1 ? split_range(items, 0, n, out.bounds, 0) : -1;
  if (root_split < 0) {
    out.nodes[0].set_child(0, out.bounds, emit_leaf(0, n));
    out.nodes[0].set_child(1, Aabb(), kEmptyLeaf);
    return out;
  }
  Aabb c;
  stack.push_back({root_split, n, 0, 1, 1, range_box(items, root_split, n, &c)});
  stack.push_back({0, root_split, 0, 0, 1, range_box(items, 0, root_split, &c)});
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    const int mid = t.end - t.begin > 1 ? split_range(items, t.begin, t.end, t.box, t.depth) : -1;
    if (mid < 0) {
      out.nodes[t.node].set_child(t.slot, t.box, emit_leaf(t.begin, t.end));
      continue;
    }
    const int id = static_cast<int>(out.nodes.size());
    out.nodes.emplace_back();
    out.nodes[t.node].set_child(t.slot, t.box, static_cast<std::uint32_t>(id));
    // Depth-first order: the left child is processed next, so it lands next to its parent.
    stack.push_back({mid, t.end, id, 1, t.depth + 1, range_box(items, mid, t.end, &c)});
    stack.push_back({t.begin, mid, id, 0, t.depth + 1, range_box(items, t.begin, mid, &c)});
  }
  return out;
}

}  // namespace rtmini::bvh
