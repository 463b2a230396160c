#include "rtmini/bvh/build_sah.hpp"

#include <algorithm>

#include "rtmini/bvh/finish.hpp"
#include "rtmini/bvh/presplit.hpp"

namespace rtmini::bvh {

namespace {

constexpr int kBins = 16;
constexpr Real kTraversalCost = 1;
constexpr Real kTriangleCost = 1;
constexpr int kMaxDepth = kStackSize - 2;
// Subtrees of at most max(kMinFragment, n / kFragmentShare) items are built in parallel.
constexpr int kFragmentShare = 64;
constexpr int kMinFragment = 256;

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
  // One pass bins every item on all three axes (bin boxes are min/max, so exact in any order).
  Aabb bins[3][kBins];
  int counts[3][kBins] = {};
  Real scale[3];
  for (int axis = 0; axis < 3; ++axis)
    scale[axis] = ext[axis] > Real(0) ? Real(kBins) / ext[axis] * Real(0.999999) : Real(0);
  for (int i = b; i < e; ++i) {
    const Item& it = items[i];
    for (int axis = 0; axis < 3; ++axis) {
      const int k =
          std::min(kBins - 1, static_cast<int>((it.centroid[axis] - cb.lo[axis]) * scale[axis]));
      bins[axis][k].expand(it.box);
      ++counts[axis][k];
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(ext[axis] > Real(0))) continue;
    Real right_area[kBins];
    int right_count[kBins];
    Aabb acc;
    int cnt = 0;
    for (int k = kBins - 1; k > 0; --k) {
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
      right_area[k] = acc.surface_area();
      right_count[k] = cnt;
    }
    acc = Aabb();
    cnt = 0;
    for (int k = 0; k < kBins - 1; ++k) {
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
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
  const Real s = scale[best_axis];
  auto it = std::partition(items.begin() + b, items.begin() + e, [&](const Item& x) {
    return std::min(kBins - 1, static_cast<int>((x.centroid[best_axis] - cb.lo[best_axis]) * s)) <=
           best_bin;
  });
  return static_cast<int>(it - items.begin());
}

// One subtree built on its own (possibly by another thread): nodes and leaf triangles with local
// indices, appended to the whole tree afterwards.
struct Fragment {
  std::vector<BvhNode> nodes;
  std::vector<Triangle> tris;
  std::vector<int> prim;
  std::uint32_t root = 0;  // reference for the parent's slot (local node index or local leaf)
};

// The serial top-down build of items[task.begin, task.end), depth first (the left child is
// processed next, so it lands next to its parent).
void build_fragment(std::vector<Item>& items, const std::vector<Triangle>& input, const Task& top,
                    Fragment& f) {
  // A leaf stores each triangle once, even when several of its pre-split parts landed here.
  auto emit_leaf = [&](int b, int e) {
    const auto first = static_cast<std::uint32_t>(f.tris.size());
    for (int i = b; i < e; ++i) {
      const int id = items[i].index;
      if (std::any_of(f.prim.begin() + first, f.prim.end(), [id](int p) { return p == id; }))
        continue;
      f.tris.push_back(point_if_zero_area(input[id]));
      f.prim.push_back(id);
    }
    return make_leaf(first, static_cast<std::uint32_t>(f.tris.size() - first));
  };
  auto set_ref = [&](const Task& t, std::uint32_t ref) {
    if (t.node < 0)
      f.root = ref;
    else
      f.nodes[t.node].set_child(t.slot, t.box, ref);
  };
  std::vector<Task> stack{top};
  Aabb c;
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    const int mid = t.end - t.begin > 1 ? split_range(items, t.begin, t.end, t.box, t.depth) : -1;
    if (mid < 0) {
      set_ref(t, emit_leaf(t.begin, t.end));
      continue;
    }
    const int id = static_cast<int>(f.nodes.size());
    f.nodes.emplace_back();
    set_ref(t, static_cast<std::uint32_t>(id));
    stack.push_back({mid, t.end, id, 1, t.depth + 1, range_box(items, mid, t.end, &c)});
    stack.push_back({t.begin, mid, id, 0, t.depth + 1, range_box(items, t.begin, mid, &c)});
  }
}

// Appends a fragment to the tree and returns its root reference with global indices.
std::uint32_t append_fragment(const Fragment& f, HostBvh& out) {
  const auto node_base = static_cast<std::uint32_t>(out.nodes.size());
  const auto tri_base = static_cast<std::uint32_t>(out.tris.size());
  auto global = [&](std::uint32_t ref) {
    if (ref == kEmptyLeaf) return ref;
    return is_leaf(ref) ? make_leaf(leaf_first(ref) + tri_base, leaf_count(ref)) : ref + node_base;
  };
  for (BvhNode n : f.nodes) {
    for (int k = 0; k < 2; ++k) n.child[k] = global(n.child[k]);
    out.nodes.push_back(n);
  }
  out.tris.insert(out.tris.end(), f.tris.begin(), f.tris.end());
  out.prim.insert(out.prim.end(), f.prim.begin(), f.prim.end());
  return global(f.root);
}

// One item per triangle, or per pre-split part of a sliver when splitting pays (presplit.hpp).
std::vector<Item> make_items(const std::vector<Triangle>& input, double split_budget) {
  const int n = static_cast<int>(input.size());
  std::vector<Item> items(n);
  Aabb bounds;
  for (int i = 0; i < n; ++i) {
    Aabb b;
    b.expand(input[i].a);
    b.expand(input[i].b);
    b.expand(input[i].c);
    items[i] = {b, (input[i].a + input[i].b + input[i].c) * (Real(1) / Real(3)), i};
    bounds.expand(b);
  }
  const std::vector<SplitReference> refs = presplit_triangles(input, bounds, split_budget);
  if (refs.empty()) return items;
  items.resize(refs.size());
  for (std::size_t i = 0; i < refs.size(); ++i)
    items[i] = {refs[i].box, refs[i].centroid, refs[i].prim};
  return items;
}

// The tree over all items, its child boxes as the SAH saw them (not yet padded).
void build_tree(std::vector<Item>& items, const std::vector<Triangle>& input, HostBvh& out) {
  const int n = static_cast<int>(items.size());
  out.nodes.reserve(std::max(1, 2 * n / kMaxLeafSize + 1));
  out.tris.reserve(n);
  out.prim.reserve(n);

  // The root is always an internal node with two slots.
  out.nodes.emplace_back();
  const int root_split = n > 1 ? split_range(items, 0, n, out.bounds, 0) : -1;
  if (root_split < 0) {
    Fragment leaf;
    build_fragment(items, input, {0, n, -1, 0, kMaxDepth, out.bounds}, leaf);
    const std::uint32_t ref = append_fragment(leaf, out);
    out.nodes[0].set_child(0, out.bounds, ref);
    out.nodes[0].set_child(1, Aabb(), kEmptyLeaf);
    return;
  }
  // Top levels serially, down to ranges of at most kFragmentShare of the input; those subtrees
  // are independent and are built in parallel. The cut depends on n only, and fragments are
  // appended in the serial depth-first order, so the tree is the same for any thread count.
  const int fragment_max = std::max(kMinFragment, n / kFragmentShare);
  std::vector<Task> fragments, stack;
  Aabb c;
  stack.push_back({root_split, n, 0, 1, 1, range_box(items, root_split, n, &c)});
  stack.push_back({0, root_split, 0, 0, 1, range_box(items, 0, root_split, &c)});
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    const int mid =
        t.end - t.begin > fragment_max ? split_range(items, t.begin, t.end, t.box, t.depth) : -1;
    if (mid < 0) {
      fragments.push_back(t);
      continue;
    }
    const int id = static_cast<int>(out.nodes.size());
    out.nodes.emplace_back();
    out.nodes[t.node].set_child(t.slot, t.box, static_cast<std::uint32_t>(id));
    stack.push_back({mid, t.end, id, 1, t.depth + 1, range_box(items, mid, t.end, &c)});
    stack.push_back({t.begin, mid, id, 0, t.depth + 1, range_box(items, t.begin, mid, &c)});
  }
  std::vector<Fragment> built(fragments.size());
  Kokkos::parallel_for(
      "rtmini::bvh::build_sah::fragments",
      Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>>(
          0, static_cast<int>(fragments.size())),
      [&](const int i) {
        Task t = fragments[i];
        t.node = -1;  // the fragment's root reference goes to the parent slot below
        build_fragment(items, input, t, built[i]);
      });
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    const std::uint32_t ref = append_fragment(built[i], out);  // may reallocate out.nodes
    out.nodes[fragments[i].node].set_child(fragments[i].slot, fragments[i].box, ref);
  }
}

}  // namespace

HostBvh build_sah_host(const std::vector<Triangle>& input, double split_budget) {
  HostBvh out;
  std::vector<Item> items = make_items(input, split_budget);
  const int n = static_cast<int>(items.size());
  out.references = n;
  Aabb dummy;
  out.bounds = range_box(items, 0, n, &dummy);
  if (n == 0) return out;
  build_tree(items, input, out);
  for (BvhNode& node : out.nodes) pad_child_boxes(node);
  return out;
}

}  // namespace rtmini::bvh
