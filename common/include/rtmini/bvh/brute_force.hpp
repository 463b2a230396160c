#pragma once
// Reference "acceleration structure" that tests every triangle, behind the same
// closest_hit / any_hit interface as the BVH; used by tests and to count how
// many ray-triangle tests the BVH saves.
#include "rtmini/geometry/triangle.hpp"

namespace rtmini::bvh {

template <class MemorySpace>
struct BruteForce {
  Kokkos::View<const Triangle*, MemorySpace> tris;  // original order
};

template <class MemorySpace>
KOKKOS_INLINE_FUNCTION Hit closest_hit(const BruteForce<MemorySpace>& bf, const Ray& ray) {
  Hit hit;
  hit.t = ray.tmax;
  const WatertightRay wr(ray.org, ray.dir);
  const int n = static_cast<int>(bf.tris.extent(0));
  for (int i = 0; i < n; ++i) {
    Real t, u, v;
    const Triangle& tri = bf.tris(i);
    if (is_zero_area(tri.a, tri.b, tri.c)) continue;
    // Ascending ids and a strict "<" on t give the same tie-break as the BVH.
    if (intersect_triangle(wr, tri.a, tri.b, tri.c, ray.tmin, hit.t, t, u, v) &&
        (t < hit.t || hit.prim < 0)) {
      hit.t = t;
      hit.u = u;
      hit.v = v;
      hit.prim = i;
    }
  }
  return hit;
}

template <class MemorySpace>
KOKKOS_INLINE_FUNCTION bool any_hit(const BruteForce<MemorySpace>& bf, const Ray& ray) {
  const WatertightRay wr(ray.org, ray.dir);
  const int n = static_cast<int>(bf.tris.extent(0));
  for (int i = 0; i < n; ++i) {
    Real t, u, v;
    const Triangle& tri = bf.tris(i);
    if (is_zero_area(tri.a, tri.b, tri.c)) continue;
    if (intersect_triangle(wr, tri.a, tri.b, tri.c, ray.tmin, ray.tmax, t, u, v)) return true;
  }
  return false;
}

}  // namespace rtmini::bvh
