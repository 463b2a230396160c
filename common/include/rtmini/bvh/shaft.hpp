#pragma once
// Shaft culling (Haines & Wallace 1991, "Shaft culling for efficient ray-traced
// radiosity"): the many shadow rays from one shading point to one area light all
// lie in the convex hull of the point and the light polygon (the shaft). One walk
// of the BVH with the shaft instead of a ray collects the few triangles that can
// block any of them; every shadow ray is then tested against those triangles only,
// with the same ray-triangle test as a traversal. The culling is conservative, so
// the answer of every ray is the one a full traversal gives.
//
// Culling tests, each with a margin far above rounding and far below the origin
// offset of a shadow ray (geometry/offset.hpp: 256 ulps):
//   box: outside the shaft's bounding box, or wholly outside one of its planes
//        (the light plane and the four side planes through the apex);
//   triangle: all three vertices outside one shaft plane, or the whole shaft (apex
//        and light corners) strictly on one side of the triangle's plane (decided in
//        double, exactly enough for the origin offset), which removes the surface the
//        shading point lies on and its convex neighbourhood.
// When more than kShaftTriangles triangles (or kShaftNodes node visits) survive,
// the shaft is abandoned and each ray traverses the BVH as usual.
#include "rtmini/bvh/traverse.hpp"

namespace rtmini::bvh {

inline constexpr int kShaftTriangles = 16;
inline constexpr int kShaftNodes = 96;

struct Shaft {
  Vec3 lo, hi;  // bounding box of apex and corners, widened by the margin
  Vec3 n[5];    // outward plane normals: light plane, then four sides
  Real d[5];    // plane offsets: inside is dot(n, x) <= d + margin
  Vec3 pts[5];  // apex, then the four corners
  Real margin;
};

// The shaft from `apex` towards the quad corner, corner + u, corner + u + v, corner + v,
// holding the segments from the apex to `reach` of the way to each point of the quad
// (shadow rays stop short of the light, so the light's own geometry is no blocker).
// False when it is degenerate (apex in the light's plane): use plain rays then.
KOKKOS_INLINE_FUNCTION bool make_shaft(const Vec3& apex, const Vec3& corner, const Vec3& u,
                                       const Vec3& v, Real reach, Shaft& s) {
  const Vec3 quad[4] = {corner, corner + u, corner + u + v, corner + v};
  s.pts[0] = apex;
  for (int k = 0; k < 4; ++k) s.pts[1 + k] = apex + (quad[k] - apex) * reach;
  Real mag = Real(0);
  s.lo = s.hi = apex;
  for (int k = 0; k < 5; ++k) {
    s.lo = vmin(s.lo, s.pts[k]);
    s.hi = vmax(s.hi, s.pts[k]);
    const Vec3 a = vabs(s.pts[k]);
    mag = compat::kmax(mag, compat::kmax(a.x, compat::kmax(a.y, a.z)));
  }
  mag = compat::kmax(mag, max_component(s.hi - s.lo));
  // ~64 float ulps of the largest coordinate: rounding of the tests below stays far
  // under it, and a shadow ray's origin offset (256 ulps) stays above it.
  s.margin = mag * Real(4e-6) + Real(1e-30);
  const Vec3 pad(s.margin, s.margin, s.margin);
  s.lo = s.lo - pad;
  s.hi = s.hi + pad;
  const Vec3 centre = (apex + s.pts[1] + s.pts[2] + s.pts[3] + s.pts[4]) * Real(0.2);
  Vec3 nl = cross(u, v);
  const Real nl_len = length(nl);
  if (!(nl_len > Real(0))) return false;
  nl = nl / nl_len;
  if (dot(nl, apex - corner) > Real(0)) nl = -nl;
  if (!(math::fabs(dot(nl, apex - corner)) > Real(4) * s.margin)) return false;
  s.n[0] = nl;
  s.d[0] = dot(nl, s.pts[1]);
  for (int k = 0; k < 4; ++k) {
    const Vec3 a = s.pts[1 + k] - apex, b = s.pts[1 + (k + 1) % 4] - apex;
    Vec3 n = cross(a, b);
    const Real len = length(n);
    if (!(len > Real(0))) return false;
    n = n / len;
    if (dot(n, centre - apex) > Real(0)) n = -n;
    s.n[1 + k] = n;
    s.d[1 + k] = dot(n, apex);
  }
  return true;
}

// True when the box may meet the shaft.
KOKKOS_INLINE_FUNCTION bool shaft_meets_box(const Shaft& s, const Vec3& lo, const Vec3& hi) {
  if (lo.x > s.hi.x || lo.y > s.hi.y || lo.z > s.hi.z || hi.x < s.lo.x || hi.y < s.lo.y ||
      hi.z < s.lo.z)
    return false;
  for (int k = 0; k < 5; ++k) {
    const Vec3& n = s.n[k];
    const Vec3 nearest(n.x > Real(0) ? lo.x : hi.x, n.y > Real(0) ? lo.y : hi.y,
                       n.z > Real(0) ? lo.z : hi.z);
    if (dot(n, nearest) > s.d[k] + s.margin) return false;
  }
  return true;
}

// True when the triangle may block a segment inside the shaft.
KOKKOS_INLINE_FUNCTION bool shaft_meets_triangle(const Shaft& s, const Triangle& t) {
  for (int k = 0; k < 5; ++k) {
    const Real lim = s.d[k] + s.margin;
    if (dot(s.n[k], t.a) > lim && dot(s.n[k], t.b) > lim && dot(s.n[k], t.c) > lim) return false;
  }
  // The triangle's plane in double: differences and products of floats are exact
  // there, so the side of a shadow-ray origin a few hundred ulps off the surface is exact.
  const double ax = t.a.x, ay = t.a.y, az = t.a.z;
  const double ux = t.b.x - ax, uy = t.b.y - ay, uz = t.b.z - az;
  const double vx = t.c.x - ax, vy = t.c.y - ay, vz = t.c.z - az;
  const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
  if (nx == 0.0 && ny == 0.0 && nz == 0.0) return true;  // degenerate: leave it to the ray test
  bool above = true, below = true;
  for (int k = 0; k < 5; ++k) {
    const double h = nx * (s.pts[k].x - ax) + ny * (s.pts[k].y - ay) + nz * (s.pts[k].z - az);
    above = above && h > 0.0;
    below = below && h < 0.0;
  }
  return !(above || below);
}

// Triangles (slots of bvh.tris) that may block rays inside a shaft.
struct ShaftBlockers {
  std::uint32_t tri[kShaftTriangles];
  int count = 0;
};

// Collects the shaft's blockers; false when there are too many (trace rays instead).
// `nodes` counts the node visits.
template <class BvhT>
KOKKOS_INLINE_FUNCTION bool collect_shaft_blockers(const BvhT& bvh, const Shaft& s,
                                                   ShaftBlockers& out, std::uint32_t& nodes) {
  out.count = 0;
  if (bvh.num_prims == 0) return true;
  std::uint32_t stack[kStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  int visits = 0;
  while (true) {
    if (++visits > kShaftNodes) return false;
    ++nodes;
    const BvhNode& nd = bvh.nodes(node);
    std::uint32_t next[2];
    int m = 0;
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t c = nd.child[k];
      if (c == kEmptyLeaf) continue;
      if (!shaft_meets_box(s, Vec3(nd.lo_x[k], nd.lo_y[k], nd.lo_z[k]),
                           Vec3(nd.hi_x[k], nd.hi_y[k], nd.hi_z[k])))
        continue;
      if (!is_leaf(c)) {
        next[m++] = c;
        continue;
      }
      const std::uint32_t first = leaf_first(c), end = first + leaf_count(c);
      for (std::uint32_t i = first; i < end; ++i) {
        if (!shaft_meets_triangle(s, bvh.tris(i))) continue;
        if (out.count == kShaftTriangles) return false;
        out.tri[out.count++] = i;
      }
    }
    if (m == 2) {
      if (sp == kStackSize) return false;
      stack[sp++] = next[1];
    }
    if (m > 0) {
      node = next[0];
    } else {
      if (sp == 0) break;
      node = stack[--sp];
    }
  }
  return true;
}

// Any-hit of a ray inside the shaft against its blockers only: the answer of any_hit().
template <class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit_blockers(const BvhT& bvh, const ShaftBlockers& b,
                                             const Ray& ray, std::uint64_t* tests = nullptr) {
  if (b.count == 0) return false;
  const WatertightRay wr(ray.org, ray.dir);
  for (int k = 0; k < b.count; ++k) {
    const Triangle& t = bvh.tris(b.tri[k]);
    if (tests) ++*tests;
    Real th, u, v;
    if (intersect_triangle(wr, t.a, t.b, t.c, ray.tmin, ray.tmax, th, u, v)) return true;
  }
  return false;
}

}  // namespace rtmini::bvh
