#pragma once
// Clipping a triangle to axis-aligned boxes and slabs, in double, for the builders that split
// a triangle's reference into parts (presplit.cpp, the spatial splits of build_sah.cpp). A part's
// box must contain every hit the watertight test can report on that part of the triangle.
#include <algorithm>
#include <cmath>
#include <limits>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// A part's box faces that come from clipped edges (not from the triangle's own vertices) are
// widened by this fraction of the scene's largest extent: the watertight test may report a hit
// a few rounding errors of the ray-to-vertex distance outside the exact triangle, and such a hit
// must still lie inside the box of some part (covers origins up to ~100 scene sizes away in
// float; the builder's 4-ulp padding covers the triangle's own box faces).
inline constexpr double kClipMargin = 1.0 / 16384;

// A triangle clipped by up to nine planes has at most twelve vertices.
struct Polygon {
  Vec3d v[12];
  int n = 0;
};

inline Vec3d to_double(const Vec3& p) { return {double(p.x), double(p.y), double(p.z)}; }

// Sutherland-Hodgman against one axis-aligned half-space (below or above c on `axis`).
inline Polygon clip_halfspace(const Polygon& in, int axis, double c, bool keep_below) {
  Polygon out;
  for (int i = 0; i < in.n; ++i) {
    const Vec3d& p = in.v[i];
    const Vec3d& q = in.v[(i + 1) % in.n];
    const bool p_in = keep_below ? p[axis] <= c : p[axis] >= c;
    const bool q_in = keep_below ? q[axis] <= c : q[axis] >= c;
    if (p_in) out.v[out.n++] = p;
    if (p_in != q_in) {
      Vec3d x = p + (q - p) * ((c - p[axis]) / (q[axis] - p[axis]));
      x[axis] = c;
      out.v[out.n++] = x;
    }
  }
  return out;
}

// The part of a triangle inside a box.
inline Polygon triangle_in_box(const Triangle& t, const Aabb& box) {
  Polygon p;
  p.v[0] = to_double(t.a);
  p.v[1] = to_double(t.b);
  p.v[2] = to_double(t.c);
  p.n = 3;
  for (int axis = 0; axis < 3 && p.n >= 3; ++axis) {
    p = clip_halfspace(p, axis, double(box.lo[axis]), false);
    if (p.n >= 3) p = clip_halfspace(p, axis, double(box.hi[axis]), true);
  }
  return p;
}

inline Real round_down(double x) {
  Real r = Real(x);
  if (double(r) > x) r = std::nextafter(r, -std::numeric_limits<Real>::infinity());
  return r;
}
inline Real round_up(double x) {
  Real r = Real(x);
  if (double(r) < x) r = std::nextafter(r, std::numeric_limits<Real>::infinity());
  return r;
}

// The box of a clipped part, widened by `margin`, within the box of the part it came from.
inline Aabb part_box(const Polygon& p, const Aabb& parent, double margin) {
  Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (int i = 0; i < p.n; ++i) {
    lo = vmin(lo, p.v[i]);
    hi = vmax(hi, p.v[i]);
  }
  Aabb b;
  for (int axis = 0; axis < 3; ++axis) {
    b.lo[axis] = std::max(parent.lo[axis], round_down(lo[axis] - margin));
    b.hi[axis] = std::min(parent.hi[axis], round_up(hi[axis] + margin));
  }
  return b;
}

}  // namespace rtmini::bvh
