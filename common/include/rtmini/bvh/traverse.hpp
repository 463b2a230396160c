#pragma once
// Iterative BVH traversal with a short fixed stack (no recursion, GPU-safe):
// closest hit with a deterministic tie-break (equal t -> lower triangle id, so
// results match the brute-force reference exactly) and any hit for shadow/AO.
#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// Statistics a caller may ask for (ray-primitive tests per ray against brute force).
struct TraversalStats {
  std::uint32_t nodes = 0;
  std::uint32_t tests = 0;
};

namespace detail {

template <class BvhT, bool kAnyHit, bool kStats>
KOKKOS_INLINE_FUNCTION bool traverse(const BvhT& bvh, const Ray& ray, Hit& hit, TraversalStats* stats) {
  if (bvh.num_prims == 0) return false;
  const WatertightRay wr(ray.org, ray.dir);
  const RaySlab rs(ray.org, ray.dir);
  Real tmax = ray.tmax;
  std::uint32_t stack[kStackSize];
  int sp = 0;
  std::uint32_t node = 0;
  bool found = false;
  while (true) {
    const BvhNode& nd = bvh.nodes(node);
    if (kStats) ++stats->nodes;
    Real t0, t1;
    bool h0 = slab_test(rs, Vec3(nd.lo_x[0], nd.lo_y[0], nd.lo_z[0]),
                        Vec3(nd.hi_x[0], nd.hi_y[0], nd.hi_z[0]), ray.tmin, tmax, t0);
    bool h1 = slab_test(rs, Vec3(nd.lo_x[1], nd.lo_y[1], nd.lo_z[1]),
                        Vec3(nd.hi_x[1], nd.hi_y[1], nd.hi_z[1]), ray.tmin, tmax, t1);
    const std::uint32_t c[2] = {nd.child[0], nd.child[1]};
    bool hk[2] = {h0, h1};
    for (int k = 0; k < 2; ++k) {
      if (!hk[k] || !is_leaf(c[k])) continue;
      hk[k] = false;
      if (c[k] == kEmptyLeaf) continue;
      const std::uint32_t first = leaf_first(c[k]), end = first + leaf_count(c[k]);
      for (std::uint32_t i = first; i < end; ++i) {
        const Triangle& tri = bvh.tris(i);
        if (kStats) ++stats->tests;
        Real t, u, v;
        if (!intersect_triangle(wr, tri.a, tri.b, tri.c, ray.tmin, tmax, t, u, v)) continue;
        const int id = bvh.prim(i);
        if (kAnyHit) {
          hit.t = t; hit.u = u; hit.v = v; hit.prim = id;
          return true;
        }
        if (t < tmax || id < hit.prim || !found) {
          tmax = t;
          hit.t = t; hit.u = u; hit.v = v; hit.prim = id;
          found = true;
        }
      }
    }
    h0 = hk[0];
    h1 = hk[1];
    if (h0 && h1) {
      const bool first0 = t0 <= t1;
      stack[sp++] = first0 ? c[1] : c[0];
      node = first0 ? c[0] : c[1];
    } else if (h0) {
      node = c[0];
    } else if (h1) {
      node = c[1];
    } else {
      if (sp == 0) break;
      node = stack[--sp];
    }
  }
  return found;
}

}  // namespace detail

// Closest hit in [ray.tmin, ray.tmax]; hit.prim = -1 when nothing is hit.
template <class BvhT>
KOKKOS_INLINE_FUNCTION Hit closest_hit(const BvhT& bvh, const Ray& ray) {
  Hit hit;
  hit.t = ray.tmax;
  detail::traverse<BvhT, false, false>(bvh, ray, hit, nullptr);
  return hit;
}

template <class BvhT>
KOKKOS_INLINE_FUNCTION Hit closest_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  Hit hit;
  hit.t = ray.tmax;
  detail::traverse<BvhT, false, true>(bvh, ray, hit, &stats);
  return hit;
}

// True if anything blocks the segment [ray.tmin, ray.tmax].
template <class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray) {
  Hit hit;
  return detail::traverse<BvhT, true, false>(bvh, ray, hit, nullptr);
}

template <class BvhT>
KOKKOS_INLINE_FUNCTION bool any_hit(const BvhT& bvh, const Ray& ray, TraversalStats& stats) {
  Hit hit;
  return detail::traverse<BvhT, true, true>(bvh, ray, hit, &stats);
}

}  // namespace rtmini::bvh
