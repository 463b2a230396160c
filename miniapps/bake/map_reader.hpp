#pragma once
// Device helpers shared by the Chef's kernels and the convergence test: the mirror direction
// of a viewpoint, and reading the previous iteration's map at a ray hit.
#include <cstdint>

#include "bake_scene.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {

// The side of vertex normal n that a mirror ray for viewpoint direction d leaves from: n for
// one-sided mirrors (the default; mirror_direction folds a viewpoint behind to the front), -n
// for a viewpoint behind a two-sided mirror (`--two-sided`), which then reflects on its back.
KOKKOS_INLINE_FUNCTION Vec3 mirror_normal(const Vec3& d, const Vec3& n, bool two_sided) {
  return two_sided && dot(d, n) > Real(0) ? -n : n;
}

// Mirror ray of viewpoint direction d (camera ray into the vertex) about the vertex normal n.
// A viewpoint behind the surface is shaded as its mirror image in the tangent plane (README:
// continuous at grazing, and every mirror ray leaves on the front side).
KOKKOS_INLINE_FUNCTION Vec3 mirror_direction(const Vec3& d, const Vec3& n) {
  const Real dn = dot(d, n);
  const Vec3 front = dn > Real(0) ? d - n * (Real(2) * dn) : d;
  return normalize(reflect(front, n));
}

// Colour of the previous map seen along `dir` at a hit: the hit triangle's three vertex
// colours, each looked up at `dir` among its nearest viewpoints, mixed barycentrically.
template <class LookupT>
struct MapReader {
  Kokkos::View<int* [3], MemSpace> tri_vertices;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<const Vec3f*, MemSpace> prev;
  Kokkos::View<Vec3*, MemSpace> emissive;
  LookupT lookup;
  Real radius;
  Vec3 background;

  // without_emission: the diffuse gather already has the lights through its shadow rays, so
  // it reads only the light that the hit surface reflects (no double counting).
  KOKKOS_INLINE_FUNCTION Vec3 read(int prim, Real u, Real v, const Vec3& dir,
                                   bool without_emission = false) const {
    if (prim < 0) return background;
    const Real w[3] = {Real(1) - u - v, u, v};
    ViewNeighbors nb;
    bool have_nb = false;
    Vec3 sum(Real(0));
    for (int k = 0; k < 3; ++k) {
      const int vert = tri_vertices(prim, k);
      const std::int64_t first = color_offset(vert);
      if (color_offset(vert + 1) - first == 1) {
        sum += Vec3(prev(first)) * w[k];
        continue;
      }
      if (!have_nb) {
        nb = lookup.neighbors(dir, radius);
        have_nb = true;
      }
      Vec3 c(Real(0));
      for (int j = 0; j < nb.count; ++j) c += Vec3(prev(first + nb.index[j])) * nb.weight[j];
      sum += c * w[k];
    }
    if (without_emission) {
      for (int k = 0; k < 3; ++k) sum -= emissive(tri_vertices(prim, k)) * w[k];
    }
    return sum;
  }
};

}  // namespace rtmini::bake
