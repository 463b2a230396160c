#include "rtmini/bvh/presplit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "rtmini/bvh/clip.hpp"

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

struct Candidate {
  double area;  // the box's surface area: the largest boxes are split first
  int prim;
  std::size_t slot;
  bool operator<(const Candidate& o) const {  // priority order, deterministic on ties
    if (area != o.area) return area < o.area;
    if (prim != o.prim) return prim > o.prim;
    return slot > o.slot;
  }
};

class Splitter {
 public:
  Splitter(const std::vector<Triangle>& tris, const Aabb& bounds) : tris_(tris), bounds_(bounds) {
    const Vec3 e = bounds.extent();
    const double largest = double(std::max(e.x, std::max(e.y, e.z)));
    min_extent_ = kMinPartExtent * largest;
    margin_ = kClipMargin * largest;
  }

  // Queues the reference at `slot` if it is a sliver worth splitting.
  void consider(const std::vector<SplitReference>& refs, std::size_t slot, double part_area) {
    const Aabb& b = refs[slot].box;
    const Vec3 e = b.extent();
    const double sa = double(b.surface_area());
    if (part_area > 0 && sa > kSliverRatio * 2 * part_area &&
        double(std::max(e.x, std::max(e.y, e.z))) >= min_extent_)
      queue_.push({sa, refs[slot].prim, slot});
  }

  bool empty() const { return queue_.empty(); }

  // Splits the largest queued part in two on a grid plane across its longest axis; returns the
  // surface area it removed (0 when it could not be split).
  double split_next(std::vector<SplitReference>& refs) {
    const Candidate c = queue_.top();
    queue_.pop();
    const SplitReference r = refs[c.slot];
    const int axis = max_dimension(r.box.extent());
    Real plane;
    if (!grid_plane(double(bounds_.lo[axis]), double(bounds_.extent()[axis]), r.box.lo[axis],
                    r.box.hi[axis], plane))
      return 0;
    const Polygon part = triangle_in_box(tris_[r.prim], r.box);
    const Polygon below = clip_halfspace(part, axis, double(plane), true);
    const Polygon above = clip_halfspace(part, axis, double(plane), false);
    if (below.n < 3 || above.n < 3) return 0;  // the plane misses the part itself
    Aabb lo = part_box(below, r.box, margin_), hi = part_box(above, r.box, margin_);
    lo.hi[axis] = plane;  // the two boxes meet exactly on the plane
    hi.lo[axis] = plane;
    refs[c.slot] = {lo, lo.center(), r.prim};
    refs.push_back({hi, hi.center(), r.prim});
    consider(refs, c.slot, polygon_area(below));
    consider(refs, refs.size() - 1, polygon_area(above));
    return c.area - double(lo.surface_area()) - double(hi.surface_area());
  }

 private:
  const std::vector<Triangle>& tris_;
  Aabb bounds_;
  double min_extent_, margin_;
  std::priority_queue<Candidate> queue_;
};

}  // namespace

std::vector<SplitReference> presplit_triangles(const std::vector<Triangle>& tris,
                                               const Aabb& bounds, double budget) {
  const std::size_t n = tris.size();
  if (n == 0 || !(budget > 0) || bounds.empty()) return {};
  Splitter splitter(tris, bounds);
  std::vector<SplitReference> refs(n);
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Triangle& t = tris[i];
    Aabb b;
    b.expand(t.a);
    b.expand(t.b);
    b.expand(t.c);
    refs[i] = {b, (t.a + t.b + t.c) * (Real(1) / Real(3)), static_cast<int>(i)};
    total += double(b.surface_area());
    if (is_zero_area(t.a, t.b, t.c)) continue;  // stored as a point, never hit
    const Vec3d a = to_double(t.a);
    splitter.consider(refs, i, 0.5 * length(cross(to_double(t.b) - a, to_double(t.c) - a)));
  }
  if (splitter.empty()) return {};
  const std::size_t max_refs = n + static_cast<std::size_t>(budget * double(n));
  refs.reserve(max_refs);
  double removed = 0;
  while (!splitter.empty() && refs.size() < max_refs) removed += splitter.split_next(refs);
  if (!(removed >= kPresplitMinGain * total)) return {};
  return refs;
}

}  // namespace rtmini::bvh
