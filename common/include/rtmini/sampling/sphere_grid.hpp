#pragma once
// A third viewpoint lookup, beside the KD-tree and the inverse mapping (fibonacci_lookup.hpp):
// a cube map over the unit sphere whose cells each list every point a query inside them can
// need, so that a query scans one short list (about 1.6 caps' worth of points) with no tree
// walk and no data-dependent branching beyond the list's length. It answers exactly what the
// other two answer (same neighbours, same weights, same nearest; ViewNeighbors' order does not
// depend on the order points are visited in), so switching lookups never changes a result.
//
// Why a cell's list is enough. Let cell C have centre direction c and chord radius h (no
// point of C on the sphere is further than h from c). A point within r of a query q in C is
// within r + h of c; and if some point lies within r - h of c, the point nearest to q lies
// within d_c + 2h <= r + h of c (d_c: c's nearest distance). So C lists every point within
// r + h of c, plus a margin for rounding and slightly off-unit queries; a query in a cell with
// no point within r - h of c (tiny N, or a set that leaves part of the sphere empty) scans all
// points, as does a query off the unit sphere or with a radius above the one the lists were
// built for: still exact.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rtmini/kokkos_compat.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini {

// Cube-face cells per unit of cap radius (a cell edge of about r / 2.8 near a face's centre,
// lists of about 11 points for caps of 8). rtmini-bake-lookup-bench's sweep, one core of the
// 2-core VM (results/bake/raw_grid_lookup/local/lookup_bench_1t.txt): 2.8 -> 11.3 cells per r
// took a cap query from 318 to 287 ns at N = 100 and 321 to 292 ns at N = 1000 (the KD-tree:
// 706 and 1410 ns), while the table grows 16-fold; 5.7 is within 4 % of the finest.
inline constexpr double kGridCellsPerRadius = 5.7;
inline constexpr int kGridMaxCellsPerEdge = 512;

namespace detail {

// Direction of cube-face coordinates (u, v) in [-1, 1] on face f (0: +x, 1: -x, 2: +y, 3: -y,
// 4: +z, 5: -z), not normalised; SphereGrid::cell_of inverts it.
inline Vec3 cube_face_direction(int f, double u, double v) {
  const Real s = (f % 2 == 0) ? Real(1) : Real(-1);
  if (f < 2) return {s, Real(u), Real(v)};
  if (f < 4) return {Real(v), s, Real(u)};
  return {Real(u), Real(v), s};
}

}  // namespace detail

template <class MemorySpace>
struct SphereGrid {
  Kokkos::View<const int*, MemorySpace> cell_start;   // 6 g^2 + 1 offsets into cell_points
  Kokkos::View<const int*, MemorySpace> cell_points;  // point indices, cell after cell; -1: all
  Kokkos::View<const Vec3*, MemorySpace> points;      // the points, by index
  int n = 0;                                          // points
  int g = 1;                                          // cells per cube-face edge
  Real radius = 0;                                    // the largest cap radius the lists serve

  // Cube-map cell of a unit direction: the face of its largest component, then g x g cells
  // over the other two components divided by it.
  KOKKOS_INLINE_FUNCTION int cell_of(const Vec3& q) const {
    const Real ax = math::fabs(q.x), ay = math::fabs(q.y), az = math::fabs(q.z);
    int face;
    Real m, u, v;
    if (ax >= ay && ax >= az) {
      face = q.x < Real(0) ? 1 : 0;
      m = ax, u = q.y, v = q.z;
    } else if (ay >= az) {
      face = q.y < Real(0) ? 3 : 2;
      m = ay, u = q.z, v = q.x;
    } else {
      face = q.z < Real(0) ? 5 : 4;
      m = az, u = q.x, v = q.y;
    }
    const Real half = Real(0.5) * Real(g), top = Real(g - 1);
    const int iu = static_cast<int>(math::fmin(math::fmax((u / m + Real(1)) * half, Real(0)), top));
    const int iv = static_cast<int>(math::fmin(math::fmax((v / m + Real(1)) * half, Real(0)), top));
    return (face * g + iv) * g + iu;
  }

  // Queries the lists are not built for: off the unit sphere (zero, NaN, unnormalised) or a
  // larger cap. They scan every point.
  KOKKOS_INLINE_FUNCTION bool scans_all(const Vec3& q, Real r) const {
    const Real l = length_squared(q);
    return !(l > Real(1) - Real(1e-4) && l < Real(1) + Real(1e-4)) || r > radius;
  }

  // Calls visit(i) for every point index q's answer may need.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_candidates(const Vec3& q, Real r, F&& visit) const {
    if (scans_all(q, r)) {
      for (int i = 0; i < n; ++i) visit(i);
      return;
    }
    const int cell = cell_of(q);
    const int begin = cell_start(cell), end = cell_start(cell + 1);
    if (begin < end && cell_points(begin) < 0) {
      for (int i = 0; i < n; ++i) visit(i);
      return;
    }
    for (int k = begin; k < end; ++k) visit(cell_points(k));
  }

  // Nearest point (ties -> lower index), as FibonacciKdTree::nearest.
  KOKKOS_INLINE_FUNCTION int nearest(const Vec3& q) const {
    int best = -1;
    Real best_d2 = Real(1e30);
    for_candidates(q, radius, [&](int i) {
      const Real d2 = length_squared(points(i) - q);
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = i;
      }
    });
    return best;
  }

  KOKKOS_INLINE_FUNCTION ViewNeighbors neighbors(const Vec3& q, Real r) const {
    detail::NeighborCollector c;
    const Real r2 = r * r;
    int best = -1;
    Real best_d2 = Real(1e30);
    for_candidates(q, r, [&](int i) {
      const Real d2 = length_squared(points(i) - q);
      if (d2 <= r2) c.add(i, d2);
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = i;
      }
    });
    return detail::finish_neighbors(c, r, best);
  }
};

namespace detail {

// Centre direction and chord radius of cube-map cell (face, iu, iv) on the unit sphere. The
// chord radius is the largest distance to 16 samples per edge (the farthest point of a small
// spherical quadrilateral from its centre is on its boundary), plus 1 % for between samples.
inline void grid_cell_shape(int g, int face, int iu, int iv, Vec3& centre, double& chord) {
  const double du = 2.0 / g;
  const double u0 = -1.0 + du * iu, v0 = -1.0 + du * iv;
  centre = normalize(cube_face_direction(face, u0 + 0.5 * du, v0 + 0.5 * du));
  constexpr int kSamples = 16;
  double h = 0;
  for (int s = 0; s <= kSamples; ++s) {
    const double t = du * s / kSamples;
    const double edge[4][2] = {{u0 + t, v0}, {u0 + t, v0 + du}, {u0, v0 + t}, {u0 + du, v0 + t}};
    for (const auto& e : edge) {
      const Vec3 b = normalize(cube_face_direction(face, e[0], e[1]));
      h = std::max(h, double(length(b - centre)));
    }
  }
  chord = 1.01 * h;
}

// Points bucketed in a uniform 3D grid of bins at least `width` wide over [-1, 1]^3, so that
// every point within `width` of a position lies in the 27 bins around it.
struct PointBins {
  int per_axis = 1;
  std::vector<int> start, ids;

  PointBins(const std::vector<Vec3>& pts, double width) {
    per_axis = std::max(1, std::min(128, static_cast<int>(2.0 / std::max(width, 1e-9))));
    start.assign(static_cast<std::size_t>(per_axis) * per_axis * per_axis + 1, 0);
    std::vector<int> bin(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      bin[i] = index(axis_bin(pts[i].x), axis_bin(pts[i].y), axis_bin(pts[i].z));
      ++start[bin[i] + 1];
    }
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    ids.resize(pts.size());
    std::vector<int> at(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i) ids[at[bin[i]]++] = static_cast<int>(i);
  }
  int axis_bin(double x) const {
    return std::clamp(static_cast<int>((x + 1.0) * 0.5 * per_axis), 0, per_axis - 1);
  }
  int index(int x, int y, int z) const { return (z * per_axis + y) * per_axis + x; }

  template <class F>
  void around(const Vec3& p, F&& f) const {
    const int x = axis_bin(p.x), y = axis_bin(p.y), z = axis_bin(p.z);
    for (int k = std::max(0, z - 1); k <= std::min(per_axis - 1, z + 1); ++k)
      for (int j = std::max(0, y - 1); j <= std::min(per_axis - 1, y + 1); ++j)
        for (int i = std::max(0, x - 1); i <= std::min(per_axis - 1, x + 1); ++i) {
          const int b = index(i, j, k);
          for (int s = start[b]; s < start[b + 1]; ++s) f(ids[s]);
        }
  }
};

}  // namespace detail

// Host build over any point set on the unit sphere for caps up to `radius`, then one upload; a
// query reports a point by its position in `pts`.
template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
SphereGrid<MemorySpace> build_point_grid(const std::vector<Vec3>& pts, Real radius,
                                         double cells_per_radius = kGridCellsPerRadius) {
  SphereGrid<MemorySpace> grid;
  grid.n = static_cast<int>(pts.size());
  grid.radius = radius;
  grid.g = std::clamp(static_cast<int>(std::ceil(cells_per_radius / double(radius))), 1,
                      kGridMaxCellsPerEdge);
  const int g = grid.g, cells = 6 * g * g;
  std::vector<Vec3> centre(cells);
  std::vector<double> chord(cells);
  double widest = 0;
  for (int f = 0; f < 6; ++f)
    for (int iv = 0; iv < g; ++iv)
      for (int iu = 0; iu < g; ++iu) {
        const int c = (f * g + iv) * g + iu;
        detail::grid_cell_shape(g, f, iu, iv, centre[c], chord[c]);
        widest = std::max(widest, chord[c]);
      }
  // Rounding, and queries up to 1e-4 off unit length (scans_all), stay inside this margin.
  const auto margin = [](double h) { return 2e-4 + 0.01 * h; };
  const double reach_max = double(radius) + widest + margin(widest);
  const detail::PointBins bins(pts, reach_max);
  std::vector<int> start(cells + 1, 0), ids, list;
  for (int c = 0; c < cells; ++c) {
    const double reach = double(radius) + chord[c] + margin(chord[c]);
    double nearest = 1e30;
    list.clear();
    bins.around(centre[c], [&](int i) {
      const double d = length(pts[i] - centre[c]);
      nearest = std::min(nearest, d);
      if (d <= reach) list.push_back(i);
    });
    if (nearest > double(radius) - chord[c]) list.assign(1, -1);  // the nearest may lie beyond
    std::sort(list.begin(), list.end());
    ids.insert(ids.end(), list.begin(), list.end());
    start[c + 1] = static_cast<int>(ids.size());
  }
  grid.cell_start = compat::upload<MemorySpace>("rtmini::sampling::grid_start", start);
  grid.cell_points = compat::upload<MemorySpace>("rtmini::sampling::grid_points", ids);
  grid.points = compat::upload<MemorySpace>("rtmini::sampling::grid_positions", pts);
  return grid;
}

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
SphereGrid<MemorySpace> build_fibonacci_grid(int n) {
  std::vector<Vec3> pts(n);
  for (int i = 0; i < n; ++i) pts[i] = fibonacci_point(i, n);
  return build_point_grid<MemorySpace>(pts, fibonacci_radius(n));
}

}  // namespace rtmini
