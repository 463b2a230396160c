#include "rtmini/bvh/build_sah.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>

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
  Aabb box;        // bounds of the items' boxes
  Aabb centroids;  // bounds of their centroids
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

Task range_task(const std::vector<Item>& items, int b, int e, int node, int slot, int depth) {
  Task t{b, e, node, slot, depth, Aabb(), Aabb()};
  t.box = range_box(items, b, e, &t.centroids);
  return t;
}

// A bin's box as four lanes (x, y, z, unused) so a merge is one 4-wide min and max, which the
// compiler vectorises; lane 3 carries whatever follows x, y, z in memory and is never read.
struct BinBox {
  Real lo[4], hi[4];
  BinBox() {
    for (int j = 0; j < 4; ++j) lo[j] = Real(1e30), hi[j] = Real(-1e30);
  }
  void expand(const Real* l, const Real* h) {
    for (int j = 0; j < 4; ++j) lo[j] = l[j] < lo[j] ? l[j] : lo[j];
    for (int j = 0; j < 4; ++j) hi[j] = h[j] > hi[j] ? h[j] : hi[j];
  }
  void expand(const BinBox& b) { expand(b.lo, b.hi); }
  Aabb aabb() const {
    Aabb a;
    a.lo = Vec3(lo[0], lo[1], lo[2]);
    a.hi = Vec3(hi[0], hi[1], hi[2]);
    return a;
  }
  Real surface_area() const { return aabb().surface_area(); }
};
static_assert(offsetof(Item, box) == 0 && sizeof(Aabb) == 6 * sizeof(Real) &&
                  sizeof(Item) >= sizeof(Aabb) + 4 * sizeof(Real),
              "an item's box can be read as two 4-lane loads");

// The two halves of a split, as tasks whose boxes are already known.
struct Split {
  Task left, right;
};

// Median split on the largest centroid axis, for ranges the SAH cannot split (e.g. identical
// centroids) or too deep.
int median_split(std::vector<Item>& items, const Task& t) {
  const int axis = max_dimension(t.centroids.extent());
  const int mid = t.begin + (t.end - t.begin) / 2;
  std::nth_element(items.begin() + t.begin, items.begin() + mid, items.begin() + t.end,
                   [axis](const Item& x, const Item& y) {
                     return x.centroid[axis] < y.centroid[axis] ||
                            (x.centroid[axis] == y.centroid[axis] && x.index < y.index);
                   });
  return mid;
}

// Moves the items with `left(item)` true to the front of [b, e) (the same swaps as
// std::partition) and returns the first of the others; also bounds each side's centroids,
// so the children need no pass of their own.
template <class Pred>
int partition_bounding(std::vector<Item>& items, int b, int e, const Pred& left, Aabb& lc,
                       Aabb& rc) {
  int first = b, last = e;
  while (true) {
    while (true) {
      if (first == last) return first;
      if (!left(items[first])) break;
      lc.expand(items[first].centroid);
      ++first;
    }
    rc.expand(items[first].centroid);
    --last;
    while (true) {
      if (first == last) return first;
      if (left(items[last])) break;
      rc.expand(items[last].centroid);
      --last;
    }
    lc.expand(items[last].centroid);
    std::swap(items[first], items[last]);
    ++first;
  }
}

// Best binned split of the task's range: true with the two halves, false for "make a leaf".
// One pass bins every item on all three axes (bin boxes are min/max, so exact in any order);
// the chosen bins' boxes are the children's boxes, and the partition bounds their centroids.
bool split_range(std::vector<Item>& items, const Task& t, Split& out) {
  const int b = t.begin, e = t.end;
  const int count = e - b;
  const Aabb& cb = t.centroids;
  const Real parent_area = t.box.surface_area();
  const Real leaf_cost = kTriangleCost * count * parent_area;
  Real best = leaf_cost;
  int best_axis = -1, best_bin = -1;
  const Vec3 ext = cb.extent();
  BinBox bins[3][kBins];
  int counts[3][kBins] = {};
  Real scale[3];
  for (int axis = 0; axis < 3; ++axis)
    scale[axis] = ext[axis] > Real(0) ? Real(kBins) / ext[axis] * Real(0.999999) : Real(0);
  for (int i = b; i < e; ++i) {
    const Item& it = items[i];
    Real lo[4], hi[4];
    std::memcpy(lo, &it.box.lo, sizeof lo);
    std::memcpy(hi, &it.box.hi, sizeof hi);
    for (int axis = 0; axis < 3; ++axis) {
      const int k =
          std::min(kBins - 1, static_cast<int>((it.centroid[axis] - cb.lo[axis]) * scale[axis]));
      bins[axis][k].expand(lo, hi);
      ++counts[axis][k];
    }
  }
  Aabb best_left, best_right;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(ext[axis] > Real(0))) continue;
    BinBox right_box[kBins];
    int right_count[kBins];
    BinBox acc;
    int cnt = 0;
    for (int k = kBins - 1; k > 0; --k) {
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
      right_box[k] = acc;
      right_count[k] = cnt;
    }
    acc = BinBox();
    cnt = 0;
    for (int k = 0; k < kBins - 1; ++k) {
      // An empty bin would repeat the previous candidate's cost, which never wins (strict <).
      if (counts[axis][k] == 0) continue;
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
      if (right_count[k + 1] == 0) continue;
      const Real c = kTraversalCost * parent_area +
                     kTriangleCost * (cnt * acc.surface_area() +
                                      right_count[k + 1] * right_box[k + 1].surface_area());
      if (c < best) {
        best = c;
        best_axis = axis;
        best_bin = k;
        best_left = acc.aabb();
        best_right = right_box[k + 1].aabb();
      }
    }
  }
  int mid;
  Aabb lc, rc;
  if (best_axis < 0 || t.depth >= kMaxDepth) {
    if (count <= kMaxLeafSize) return false;
    mid = median_split(items, t);
    out.left = range_task(items, b, mid, -1, 0, t.depth + 1);
    out.right = range_task(items, mid, e, -1, 1, t.depth + 1);
    return true;
  }
  const Real s = scale[best_axis];
  const Real lo = cb.lo[best_axis];
  mid = partition_bounding(
      items, b, e,
      [&](const Item& x) {
        return std::min(kBins - 1, static_cast<int>((x.centroid[best_axis] - lo) * s)) <= best_bin;
      },
      lc, rc);
  out.left = {b, mid, -1, 0, t.depth + 1, best_left, lc};
  out.right = {mid, e, -1, 1, t.depth + 1, best_right, rc};
  return true;
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
  Split sp;
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    if (t.end - t.begin <= 1 || !split_range(items, t, sp)) {
      set_ref(t, emit_leaf(t.begin, t.end));
      continue;
    }
    const int id = static_cast<int>(f.nodes.size());
    f.nodes.emplace_back();
    set_ref(t, static_cast<std::uint32_t>(id));
    sp.left.node = sp.right.node = id;
    stack.push_back(sp.right);
    stack.push_back(sp.left);
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

// The tree over all items (sets out.bounds), its child boxes as the SAH saw them (not yet padded).
void build_tree(std::vector<Item>& items, const std::vector<Triangle>& input, HostBvh& out) {
  const int n = static_cast<int>(items.size());
  Task root = range_task(items, 0, n, -1, 0, 0);
  out.bounds = root.box;
  if (n == 0) return;
  out.nodes.reserve(std::max(1, 2 * n / kMaxLeafSize + 1));
  out.tris.reserve(n);
  out.prim.reserve(n);

  // The root is always an internal node with two slots.
  out.nodes.emplace_back();
  Split sp;
  if (n == 1 || !split_range(items, root, sp)) {
    Fragment leaf;
    root.depth = kMaxDepth;
    build_fragment(items, input, root, leaf);
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
  sp.left.node = sp.right.node = 0;
  stack.push_back(sp.right);
  stack.push_back(sp.left);
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    if (t.end - t.begin <= fragment_max || !split_range(items, t, sp)) {
      fragments.push_back(t);
      continue;
    }
    const int id = static_cast<int>(out.nodes.size());
    out.nodes.emplace_back();
    out.nodes[t.node].set_child(t.slot, t.box, static_cast<std::uint32_t>(id));
    sp.left.node = sp.right.node = id;
    stack.push_back(sp.right);
    stack.push_back(sp.left);
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
  out.references = static_cast<int>(items.size());
  build_tree(items, input, out);
  for (BvhNode& node : out.nodes) pad_child_boxes(node);
  return out;
}

}  // namespace rtmini::bvh
