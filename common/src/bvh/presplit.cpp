#include "rtmini/bvh/presplit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "rtmini/bvh/build_lbvh.hpp"  // triangle_box
#include "rtmini/bvh/clip.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::bvh {

namespace {

// A part is a sliver when its box's surface area exceeds this multiple of twice its own area:
// an axis-aligned right triangle has 2, an equilateral one in general position about 3.5, a
// diagonal sliver of aspect A about A.
constexpr double kSliverRatio = 16;
// Parts smaller than this fraction of the scene's largest extent are not split further.
constexpr double kMinPartExtent = 1.0 / 1024;

double polygon_area(const Polygon& p) {
  Vec3d s(0.0);
  for (int i = 1; i + 1 < p.n; ++i) s = s + cross(p.v[i] - p.v[0], p.v[i + 1] - p.v[0]);
  return 0.5 * length(s);
}

// A split plane inside (lo, hi) on the power-of-two grid of the scene's [origin, origin + size]
// on that axis, as coarse as possible and nearest the middle, so the parts of neighbouring
// triangles share planes the builder can then separate cleanly (Dammertz & Keller 2008).
bool grid_plane(double origin, double size, Real lo, Real hi, Real& plane) {
  const double u0 = (double(lo) - origin) / size, u1 = (double(hi) - origin) / size;
  if (!(u1 > u0)) return false;
  const int coarsest = std::max(0, static_cast<int>(std::floor(-std::log2(u1 - u0))));
  for (int level = coarsest; level < coarsest + 3; ++level) {
    const double cell = std::ldexp(1.0, -level);
    const double u = std::nearbyint(0.5 * (u0 + u1) / cell) * cell;
    plane = Real(origin + u * size);
    if (plane > lo && plane < hi) return true;
  }
  return false;
}

// Parts waiting to be split, largest box first: one bucket per 1/16 octave of box area (the
// area's float bits without their low 19 mantissa bits order like the areas), each in the order
// its parts were queued. Splitting bucket by bucket is the greedy order of a priority queue up
// to that resolution, without its cache misses on millions of parts, and a bucket is a batch
// whose parts can be split in parallel.
class PartQueue {
 public:
  PartQueue() : buckets_(std::size_t(1) << (32 - kDroppedBits)) {}

  void push(std::uint32_t slot, double area) {
    const std::size_t k = key(area);
    buckets_[k].push_back(slot);
    top_ = std::max(top_, k + 1);
  }

  bool empty() {  // (first drops the empty buckets above the largest queued part)
    while (top_ > 0 && buckets_[top_ - 1].empty()) --top_;
    return top_ == 0;
  }

  // Takes up to `count` parts of the largest non-empty bucket (the last queued first).
  void take(std::size_t count, std::vector<std::uint32_t>& out) {
    out.clear();
    if (empty()) return;
    std::vector<std::uint32_t>& b = buckets_[top_ - 1];
    const std::size_t k = std::min(count, b.size());
    out.assign(b.end() - static_cast<std::ptrdiff_t>(k), b.end());
    b.resize(b.size() - k);
  }

 private:
  static constexpr int kDroppedBits = 19;
  static std::size_t key(double area) {
    const float f = static_cast<float>(area);
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits >> kDroppedBits;
  }
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::size_t top_ = 0;
};

// A part cut in two, with the two halves' own areas (to decide whether they are slivers too).
struct Halves {
  SplitReference lo, hi;
  double lo_area = 0, hi_area = 0;
  bool ok = false;
};

// A split part's reference as it was, to undo an auto step that did not pay.
struct Undo {
  std::uint32_t slot;
  SplitReference ref;
};

// Batches smaller than this are split on the calling thread: a parallel region costs more.
constexpr std::size_t kMinParallelBatch = 4096;

class Splitter {
 public:
  Splitter(TriangleSpan tris, const Aabb& bounds) : tris_(tris), bounds_(bounds) {
    const Vec3 e = bounds.extent();
    const double largest = double(std::max(e.x, std::max(e.y, e.z)));
    min_extent_ = kMinPartExtent * largest;
    margin_ = kClipMargin * largest;
  }

  // The surface area of a part's box if the part is a sliver worth splitting, else 0.
  double sliver_box_area(const Aabb& b, double part_area) const {
    const Vec3 e = b.extent();
    const double sa = double(b.surface_area());
    return part_area > 0 && sa > kSliverRatio * 2 * part_area &&
                   double(std::max(e.x, std::max(e.y, e.z))) >= min_extent_
               ? sa
               : 0;
  }

  // Queues the reference at `slot` if it is a sliver worth splitting.
  void consider(const std::vector<SplitReference>& refs, std::size_t slot, double part_area) {
    const double sa = sliver_box_area(refs[slot].box, part_area);
    if (sa > 0) queue_.push(static_cast<std::uint32_t>(slot), sa);
  }

  bool empty() { return queue_.empty(); }

  // Splits the largest queued parts until there are `max_refs` references or none is left to
  // split; returns the surface area removed. Records each split reference in `undo` when given
  // (only those below `keep`: the later ones are new and go with a resize).
  double split_until(std::vector<SplitReference>& refs, std::size_t max_refs,
                     std::vector<Undo>* undo, std::size_t keep) {
    double removed = 0;
    while (refs.size() < max_refs && !queue_.empty()) {
      queue_.take(max_refs - refs.size(), batch_);
      split_batch(refs);
      for (std::size_t i = 0; i < batch_.size(); ++i) {
        const Halves& h = halves_[i];
        if (!h.ok) continue;
        const std::uint32_t slot = batch_[i];
        if (undo && slot < keep) undo->push_back({slot, refs[slot]});
        removed += double(refs[slot].box.surface_area()) - double(h.lo.box.surface_area()) -
                   double(h.hi.box.surface_area());
        refs[slot] = h.lo;
        refs.push_back(h.hi);
        consider(refs, slot, h.lo_area);
        consider(refs, refs.size() - 1, h.hi_area);
      }
    }
    return removed;
  }

 private:
  // Cuts every part of the batch (in parallel when it is large: each cut reads its own part
  // only, and the results are applied in batch order, so the outcome is thread-count free).
  void split_batch(const std::vector<SplitReference>& refs) {
    halves_.resize(batch_.size());
    const auto cut = [&](const std::int64_t i) { halves_[i] = split_part(refs[batch_[i]]); };
    const auto n = static_cast<std::int64_t>(batch_.size());
    if (batch_.size() < kMinParallelBatch) {
      for (std::int64_t i = 0; i < n; ++i) cut(i);
      return;
    }
    Kokkos::parallel_for("rtmini::bvh::presplit::batch",
                         Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>(std::int64_t(0), n),
                         cut);
    Kokkos::DefaultHostExecutionSpace().fence();
  }

  // The part cut in two on a grid plane across its longest axis (not ok when the plane misses
  // the part itself).
  Halves split_part(const SplitReference& r) const {
    Halves h;
    const int axis = max_dimension(r.box.extent());
    Real plane;
    if (!grid_plane(double(bounds_.lo[axis]), double(bounds_.extent()[axis]), r.box.lo[axis],
                    r.box.hi[axis], plane))
      return h;
    const Polygon part = triangle_in_box(tris_[r.prim], r.box);
    const Polygon below = clip_halfspace(part, axis, double(plane), true);
    const Polygon above = clip_halfspace(part, axis, double(plane), false);
    if (below.n < 3 || above.n < 3) return h;
    Aabb lo = part_box(below, r.box, margin_), hi = part_box(above, r.box, margin_);
    lo.hi[axis] = plane;  // the two boxes meet exactly on the plane
    hi.lo[axis] = plane;
    h.lo = {lo, lo.center(), r.prim};
    h.hi = {hi, hi.center(), r.prim};
    h.lo_area = polygon_area(below);
    h.hi_area = polygon_area(above);
    h.ok = true;
    return h;
  }

  TriangleSpan tris_;
  Aabb bounds_;
  double min_extent_, margin_;
  PartQueue queue_;
  std::vector<std::uint32_t> batch_;
  std::vector<Halves> halves_;
};

// Puts back the references an auto step split and drops the ones it added.
void undo_step(std::vector<SplitReference>& refs, const std::vector<Undo>& undo,
               std::size_t size_before) {
  for (auto it = undo.rbegin(); it != undo.rend(); ++it) refs[it->slot] = it->ref;
  refs.resize(size_before);
}

// Auto: doubles the references while each doubling removes kAutoStepMinGain of the summed box
// area left (`area`), up to the ceilings of presplit.hpp.
void grow_auto_budget(Splitter& splitter, std::vector<SplitReference>& refs, std::size_t ceiling,
                      double area) {
  std::vector<Undo> undo;
  while (refs.size() < ceiling && !splitter.empty()) {
    const std::size_t before = refs.size();
    undo.clear();
    const double removed = splitter.split_until(refs, std::min(2 * before, ceiling), &undo, before);
    if (!(removed >= kAutoStepMinGain * area)) {
      undo_step(refs, undo, before);
      return;
    }
    area -= removed;
  }
}

}  // namespace

std::vector<SplitReference> presplit_triangles(TriangleSpan tris, const Aabb& bounds,
                                               double budget) {
  const std::size_t n = tris.size();
  if (n == 0 || budget == 0 || bounds.empty()) return {};
  const bool auto_budget = is_auto_split_budget(budget);
  const std::size_t ceiling = std::min(
      kAutoMaxReferences, static_cast<std::size_t>(kAutoMaxReferencesPerTriangle * double(n)));
  // Auto starts as a budget of 1, within the ceiling.
  const std::size_t max_refs = auto_budget ? std::min(2 * n, std::max(n, ceiling))
                                           : n + static_cast<std::size_t>(budget * double(n));
  if (max_refs > std::numeric_limits<std::uint32_t>::max()) return {};  // slots are 32-bit
  Splitter splitter(tris, bounds);
  // The slivers (triangle, area) and the summed box areas, before any reference is made.
  std::vector<std::pair<std::size_t, double>> slivers;
  double total = 0, sliver_total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Triangle& t = tris[i];
    const Aabb b = triangle_box(t);
    total += double(b.surface_area());
    if (is_zero_area(t.a, t.b, t.c)) continue;  // stored as a point, never hit
    const Vec3d a = to_double(t.a);
    const double area = 0.5 * length(cross(to_double(t.b) - a, to_double(t.c) - a));
    const double sa = splitter.sliver_box_area(b, area);
    if (sa == 0) continue;
    slivers.push_back({i, area});
    sliver_total += sa;
  }
  // Splitting removes at most the slivers' box area (only they and their parts are ever split,
  // and a triangle's parts end with boxes of area >= 0); when that is short of the gain to keep,
  // no split would be kept, so none is tried (ordinary meshes, e.g. the dragon, whose few slivers
  // were split and the parts dropped). The factor covers the rounding of `removed`.
  if (slivers.empty() || !(sliver_total * (1 + 1e-6) >= kPresplitMinGain * total)) return {};
  std::vector<SplitReference> refs;
  refs.reserve(max_refs);
  for (const Triangle& t : tris)
    refs.push_back(
        {triangle_box(t), (t.a + t.b + t.c) * (Real(1) / Real(3)), static_cast<int>(refs.size())});
  for (const auto& [i, area] : slivers) splitter.consider(refs, i, area);
  const double removed = splitter.split_until(refs, max_refs, nullptr, 0);
  if (!(removed >= kPresplitMinGain * total)) return {};
  if (auto_budget) grow_auto_budget(splitter, refs, ceiling, total - removed);
  return refs;
}

}  // namespace rtmini::bvh
