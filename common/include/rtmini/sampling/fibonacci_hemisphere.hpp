#pragma once
// Hemisphere viewpoint maps: a vertex whose viewpoints behind it are folded to the front (bake's
// one-sided mirrors) needs colours on one hemisphere only. Its viewpoints are the first N/2
// points of the N-point Fibonacci sphere (z_i > 0 for an even N), expressed in the vertex's
// tangent frame, whose z axis points to the front. The same point table and lookups as the full
// sphere then serve every vertex: a direction is turned into the frame, folded to z >= 0 and
// looked up among the N points, keeping the stored half.
//
// Near the horizon a cap also covers folded images: the colour a full-sphere map stores at a
// viewpoint p behind the vertex is, under folding, the colour at its mirror image. The lookup
// reads the point set S u mirror(S) (S: the stored half), so a direction at grazing angles
// blends as many neighbours as elsewhere instead of half as many: the cap around q gathers the
// stored points near q, plus every stored point whose mirror image is near q (= stored points
// near q's mirror image below the horizon).
#include <vector>

#include "rtmini/sampling/fibonacci_lookup.hpp"
#include "rtmini/sampling/sphere_grid.hpp"

namespace rtmini {

// An orthonormal frame with z = front (unit); x, y span the tangent plane. Duff et al.,
// "Building an Orthonormal Basis, Revisited" (JCGT 2017): branch-free, continuous except on
// z = 0, and the same bits on every backend for the same input.
struct ViewFrame {
  Vec3 x, y, z;

  KOKKOS_INLINE_FUNCTION Vec3 to_world(const Vec3& p) const { return x * p.x + y * p.y + z * p.z; }
  KOKKOS_INLINE_FUNCTION Vec3 to_local(const Vec3& d) const {
    return {dot(d, x), dot(d, y), dot(d, z)};
  }
};

KOKKOS_INLINE_FUNCTION ViewFrame view_frame(const Vec3& front) {
  const Real sign = front.z >= Real(0) ? Real(1) : Real(-1);
  const Real a = Real(-1) / (sign + front.z);
  const Real b = front.x * front.y * a;
  ViewFrame f;
  f.x = Vec3(Real(1) + sign * front.x * front.x * a, sign * b, -sign * front.x);
  f.y = Vec3(b, sign + front.y * front.y * a, -front.y);
  f.z = front;
  return f;
}

// Viewpoints a hemisphere map stores per view-dependent vertex at N sphere viewpoints (N even).
KOKKOS_INLINE_FUNCTION int hemisphere_viewpoints(int n) { return n / 2; }

// Neighbours of local direction q (q.z >= 0) among the m = N/2 stored points of an N-point set,
// with their mirror images; `points` holds the N points (the lookup's own positions, so the
// distances are the lookup's bits). Sorted and weighted as ViewNeighbors: the sums are the same
// for either lookup.
template <class LookupT, class PointsView>
KOKKOS_INLINE_FUNCTION ViewNeighbors hemisphere_neighbors(const LookupT& lookup,
                                                          const PointsView& points, const Vec3& q,
                                                          Real radius, int m) {
  detail::NeighborCollector c;
  const Real r2 = radius * radius;
  const ViewNeighbors above = lookup.neighbors(q, radius);
  for (int k = 0; k < above.count; ++k) {
    const int i = above.index[k];
    const Real d2 = length_squared(points(i) - q);
    if (i < m && d2 <= r2) c.add(i, d2);
  }
  // A stored point p (p.z > 0) lies at chord distance >= q.z + p.z > q.z from q's mirror image:
  // only a cap that crosses the horizon holds mirror images.
  const Vec3 below(q.x, q.y, -q.z);
  if (q.z < radius) {
    const ViewNeighbors mirrored = lookup.neighbors(below, radius);
    for (int k = 0; k < mirrored.count; ++k) {
      const int i = mirrored.index[k];
      const Real d2 = length_squared(points(i) - below);
      if (i < m && d2 <= r2) c.add(i, d2);
    }
  }
  int nearest = 0;
  if (c.count == 0) {  // a cap with no stored point (tiny N only): the nearest point or image
    Real best = Real(1e30);
    for (int i = 0; i < m; ++i) {
      const Real d2 = math::fmin(length_squared(points(i) - q), length_squared(points(i) - below));
      if (d2 < best) {
        best = d2;
        nearest = i;
      }
    }
  }
  return detail::finish_neighbors(c, radius, nearest);
}

// The stored half and its mirror images as one set of 2m points (the image of point i at m + i),
// so that one query of a KD-tree or grid over them finds what hemisphere_neighbors finds with
// two (the same points at the same distances: negating z is exact).
inline std::vector<Vec3> mirrored_points(int n) {
  const int m = hemisphere_viewpoints(n);
  std::vector<Vec3> pts(2 * static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    const Vec3 p = fibonacci_point(i, n);
    pts[i] = p;
    pts[m + i] = Vec3(p.x, p.y, -p.z);
  }
  return pts;
}

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
FibonacciKdTree<MemorySpace> build_mirrored_kdtree(int n) {
  return build_point_kdtree<MemorySpace>(mirrored_points(n));
}

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
SphereGrid<MemorySpace> build_mirrored_grid(int n) {
  return build_point_grid<MemorySpace>(mirrored_points(n), fibonacci_radius(n));
}

// hemisphere_neighbors through the mirrored tree or grid: images report the stored point they
// mirror.
template <class MirroredLookup>
KOKKOS_INLINE_FUNCTION ViewNeighbors mirrored_neighbors(const MirroredLookup& tree, const Vec3& q,
                                                        Real radius, int m) {
  ViewNeighbors nb = tree.neighbors(q, radius);
  for (int k = 0; k < nb.count; ++k)
    if (nb.index[k] >= m) nb.index[k] -= m;
  return nb;
}

}  // namespace rtmini
