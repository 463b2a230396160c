#include "rtmini/bvh/build_sah.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <memory>
#include <mutex>
#include <numeric>
#include <thread>
#include <type_traits>

#include "rtmini/bvh/clip.hpp"
#include "rtmini/bvh/finish.hpp"
#include "rtmini/bvh/presplit.hpp"
#include "rtmini/parallel/host_threads.hpp"

namespace rtmini::bvh {

namespace {

constexpr int kBins = 16;
// (Named apart from build_lbvh.hpp's subtree_cost constants: clang.syntax batches see both.)
constexpr Real kSahTraversalCost = 1;
constexpr Real kSahTriangleCost = 1;
// For the host's traversal (SahLeafCost::kBlocksOfFour), on ordinary meshes the SAH's triangle
// term counts a side's triangles in blocks of four, the lanes of a compact leaf: the traversal
// tests a wide leaf's lanes at once, so one to four triangles cost about the same. Cuts that leave
// a side just past a multiple of four then cost a block more, and small ranges stay one leaf
// instead of being split to single triangles that the collapse merges again: half the binary nodes,
// and the build's many small split_range calls with them (results/bvh/README.md, branch cpu15).
// Answers do not depend on the tree (the closest hit's tie-break is by triangle id). Builds with
// split references (pre-split or spatial splits) count single triangles, as before: larger leaves
// would hold more parts of one sliver.
constexpr int kLeafBlock = 4;
constexpr int kMaxDepth = kStackSize - 2;
// Subtrees of at most max(kMinFragment, n / kFragmentShare) items are built in parallel.
constexpr int kFragmentShare = 64;
constexpr int kMinFragment = 256;
// The levels above ranges of n / (kPartsPerThread * threads) items are split serially, the rest
// of the top in parallel (parts); that cut does not change the tree, only who builds what.
constexpr int kPartsPerThread = 2;
// Spatial splits are tried where the best object split's children overlap by more than this
// fraction of the root's surface area (the value Stich et al. 2009 suggest; on a 100K-triangle
// mesh it still passes at most nodes, which is what makes the build slow: slivers.md).
constexpr double kSpatialAlpha = 1e-5;
constexpr int kSpatialBins = 32;

struct Item {
  Aabb box;
  Vec3 centroid;
  int index;
};

using Items = std::vector<Item>;
// The lists spatial splits make, kept until the build that made them ends.
using ItemLists = std::vector<std::unique_ptr<Items>>;

struct Task {
  int begin, end;  // item range
  int node;        // node to fill with this range's split (or -1 for the root)
  int slot;        // which child of `node`
  int depth;
  Aabb box;        // bounds of the items' boxes
  Aabb centroids;  // bounds of their centroids
  // The items [begin, end) live in: object splits partition their parent's range in place, a
  // spatial split copies its (partly duplicated) references into two new lists (owned by the
  // ItemLists of the build that made them). A plain pointer: tasks are copied at every node, and
  // a shared count would be one cache line both threads write.
  Items* items = nullptr;
  double budget = 0;  // references this subtree may still add by spatial splits
};

// What the spatial splits need; `input` null means object splits only.
struct SpatialContext {
  const TriangleSpan* input = nullptr;
  Real min_overlap = 0;  // kSpatialAlpha times the root's surface area
  double margin = 0;     // kClipMargin times the scene's largest extent
  int leaf_block = 1;    // the SAH counts triangles in blocks of this many (kLeafBlock or 1)
};

// The SAH's triangle term for `n` items: n rounded up to whole blocks.
Real triangle_term(const SpatialContext& ctx, int n) {
  return Real((n + ctx.leaf_block - 1) / ctx.leaf_block * ctx.leaf_block);
}

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
  Task t{b, e, node, slot, depth, Aabb(), Aabb(), nullptr, 0};
  t.box = range_box(items, b, e, &t.centroids);
  return t;
}

// The children's share of a split parent's remaining reference budget, by item count.
void share_budget(double budget, Task& left, Task& right) {
  const double nl = left.end - left.begin, nr = right.end - right.begin;
  left.budget = budget * nl / (nl + nr);
  right.budget = budget - left.budget;
}

// A bin's box as four lanes (x, y, z, unused) so a merge is one 4-wide min and max, which the
// compiler vectorises; lane 3 carries what follows x, y, z in an item (its box's hi.x, its
// centroid's x: finite, so the min and max raise nothing) and is never read.
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
  // Aabb::surface_area's arithmetic, with its emptiness test as a select rather than branches
  // (a bin's sweep box is never empty, so those branches only cost their instructions).
  Real surface_area() const {
    const Real ex = hi[0] - lo[0], ey = hi[1] - lo[1], ez = hi[2] - lo[2];
    const bool empty = !((lo[0] <= hi[0]) & (lo[1] <= hi[1]) & (lo[2] <= hi[2]));
    const Real area = Real(2) * (ex * ey + ey * ez + ez * ex);
    return empty ? Real(0) : area;
  }
};
static_assert(offsetof(Item, box) == 0 && sizeof(Aabb) == 6 * sizeof(Real) &&
                  sizeof(Item) >= sizeof(Aabb) + 4 * sizeof(Real),
              "an item's box can be read as two 4-lane loads");

// The lowest / highest set bit of a non-zero mask.
int lowest_bit(unsigned m) { return __builtin_ctz(m); }
int highest_bit(unsigned m) { return 31 - __builtin_clz(m); }

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

// Bounds of centroids as four lanes (x, y, z and a zero), so adding an item is one 4-wide min
// and max instead of six scalar ones; the same comparisons as Aabb::expand, so in the same order
// the same bounds. Lane 3 is loaded from the item's index and, in double, 4 bytes of padding
// that nothing initialises: zeroed, because a NaN pattern there raises FE_INVALID in the min
// (the unit tests trap it; it failed 1 run in 3 before the zero).
struct CentroidBounds {
  Real lo[4], hi[4];
  CentroidBounds() {
    for (int j = 0; j < 4; ++j) lo[j] = Real(1e30), hi[j] = Real(-1e30);
  }
  void expand(const Item& it) {
    Real c[4];
    std::memcpy(c, &it.centroid, sizeof c);
    c[3] = Real(0);
    for (int j = 0; j < 4; ++j) lo[j] = lo[j] < c[j] ? lo[j] : c[j];
    for (int j = 0; j < 4; ++j) hi[j] = hi[j] > c[j] ? hi[j] : c[j];
  }
  Aabb aabb() const {
    Aabb a;
    a.lo = Vec3(lo[0], lo[1], lo[2]);
    a.hi = Vec3(hi[0], hi[1], hi[2]);
    return a;
  }
};
static_assert(offsetof(Item, centroid) + 4 * sizeof(Real) <= sizeof(Item),
              "an item's centroid can be read as one 4-lane load");

// Moves the items with `left(item)` true to the front of [b, e) (the same swaps as
// std::partition) and returns the first of the others; also bounds each side's centroids,
// so the children need no pass of their own.
template <class Pred>
int partition_bounding(std::vector<Item>& items, int b, int e, const Pred& left, Aabb& lc,
                       Aabb& rc) {
  CentroidBounds lb, rb;
  int first = b, last = e;
  while (true) {
    while (true) {
      if (first == last) {
        lc = lb.aabb();
        rc = rb.aabb();
        return first;
      }
      if (!left(items[first])) break;
      lb.expand(items[first]);
      ++first;
    }
    rb.expand(items[first]);
    --last;
    while (true) {
      if (first == last) {
        lc = lb.aabb();
        rc = rb.aabb();
        return first;
      }
      if (left(items[last])) break;
      rb.expand(items[last]);
      --last;
    }
    lb.expand(items[last]);
    std::swap(items[first], items[last]);
    ++first;
  }
}

// Ranges from this size on are partitioned without branches on the items (partition_batched).
constexpr int kBatchedPartition = 8;
// Misplaced items gathered per side in one step of partition_batched.
constexpr int kSwapBatch = 128;

// partition_bounding's result without a branch per item, whose outcome the predictor cannot
// guess at the top of the tree: std::partition swaps the k-th item of the left part that
// belongs right with the k-th item from the right end of the right part that belongs left, so
// one pass counts the left items (the partition point), then batches of both sides' misplaced
// positions are gathered (the position is stored and the count advances by the predicate) and
// swapped pairwise. The sides' centroid bounds are then taken over the same items in another
// order, which can only change the sign of a zero bound (inputs are finite), and that moves no
// bin: a bin is (centroid - lo) * scale truncated, and an extent of -0 or +0 is no extent.
template <class Pred>
int partition_batched(std::vector<Item>& items, int b, int e, const Pred& left, Aabb& lc,
                      Aabb& rc) {
  int mid = b;
  for (int i = b; i < e; ++i) mid += left(items[i]) ? 1 : 0;
  int lo = b, hi = e - 1;  // the next positions to look at on either side
  int low[kSwapBatch], high[kSwapBatch];
  while (true) {
    int nl = 0, nh = 0;  // equal: both sides hold as many misplaced items
    for (; lo < mid && nl < kSwapBatch; ++lo) {
      low[nl] = lo;
      nl += left(items[lo]) ? 0 : 1;
    }
    for (; hi >= mid && nh < kSwapBatch; --hi) {
      high[nh] = hi;
      nh += left(items[hi]) ? 1 : 0;
    }
    for (int k = 0; k < nl; ++k) std::swap(items[low[k]], items[high[k]]);
    if (nl < kSwapBatch) break;
  }
  CentroidBounds lb, rb;
  for (int i = b; i < mid; ++i) lb.expand(items[i]);
  for (int i = mid; i < e; ++i) rb.expand(items[i]);
  lc = lb.aabb();
  rc = rb.aabb();
  return mid;
}

// partition_bounding on "the item's bin on `axis` is at most `last_bin`", as the same scaled
// offset compared with last_bin + 1 (the bin is that offset truncated, and it is never negative)
// with the axis fixed at compile time: no float-to-int conversion or axis select per item.
int partition_by_bin(std::vector<Item>& items, int b, int e, int axis, Real lo, Real scale,
                     int last_bin, Aabb& lc, Aabb& rc) {
  const Real limit = Real(last_bin + 1);
  auto on_axis = [&](auto fixed) {
    constexpr int a = decltype(fixed)::value;
    const auto left = [&](const Item& x) { return (x.centroid[a] - lo) * scale < limit; };
    if (e - b >= kBatchedPartition) return partition_batched(items, b, e, left, lc, rc);
    return partition_bounding(items, b, e, left, lc, rc);
  };
  if (axis == 0) return on_axis(std::integral_constant<int, 0>());
  if (axis == 1) return on_axis(std::integral_constant<int, 1>());
  return on_axis(std::integral_constant<int, 2>());
}

// ---- Spatial splits (Stich, Friedrich & Dietrich 2009, "Spatial splits in bounding volume
// hierarchies"). An object split keeps each reference whole, so slivers that cross a node give
// both children boxes as large as the parent; a spatial split cuts the node's box by a plane and
// each straddling reference becomes two, bounded by the part of its triangle on either side
// (the triangle clipped to the reference's box and to the slab, not just the box cut in two).
// Leaves still hold whole triangles, so every hit is the one the triangle itself reports.

// Whether the best object split leaves enough overlap (or no split at all) to try a spatial one.
bool spatial_worth_trying(const SpatialContext& ctx, const Task& t, int best_axis, const Aabb& left,
                          const Aabb& right) {
  if (ctx.input == nullptr || t.budget < 1 || t.depth >= kMaxDepth) return false;
  if (best_axis < 0) return true;
  Aabb overlap;
  overlap.lo = vmax(left.lo, right.lo);
  overlap.hi = vmin(left.hi, right.hi);
  for (int axis = 0; axis < 3; ++axis)
    if (!(overlap.hi[axis] >= overlap.lo[axis])) return false;
  return overlap.surface_area() > ctx.min_overlap;
}

// The box of a clipped polygon within the reference's box (binning only: no margin).
void expand_by_polygon(BinBox& bin, const Polygon& p, const Aabb& ref) {
  if (p.n < 3) return;
  const Aabb b = part_box(p, ref, 0.0);
  const Real lo[4] = {b.lo.x, b.lo.y, b.lo.z, 0}, hi[4] = {b.hi.x, b.hi.y, b.hi.z, 0};
  bin.expand(lo, hi);
}

struct SpatialSplit {
  int axis = -1;
  Real plane = 0;
  Real cost = 0;
  int left_count = 0, right_count = 0;  // references entering / leaving, as binned
  Aabb left, right;                     // bounds of the chopped references on either side
};

// Bins every reference of the range into kSpatialBins slabs of the node's box on each axis:
// a reference counts as entering its first slab and leaving its last, and adds to every slab it
// crosses the box of its triangle's part in that slab. The best plane beats `best` (the cost to
// beat) within the range's reference budget, or `split.axis` stays -1.
SpatialSplit find_spatial_split(const SpatialContext& ctx, const Task& t, Real best) {
  const Items& items = *t.items;
  const Real parent_area = t.box.surface_area();
  const Vec3 ext = t.box.extent();
  BinBox bins[3][kSpatialBins];
  int enter[3][kSpatialBins] = {}, leave[3][kSpatialBins] = {};
  auto bin_of = [&](int axis, Real x) {
    const Real u = (x - t.box.lo[axis]) / ext[axis] * Real(kSpatialBins);
    return std::clamp(static_cast<int>(u), 0, kSpatialBins - 1);
  };
  auto plane_of = [&](int axis, int k) {  // between slabs k - 1 and k
    return t.box.lo[axis] + ext[axis] * (Real(k) / Real(kSpatialBins));
  };
  for (int i = t.begin; i < t.end; ++i) {
    const Item& it = items[i];
    const Triangle& tri = (*ctx.input)[it.index];
    Polygon whole;
    bool clipped = false;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(ext[axis] > Real(0))) continue;
      const int first = bin_of(axis, it.box.lo[axis]), last = bin_of(axis, it.box.hi[axis]);
      ++enter[axis][first];
      ++leave[axis][last];
      if (first == last) {
        bins[axis][first].expand(&it.box.lo.x, &it.box.hi.x);
        continue;
      }
      if (!clipped) {
        whole = triangle_in_box(tri, it.box);
        clipped = true;
      }
      Polygon rest = whole;
      for (int k = first; k < last; ++k) {
        const double plane = double(plane_of(axis, k + 1));
        expand_by_polygon(bins[axis][k], clip_halfspace(rest, axis, plane, true), it.box);
        rest = clip_halfspace(rest, axis, plane, false);
      }
      expand_by_polygon(bins[axis][last], rest, it.box);
    }
  }
  SpatialSplit best_split;
  const int count = t.end - t.begin;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(ext[axis] > Real(0))) continue;
    BinBox right_box[kSpatialBins];
    int right_count[kSpatialBins];
    BinBox acc;
    int cnt = 0;
    for (int k = kSpatialBins - 1; k > 0; --k) {
      acc.expand(bins[axis][k]);
      cnt += leave[axis][k];
      right_box[k] = acc;
      right_count[k] = cnt;
    }
    acc = BinBox();
    cnt = 0;
    for (int k = 0; k < kSpatialBins - 1; ++k) {
      acc.expand(bins[axis][k]);
      cnt += enter[axis][k];
      const int nr = right_count[k + 1];
      if (cnt == 0 || nr == 0 || cnt + nr - count > t.budget) continue;
      const Real c =
          kSahTraversalCost * parent_area +
          kSahTriangleCost * (cnt * acc.surface_area() + nr * right_box[k + 1].surface_area());
      if (c < best) {
        best = c;
        best_split.axis = axis;
        best_split.plane = plane_of(axis, k + 1);
        best_split.cost = c;
        best_split.left_count = cnt;
        best_split.right_count = nr;
        best_split.left = acc.aabb();
        best_split.right = right_box[k + 1].aabb();
      }
    }
  }
  return best_split;
}

// Which side a straddling reference goes to: both (-1 split it), or one whole (0 left,
// 1 right) when that costs less than splitting it ("reference unsplitting"); the running
// bounds and counts follow the decision.
int unsplit_side(const Aabb& ref, Aabb& left, Aabb& right, int& nl, int& nr) {
  Aabb lu = left, ru = right;
  lu.expand(ref);
  ru.expand(ref);
  const Real al = left.surface_area(), ar = right.surface_area();
  const Real c_split = al * nl + ar * nr;
  const Real c_left = lu.surface_area() * nl + ar * (nr - 1);
  const Real c_right = al * (nl - 1) + ru.surface_area() * nr;
  if (c_left < c_split && c_left <= c_right) {
    left = lu;
    --nr;
    return 0;
  }
  if (c_right < c_split) {
    right = ru;
    --nl;
    return 1;
  }
  return -1;
}

// Distributes the range's references over the plane of `sp` into two new lists, chopping the
// straddling ones that do not pay to keep whole; false (nothing changed) if a side is empty.
bool split_spatially(const SpatialContext& ctx, const Task& t, const SpatialSplit& sp,
                     ItemLists& lists, Split& out) {
  const Items& items = *t.items;
  const int axis = sp.axis;
  const Real plane = sp.plane;
  auto left = std::make_unique<Items>(), right = std::make_unique<Items>();
  left->reserve(sp.left_count);
  right->reserve(sp.right_count);
  Aabb lb = sp.left, rb = sp.right;
  int nl = sp.left_count, nr = sp.right_count;
  for (int i = t.begin; i < t.end; ++i) {
    const Item& it = items[i];
    if (it.box.hi[axis] <= plane) {
      left->push_back(it);
      continue;
    }
    if (it.box.lo[axis] >= plane) {
      right->push_back(it);
      continue;
    }
    const int side = unsplit_side(it.box, lb, rb, nl, nr);
    if (side >= 0) {
      (side == 0 ? left : right)->push_back(it);
      continue;
    }
    const Polygon part = triangle_in_box((*ctx.input)[it.index], it.box);
    const Polygon below = clip_halfspace(part, axis, double(plane), true);
    const Polygon above = clip_halfspace(part, axis, double(plane), false);
    if (below.n < 3 || above.n < 3) {  // the plane misses the part (or it has no area)
      const bool to_left = below.n >= 3 || (above.n < 3 && it.centroid[axis] < plane);
      (to_left ? left : right)->push_back(it);
      continue;
    }
    Aabb lo = part_box(below, it.box, ctx.margin), hi = part_box(above, it.box, ctx.margin);
    lo.hi[axis] = plane;  // the two boxes meet exactly on the plane
    hi.lo[axis] = plane;
    left->push_back({lo, lo.center(), it.index});
    right->push_back({hi, hi.center(), it.index});
  }
  if (left->empty() || right->empty()) return false;
  const int ln = static_cast<int>(left->size()), rn = static_cast<int>(right->size());
  out.left = range_task(*left, 0, ln, -1, 0, t.depth + 1);
  out.right = range_task(*right, 0, rn, -1, 1, t.depth + 1);
  out.left.items = left.get();
  out.right.items = right.get();
  lists.push_back(std::move(left));
  lists.push_back(std::move(right));
  share_budget(t.budget - (ln + rn - (t.end - t.begin)), out.left, out.right);
  return true;
}

// The boxes of the sides of the plane after bin `last_left`, merged from the occupied bins in
// the order the sweeps merge them (the left side upwards, the right side downwards), so the same
// boxes as the sweeps' running ones to the bit.
void best_boxes(const BinBox* bins, unsigned occupied, int last_left, Aabb& left, Aabb& right) {
  const unsigned left_bins = (2u << last_left) - 1u;
  BinBox l, r;
  for (unsigned m = occupied & left_bins; m != 0; m &= m - 1) l.expand(bins[lowest_bit(m)]);
  for (unsigned m = occupied & ~left_bins; m != 0;) {
    const int k = highest_bit(m);
    m &= ~(1u << k);
    r.expand(bins[k]);
  }
  left = l.aabb();
  right = r.aabb();
}

// Best binned split of the task's range: true with the two halves, false for "make a leaf".
// One pass bins every item on all three axes (bin boxes are min/max, so exact in any order);
// the chosen bins' boxes are the children's boxes, and the partition bounds their centroids.
bool split_range(const SpatialContext& ctx, const Task& t, ItemLists& lists, Split& out) {
  std::vector<Item>& items = *t.items;
  const int b = t.begin, e = t.end;
  const int count = e - b;
  const Aabb& cb = t.centroids;
  const Real parent_area = t.box.surface_area();
  const Real leaf_cost = kSahTriangleCost * triangle_term(ctx, count) * parent_area;
  Real best = leaf_cost;
  int best_axis = -1, best_bin = -1;
  const Vec3 ext = cb.extent();
  BinBox bins[3][kBins];
  int counts[3][kBins] = {};
  unsigned occupied_on[3] = {};  // bit k: bin k holds an item
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
      occupied_on[axis] |= 1u << k;
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(ext[axis] > Real(0))) continue;
    // The sweeps visit occupied bins only: an empty bin adds nothing to a running box or count,
    // and a candidate plane after one repeats the previous candidate's cost, which never wins
    // (strict <). Most nodes are small, so most of their 16 bins are empty.
    const unsigned occupied = occupied_on[axis];
    // [k]: the right side's cost term, count times area of bins k.. (read only at occupied k;
    // the same operations as in the cost below, so the same bits).
    Real right_cost[kBins];
    BinBox acc;
    int cnt = 0;
    for (unsigned m = occupied & ~1u; m != 0;) {
      const int k = highest_bit(m);
      m &= ~(1u << k);
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
      right_cost[k] = triangle_term(ctx, cnt) * acc.surface_area();
    }
    acc = BinBox();
    cnt = 0;
    for (unsigned m = occupied; m != 0;) {
      const int k = lowest_bit(m);
      m &= m - 1;
      if (m == 0) break;  // no occupied bin right of k
      const int next = lowest_bit(m);
      acc.expand(bins[axis][k]);
      cnt += counts[axis][k];
      const Real c =
          kSahTraversalCost * parent_area +
          kSahTriangleCost * (triangle_term(ctx, cnt) * acc.surface_area() + right_cost[next]);
      // Kept without a branch (whether a candidate improves is hard to predict); the winner's
      // boxes are merged again below.
      const bool better = c < best;
      best = better ? c : best;
      best_axis = better ? axis : best_axis;
      best_bin = better ? k : best_bin;
    }
  }
  Aabb best_left, best_right;
  if (best_axis >= 0)
    best_boxes(bins[best_axis], occupied_on[best_axis], best_bin, best_left, best_right);
  if (spatial_worth_trying(ctx, t, best_axis, best_left, best_right)) {
    const SpatialSplit sp = find_spatial_split(ctx, t, best);
    if (sp.axis >= 0 && split_spatially(ctx, t, sp, lists, out)) return true;
  }
  int mid;
  Aabb lc, rc;
  if (best_axis < 0 || t.depth >= kMaxDepth) {
    if (count <= kMaxLeafSize) return false;
    mid = median_split(items, t);
    out.left = range_task(items, b, mid, -1, 0, t.depth + 1);
    out.right = range_task(items, mid, e, -1, 1, t.depth + 1);
    out.left.items = out.right.items = t.items;
    share_budget(t.budget, out.left, out.right);
    return true;
  }
  mid = partition_by_bin(items, b, e, best_axis, cb.lo[best_axis], scale[best_axis], best_bin, lc,
                         rc);
  out.left = {b, mid, -1, 0, t.depth + 1, best_left, lc, t.items, 0};
  out.right = {mid, e, -1, 1, t.depth + 1, best_right, rc, t.items, 0};
  share_budget(t.budget, out.left, out.right);
  return true;
}

// One subtree built on its own (possibly by another thread): nodes and leaf triangle ids with
// local indices, placed into the whole tree afterwards (place_fragment).
struct Fragment {
  std::vector<BvhNode> nodes;  // the root's box is in the parent's slot
  std::vector<int> prim;
  std::uint32_t root = 0;       // reference for the parent's slot (local node index or local leaf)
  std::int64_t references = 0;  // items in its leaves
};

// The leaves' triangles in leaf order, zero-area ones as points, written to `tris`. One loop of
// nothing else: the reads are scattered over the input, and fetching ahead keeps many in flight.
void gather_leaf_triangles(TriangleSpan input, const std::vector<int>& prim, Triangle* tris) {
  constexpr std::size_t kAhead = 16;  // triangles fetched ahead of their use
  const std::size_t n = prim.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) __builtin_prefetch(&input[prim[i + kAhead]]);
    tris[i] = point_if_zero_area(input[prim[i]]);
  }
}

// The serial top-down build of items[task.begin, task.end), depth first (the left child is
// processed next, so it lands next to its parent).
void build_fragment(const SpatialContext& ctx, const Task& top, Fragment& f) {
  // A leaf stores each triangle once, even when several of its split parts landed here.
  auto emit_leaf = [&](const Task& t) {
    const auto first = static_cast<std::uint32_t>(f.prim.size());
    f.references += t.end - t.begin;
    for (int i = t.begin; i < t.end; ++i) {
      const int id = (*t.items)[i].index;
      if (std::any_of(f.prim.begin() + first, f.prim.end(), [id](int p) { return p == id; }))
        continue;
      f.prim.push_back(id);
    }
    return make_leaf(first, static_cast<std::uint32_t>(f.prim.size() - first));
  };
  auto set_ref = [&](const Task& t, std::uint32_t ref) {
    if (t.node < 0)
      f.root = ref;
    else
      f.nodes[t.node].set_child(t.slot, t.box, ref);
  };
  f.nodes.reserve(top.end - top.begin);  // at most one node per item: no regrowth
  f.prim.reserve(top.end - top.begin);
  std::vector<Task> stack{top};
  ItemLists lists;
  Split sp;
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    if (t.end - t.begin <= 1 || !split_range(ctx, t, lists, sp)) {
      set_ref(t, emit_leaf(t));
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

// Where a fragment goes in the whole tree: its first node and its first leaf triangle.
struct Placement {
  std::uint32_t node_base = 0;
  std::uint32_t tri_base = 0;
};

// A fragment's local reference (node or leaf) as a reference in the whole tree.
std::uint32_t global_ref(std::uint32_t ref, const Placement& at) {
  if (ref == kEmptyLeaf) return ref;
  return is_leaf(ref) ? make_leaf(leaf_first(ref) + at.tri_base, leaf_count(ref))
                      : ref + at.node_base;
}

// Writes a fragment into its place in `out`, whose arrays already have their final sizes: nodes
// relinked and padded, triangle ids, and the triangles gathered from the input straight into
// out.tris (no copy of the tree follows). Fragments occupy disjoint places, so threads may place
// different ones at once.
void place_fragment(const Fragment& f, const Placement& at, TriangleSpan input, HostBvh& out) {
  // Copied whole, then relinked in place: a node copied member by member into a local would
  // carry stack bytes in its padding, and the tree's bytes (its fingerprint) would vary.
  BvhNode* nodes = out.nodes.data() + at.node_base;
  for (std::size_t k = 0; k < f.nodes.size(); ++k) {
    nodes[k] = f.nodes[k];
    for (std::uint32_t& c : nodes[k].child) c = global_ref(c, at);
    pad_child_boxes(nodes[k]);
  }
  std::copy(f.prim.begin(), f.prim.end(), out.prim.begin() + at.tri_base);
  gather_leaf_triangles(input, f.prim, out.tris.data() + at.tri_base);
}

// Each fragment's place, in order after the `top_nodes` nodes already in the tree; sizes the
// tree's arrays for them all (once: nothing grows or moves afterwards).
std::vector<Placement> place_all(const std::vector<const Fragment*>& fragments,
                                 std::size_t top_nodes, HostBvh& out) {
  std::vector<Placement> at(fragments.size());
  Placement next{static_cast<std::uint32_t>(top_nodes), 0};
  for (std::size_t i = 0; i < fragments.size(); ++i) {
    at[i] = next;
    next.node_base += static_cast<std::uint32_t>(fragments[i]->nodes.size());
    next.tri_base += static_cast<std::uint32_t>(fragments[i]->prim.size());
    out.references += static_cast<int>(fragments[i]->references);
  }
  out.nodes.resize(next.node_base);
  out.prim.resize(next.tri_base);
  out.tris.resize(next.tri_base);
  return at;
}

// One item per triangle, or per pre-split part of a sliver when splitting pays (presplit.hpp)
// and no spatial splits will; `root` gets the items' bounds (range_task's, from the loop that
// makes them where that is the last: one pass fewer over the items).
std::vector<Item> make_items(TriangleSpan input, double split_budget, bool spatial, Task& root) {
  const int n = static_cast<int>(input.size());
  std::vector<Item> items;
  items.reserve(n);  // each written once (a sized vector would first fill every item's box)
  Aabb bounds, centroids;
  for (int i = 0; i < n; ++i) {
    Aabb b;
    b.expand(input[i].a);
    b.expand(input[i].b);
    b.expand(input[i].c);
    const Vec3 c = (input[i].a + input[i].b + input[i].c) * (Real(1) / Real(3));
    items.push_back({b, c, i});
    bounds.expand(b);
    centroids.expand(c);
  }
  root = {0, n, -1, 0, 0, bounds, centroids, nullptr, 0};
  if (spatial) return items;
  const std::vector<SplitReference> refs = presplit_triangles(input, bounds, split_budget);
  if (refs.empty()) return items;
  items.resize(refs.size());
  for (std::size_t i = 0; i < refs.size(); ++i)
    items[i] = {refs[i].box, refs[i].centroid, refs[i].prim};
  root = range_task(items, 0, static_cast<int>(items.size()), -1, 0, 0);
  return items;
}

// Part of the tree's top, split depth first: its nodes with ids local to it in the serial
// depth-first (pre-)order, and the ranges left unsplit in that order, each with the number of
// the part's nodes that precede it. A range's `node` is its parent's local id, or -1 where its
// parent is outside the part.
struct TopPart {
  std::vector<BvhNode> nodes;
  std::vector<Task> pending;
  std::vector<std::size_t> nodes_before;
  ItemLists lists;  // the spatial splits' item lists, alive until the build ends
};

// Splits the ranges on `stack` (the next on top) and their halves while they hold more than
// `largest` items and a split pays; the part's root slot (node -1) is linked by the caller.
void split_down(const SpatialContext& ctx, std::vector<Task> stack, int largest, TopPart& part) {
  Split sp;
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    if (t.end - t.begin <= largest || !split_range(ctx, t, part.lists, sp)) {
      part.pending.push_back(t);
      part.nodes_before.push_back(part.nodes.size());
      continue;
    }
    const int id = static_cast<int>(part.nodes.size());
    part.nodes.emplace_back();
    if (t.node >= 0) part.nodes[t.node].set_child(t.slot, t.box, static_cast<std::uint32_t>(id));
    sp.left.node = sp.right.node = id;
    stack.push_back(sp.right);
    stack.push_back(sp.left);
  }
}

// The upper part's nodes with each lower part's nodes (parts[i] split upper.pending[i]) inserted
// where the serial depth-first order puts them, appended to out.nodes (which holds nothing yet)
// with global ids; returns the lower parts' unsplit ranges, in order, with global parent ids.
std::vector<Task> join_top_parts(const TopPart& upper, const std::vector<TopPart>& parts,
                                 HostBvh& out) {
  std::vector<std::uint32_t> upper_id(upper.nodes.size()), base(parts.size());
  std::uint32_t next = 0;
  std::size_t u = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    while (u < upper.nodes_before[i]) upper_id[u++] = next++;
    base[i] = next;
    next += static_cast<std::uint32_t>(parts[i].nodes.size());
  }
  while (u < upper.nodes.size()) upper_id[u++] = next++;
  // Internal children are local ids; the slots of pending ranges are overwritten below.
  out.nodes.resize(next);
  for (std::size_t k = 0; k < upper.nodes.size(); ++k) {
    BvhNode& nd = out.nodes[upper_id[k]];
    nd = upper.nodes[k];
    for (std::uint32_t& c : nd.child) c = upper_id[c];
  }
  std::vector<Task> fragments;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const Task& top = upper.pending[i];
    const std::uint32_t parent = upper_id[top.node];
    for (std::size_t k = 0; k < parts[i].nodes.size(); ++k) {
      BvhNode& nd = out.nodes[base[i] + k];
      nd = parts[i].nodes[k];
      for (std::uint32_t& c : nd.child) c += base[i];
    }
    if (!parts[i].nodes.empty()) out.nodes[parent].set_child(top.slot, top.box, base[i]);
    for (Task f : parts[i].pending) {
      if (f.node < 0) {
        f.node = static_cast<int>(parent);
        f.slot = top.slot;
      } else {
        f.node += static_cast<int>(base[i]);
      }
      fragments.push_back(f);
    }
  }
  return fragments;
}

// The tasks' indices, largest range first (ties in order): handed out one at a time in this
// order, the last ones are the smallest, so no thread waits long at the end for another's big
// one (the tree does not depend on this order).
std::vector<int> largest_first(const std::vector<Task>& tasks) {
  std::vector<int> order(tasks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return tasks[x].end - tasks[x].begin > tasks[y].end - tasks[y].begin;
  });
  return order;
}

// Runs work(i) for each of the host space's threads at once. On threads of their own when they
// can have a CPU each: an OpenMP worker spin-waits for milliseconds after a parallel region
// before it sleeps (libgomp's default), ~7 ms of CPU time per build at two threads, while a
// plain thread simply ends (results/bvh/README.md, sahbuild3 and sahbuild5). Where the caller
// is pinned to fewer CPUs (OMP_PROC_BIND, an MPI rank bound to a core), threads started here
// would share them, so the host space's own threads run it.
template <class Work>
void run_build_threads(const Work& work) {
  const auto threads = static_cast<std::size_t>(Kokkos::DefaultHostExecutionSpace().concurrency());
  if (threads <= cpus_for_new_threads()) {
    on_threads(threads, work);
    return;
  }
  Kokkos::parallel_for(
      "rtmini::bvh::build_sah::parts",
      Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>(std::size_t(0), threads), work);
}

// Splits each part (parts[i] from tops[i]) down to ranges of at most fragment_max items and
// builds those ranges' fragments (built[i][j] from parts[i].pending[j]), in one parallel region:
// a thread splits the next part, largest first, while any is left, then builds the fragments of
// the parts split so far, so no thread waits at a barrier between the two steps (a thread that
// finds none ready while another still splits yields). What is built does not depend on who
// builds it or when.
void build_parts(const SpatialContext& ctx, const std::vector<Task>& tops, int fragment_max,
                 std::vector<TopPart>& parts, std::vector<std::vector<Fragment>>& built) {
  const std::vector<int> order = largest_first(tops);
  const int count = static_cast<int>(tops.size());
  std::atomic<int> next_part{0};
  std::mutex ready_mutex;
  std::vector<std::pair<int, int>> ready;  // (part, range), the largest range last
  int parts_done = 0;                      // under ready_mutex
  const auto split_part = [&](const int i) {
    Task t = tops[i];
    t.node = -1;  // the part's root reference goes to the parent slot in join_top_parts
    split_down(ctx, {t}, fragment_max, parts[i]);
    built[i].resize(parts[i].pending.size());
    const std::vector<int> by_size = largest_first(parts[i].pending);
    const std::lock_guard<std::mutex> lock(ready_mutex);
    for (auto j = by_size.rbegin(); j != by_size.rend(); ++j) ready.push_back({i, *j});
    ++parts_done;
  };
  const auto work = [&](const std::size_t) {
    while (true) {
      if (next_part.load() < count) {
        const int k = next_part.fetch_add(1);
        if (k < count) split_part(order[k]);
        continue;
      }
      std::pair<int, int> job{-1, -1};
      bool finished = false;
      {
        const std::lock_guard<std::mutex> lock(ready_mutex);
        if (!ready.empty()) {
          job = ready.back();
          ready.pop_back();
        }
        finished = job.first < 0 && parts_done == count;
      }
      if (finished) return;
      if (job.first < 0) {
        std::this_thread::yield();
        continue;
      }
      Task t = parts[job.first].pending[job.second];
      t.node = -1;  // the fragment's root reference goes to the parent slot (build_tree)
      build_fragment(ctx, t, built[job.first][job.second]);
    }
  };
  run_build_threads(work);
}

// place_fragment for every fragment, the threads taking the next one in turn (the places are
// fixed, so the tree does not depend on who writes what).
void place_fragments(const std::vector<const Fragment*>& fragments,
                     const std::vector<Placement>& at, TriangleSpan input, HostBvh& out) {
  std::atomic<std::size_t> next{0};
  run_build_threads([&](const std::size_t) {
    for (std::size_t f = next.fetch_add(1); f < fragments.size(); f = next.fetch_add(1))
      place_fragment(*fragments[f], at[f], input, out);
  });
}

// The tree over all items (sets out.bounds) with padded child boxes and the leaves' triangles;
// `root` is the range of all items with its bounds. With spatial splits, up to `budget`
// references more than items.
void build_tree(Items& items, Task root, TriangleSpan input, bool spatial, double budget,
                SahLeafCost leaf_cost, HostBvh& out) {
  const int n = static_cast<int>(items.size());
  root.items = &items;
  out.bounds = root.box;
  if (n == 0) return;
  SpatialContext ctx;
  if (leaf_cost == SahLeafCost::kBlocksOfFour && !spatial && items.size() == input.size())
    ctx.leaf_block = kLeafBlock;
  if (spatial) {
    const Vec3 e = root.box.extent();
    ctx.input = &input;
    ctx.min_overlap = Real(kSpatialAlpha) * root.box.surface_area();
    ctx.margin = kClipMargin * double(std::max(e.x, std::max(e.y, e.z)));
    root.budget = budget;
  }
  // A binary tree over n items, one or more per leaf, has at most n nodes with the root (more
  // only where spatial splits add references). Reserving them all costs address space only,
  // while growing the vector would copy the top's nodes when the fragments' are added.
  out.nodes.reserve(n + 1);

  // The root is always an internal node with two slots.
  ItemLists lists;
  Split sp;
  if (n == 1 || !split_range(ctx, root, lists, sp)) {
    out.nodes.emplace_back();
    Fragment leaf;
    root.depth = kMaxDepth;
    build_fragment(ctx, root, leaf);
    const Placement at = place_all({&leaf}, out.nodes.size(), out)[0];
    place_fragment(leaf, at, input, out);
    out.nodes[0].set_child(0, out.bounds, global_ref(leaf.root, at));
    out.nodes[0].set_child(1, Aabb(), kEmptyLeaf);
    pad_child_boxes(out.nodes[0]);
    return;
  }
  // The top levels, down to ranges of at most kFragmentShare of the input: those subtrees
  // (fragments) are independent and are built in parallel. The fragment cut depends on n only
  // (fragments are appended after the top nodes), and the top's nodes and the fragments keep
  // the serial depth-first order however the top was split up, so the tree is the same for any
  // thread count. The upper levels are split serially, the parts below them in parallel.
  const int fragment_max = std::max(kMinFragment, n / kFragmentShare);
  const int threads = Kokkos::DefaultHostExecutionSpace().concurrency();
  TopPart upper;
  upper.nodes.emplace_back();  // the root
  sp.left.node = sp.right.node = 0;
  split_down(ctx, {sp.right, sp.left}, std::max(fragment_max, n / (kPartsPerThread * threads)),
             upper);
  std::vector<TopPart> parts(upper.pending.size());
  std::vector<std::vector<Fragment>> built(parts.size());
  build_parts(ctx, upper.pending, fragment_max, parts, built);
  const std::vector<Task> ranges = join_top_parts(upper, parts, out);
  const std::size_t top_nodes = out.nodes.size();
  std::vector<const Fragment*> fragments;  // in the order of `ranges`
  for (const std::vector<Fragment>& part : built)
    for (const Fragment& b : part) fragments.push_back(&b);
  const std::vector<Placement> at = place_all(fragments, top_nodes, out);
  for (std::size_t f = 0; f < fragments.size(); ++f)
    out.nodes[ranges[f].node].set_child(ranges[f].slot, ranges[f].box,
                                        global_ref(fragments[f]->root, at[f]));
  for (std::size_t i = 0; i < top_nodes; ++i) pad_child_boxes(out.nodes[i]);
  place_fragments(fragments, at, input, out);
}

}  // namespace

// auto is object splits (with pre-splitting where that pays): measured on the bundled meshes and
// the sliver fan (results/bvh/slivers.md), spatial splits cost 10-60x the build time for at most
// ~10 % fewer triangle tests, and on the fan they cut fewer tests per reference than pre-splitting.
bool uses_spatial_splits(TriangleSpan input, SpatialSplits s) {
  (void)input;
  return s == SpatialSplits::kOn;
}

HostBvh build_sah_host(TriangleSpan input, double split_budget, SpatialSplits spatial_splits,
                       SahLeafCost leaf_cost) {
  HostBvh out;
  const bool spatial = uses_spatial_splits(input, spatial_splits);
  Task root{};
  Items items = make_items(input, split_budget, spatial, root);
  const double per_triangle =
      is_auto_split_budget(split_budget) ? kSpatialSplitAutoBudget : split_budget;
  const double budget = per_triangle * double(input.size());
  build_tree(items, root, input, spatial, budget, leaf_cost, out);
  out.spatial_splits = spatial;
  return out;
}

}  // namespace rtmini::bvh
