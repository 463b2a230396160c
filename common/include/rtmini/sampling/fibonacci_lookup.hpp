#pragma once
// Looking a direction up among the N spherical Fibonacci viewpoints (sampling/fibonacci.hpp):
// (a) the baking seed's KD-tree laid out as a heap (children of node i at 2i+1, 2i+2), queried
//     with an explicit fixed-size stack instead of the seed's recursion (which overflowed the GPU
//     call stack), and (b) the closed-form inverse mapping of Keinert et al., "Spherical Fibonacci
//     Mapping" (SIGGRAPH Asia 2015), refined by a greedy walk over lattice neighbours so that the
//     nearest index is exact. Both feed the seed's radius query r = sqrt(32/N) (~8 neighbours),
//     whose neighbours are weighted by angular distance. All queries are device-callable.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini {

inline constexpr int kMaxViewNeighbors = 32;
inline constexpr int kKdStackSize = 64;  // tree depth <= 31 for any int N; one push per level

// The seed's sample radius (chord length on the unit sphere): a cap holding 8/N of the sphere.
KOKKOS_INLINE_FUNCTION Real fibonacci_radius(int n) { return math::sqrt(Real(32) / Real(n)); }

// Neighbours of a direction with normalised weights, sorted by (distance, index), so the
// weighted sums are identical whichever lookup produced them.
struct ViewNeighbors {
  int count = 0;
  int index[kMaxViewNeighbors];
  Real weight[kMaxViewNeighbors];
};

// Whether two answers hold the same neighbours with the same weights in the same order (the
// lookups' tests and bench compare them with exhaustive search and with each other).
KOKKOS_INLINE_FUNCTION bool same_neighbors(const ViewNeighbors& a, const ViewNeighbors& b) {
  bool same = a.count == b.count;
  for (int k = 0; same && k < a.count; ++k)
    same = a.index[k] == b.index[k] && a.weight[k] == b.weight[k];
  return same;
}

namespace detail {

// Keeps the kMaxViewNeighbors closest candidates, ordered by (d2, index).
struct NeighborCollector {
  int count = 0;
  int index[kMaxViewNeighbors];
  Real d2[kMaxViewNeighbors];

  KOKKOS_INLINE_FUNCTION void add(int i, Real dist2) {
    int pos = count;
    while (pos > 0 && (d2[pos - 1] > dist2 || (d2[pos - 1] == dist2 && index[pos - 1] > i))) --pos;
    if (pos >= kMaxViewNeighbors) return;
    const int last = count < kMaxViewNeighbors ? count : kMaxViewNeighbors - 1;
    for (int k = last; k > pos; --k) {
      index[k] = index[k - 1];
      d2[k] = d2[k - 1];
    }
    index[pos] = i;
    d2[pos] = dist2;
    if (count < kMaxViewNeighbors) ++count;
  }
};

// Weight (1 - (theta/theta_r)^2)^2: smooth, compactly supported in the angular distance theta.
KOKKOS_INLINE_FUNCTION ViewNeighbors finish_neighbors(const NeighborCollector& c, Real radius,
                                                      int nearest) {
  ViewNeighbors out;
  const Real theta_r = Real(2) * math::asin(math::fmin(Real(1), Real(0.5) * radius));
  Real sum = 0;
  for (int k = 0; k < c.count; ++k) {
    const Real chord = math::sqrt(math::fmax(Real(0), c.d2[k]));
    const Real theta = Real(2) * math::asin(math::fmin(Real(1), Real(0.5) * chord));
    const Real x = theta / theta_r;
    const Real w = x < Real(1) ? (Real(1) - x * x) * (Real(1) - x * x) : Real(0);
    if (w <= Real(0)) continue;
    out.index[out.count] = c.index[k];
    out.weight[out.count] = w;
    sum += w;
    ++out.count;
  }
  if (out.count == 0) {  // nothing strictly inside the cap: take the nearest point alone
    out.count = 1;
    out.index[0] = nearest;
    out.weight[0] = Real(1);
    return out;
  }
  for (int k = 0; k < out.count; ++k) out.weight[k] /= sum;
  return out;
}

}  // namespace detail

// Reference: exhaustive nearest index (ties -> lower index) and radius query.
template <class PointsView>
KOKKOS_INLINE_FUNCTION int brute_force_nearest(const PointsView& points, const Vec3& q) {
  int best = 0;
  Real best_d2 = length_squared(points(0) - q);
  for (int i = 1; i < static_cast<int>(points.extent(0)); ++i) {
    const Real d2 = length_squared(points(i) - q);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
  }
  return best;
}

template <class PointsView>
KOKKOS_INLINE_FUNCTION ViewNeighbors brute_force_neighbors(const PointsView& points, const Vec3& q,
                                                           Real radius) {
  detail::NeighborCollector c;
  const Real r2 = radius * radius;
  for (int i = 0; i < static_cast<int>(points.extent(0)); ++i) {
    const Real d2 = length_squared(points(i) - q);
    if (d2 <= r2) c.add(i, d2);
  }
  return detail::finish_neighbors(c, radius, brute_force_nearest(points, q));
}

// Heap-laid, left-balanced KD-tree over the Fibonacci points: node i stores one point (its
// Fibonacci index and position) and its split axis; the children of i are 2i+1 and 2i+2.
template <class MemorySpace>
struct FibonacciKdTree {
  Kokkos::View<Vec3*, MemorySpace> node_point;
  Kokkos::View<int*, MemorySpace> node_index;
  Kokkos::View<std::uint8_t*, MemorySpace> node_axis;
  int n = 0;

  KOKKOS_INLINE_FUNCTION int nearest(const Vec3& q) const {
    int stack[kKdStackSize];
    int sp = 0;
    stack[sp++] = 0;
    int best = -1;
    Real best_d2 = Real(1e30);
    while (sp > 0) {
      const int i = stack[--sp];
      if (i >= n) continue;
      const Vec3 p = node_point(i);
      const Real d2 = length_squared(p - q);
      const int id = node_index(i);
      if (d2 < best_d2 || (d2 == best_d2 && id < best)) {
        best_d2 = d2;
        best = id;
      }
      const int a = node_axis(i);
      const Real diff = q[a] - p[a];
      const int near_child = diff < Real(0) ? 2 * i + 1 : 2 * i + 2;
      const int far_child = diff < Real(0) ? 2 * i + 2 : 2 * i + 1;
      if (diff * diff <= best_d2) stack[sp++] = far_child;
      stack[sp++] = near_child;
    }
    return best;
  }

  KOKKOS_INLINE_FUNCTION ViewNeighbors neighbors(const Vec3& q, Real radius) const {
    detail::NeighborCollector c;
    const Real r2 = radius * radius;
    int stack[kKdStackSize];
    int sp = 0;
    stack[sp++] = 0;
    int best = -1;
    Real best_d2 = Real(1e30);
    while (sp > 0) {
      const int i = stack[--sp];
      if (i >= n) continue;
      const Vec3 p = node_point(i);
      const Real d2 = length_squared(p - q);
      const int id = node_index(i);
      if (d2 <= r2) c.add(id, d2);
      if (d2 < best_d2 || (d2 == best_d2 && id < best)) {
        best_d2 = d2;
        best = id;
      }
      const int a = node_axis(i);
      const Real diff = q[a] - p[a];
      const Real prune = r2 > best_d2 ? r2 : best_d2;  // also finds the nearest outside the cap
      const int near_child = diff < Real(0) ? 2 * i + 1 : 2 * i + 2;
      const int far_child = diff < Real(0) ? 2 * i + 2 : 2 * i + 1;
      if (diff * diff <= prune) stack[sp++] = far_child;
      stack[sp++] = near_child;
    }
    return detail::finish_neighbors(c, radius, best);
  }
};

namespace detail {

// Size of the left subtree of a left-balanced complete binary tree with m nodes.
inline int left_subtree_size(int m) {
  if (m <= 1) return 0;
  int h = 0;
  while ((2 << h) - 1 < m) ++h;  // h = depth of the last level (root at depth 0)
  const int full_above = (1 << h) - 1;
  const int last = m - full_above;
  const int half = 1 << (h - 1);
  return (half - 1) + (last < half ? last : half);
}

}  // namespace detail

// Host build over any point set (median splits along the widest axis, iterative), then one
// upload; a query reports a point by its position in `pts`.
template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
FibonacciKdTree<MemorySpace> build_point_kdtree(const std::vector<Vec3>& pts) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> ids(n);
  for (int i = 0; i < n; ++i) ids[i] = i;
  FibonacciKdTree<MemorySpace> t;
  t.n = n;
  t.node_point = Kokkos::View<Vec3*, MemorySpace>("rtmini::sampling::kd_point", n);
  t.node_index = Kokkos::View<int*, MemorySpace>("rtmini::sampling::kd_index", n);
  t.node_axis = Kokkos::View<std::uint8_t*, MemorySpace>("rtmini::sampling::kd_axis", n);
  auto hp = Kokkos::create_mirror_view(t.node_point);
  auto hi = Kokkos::create_mirror_view(t.node_index);
  auto ha = Kokkos::create_mirror_view(t.node_axis);
  struct Task {
    int node, begin, end;
  };
  std::vector<Task> work{{0, 0, n}};
  while (!work.empty()) {
    const Task task = work.back();
    work.pop_back();
    if (task.begin >= task.end) continue;
    Vec3 lo(Real(1e30)), hi_(Real(-1e30));
    for (int k = task.begin; k < task.end; ++k) {
      lo = vmin(lo, pts[ids[k]]);
      hi_ = vmax(hi_, pts[ids[k]]);
    }
    const int axis = max_dimension(hi_ - lo);
    const int mid = task.begin + detail::left_subtree_size(task.end - task.begin);
    std::nth_element(
        ids.begin() + task.begin, ids.begin() + mid, ids.begin() + task.end, [&](int a, int b) {
          return pts[a][axis] < pts[b][axis] || (pts[a][axis] == pts[b][axis] && a < b);
        });
    hp(task.node) = pts[ids[mid]];
    hi(task.node) = ids[mid];
    ha(task.node) = static_cast<std::uint8_t>(axis);
    work.push_back({2 * task.node + 1, task.begin, mid});
    work.push_back({2 * task.node + 2, mid + 1, task.end});
  }
  Kokkos::deep_copy(t.node_point, hp);
  Kokkos::deep_copy(t.node_index, hi);
  Kokkos::deep_copy(t.node_axis, ha);
  return t;
}

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
FibonacciKdTree<MemorySpace> build_fibonacci_kdtree(int n) {
  std::vector<Vec3> pts(n);
  for (int i = 0; i < n; ++i) pts[i] = fibonacci_point(i, n);
  return build_point_kdtree<MemorySpace>(pts);
}

// Keinert et al.'s inverse spherical Fibonacci mapping over a table of the N points (the
// table keeps point positions bit-identical to the KD-tree's and avoids trigonometry per
// candidate). The lattice arithmetic is in double: i * phi loses the angle in float for N ~ 1e5.
template <class MemorySpace>
struct FibonacciInverse {
  Kokkos::View<Vec3*, MemorySpace> points;
  int n = 0;

  // Local lattice offsets at the query's latitude: F_{k-1}, F_k, F_{k+1}, F_{k+2} and 1.
  KOKKOS_INLINE_FUNCTION void lattice(const Vec3& q, long long& f0, long long& f1,
                                      long long& cell) const {
    const double kPhi = kGoldenRatio;
    const double pi = math::kPi;
    const double z = math::fmax(-1.0, math::fmin(1.0, double(q.z)));
    const double phi = math::fmin(math::atan2(double(q.y), double(q.x)), pi);
    const double s2 = math::fmax(1.0 - z * z, 1e-300);
    const double kk =
        math::floor(math::log(n * pi * 2.2360679774997896964 * s2) / math::log(kPhi * kPhi));
    const double k = math::fmax(2.0, kk);
    const double fk = math::pow(kPhi, k) / 2.2360679774997896964;
    const double F0 = math::floor(fk + 0.5), F1 = math::floor(fk * kPhi + 0.5);
    const double ka0 = 2.0 * F0 / n, ka1 = 2.0 * F1 / n;
    auto centred = [&](double f) {
      const double x = (f + 1.0) * kPhi;
      return 2.0 * pi * ((x - math::floor(x)) - (kPhi - 1.0));
    };
    const double kb0 = centred(F0), kb1 = centred(F1);
    const double det = ka1 * kb0 - ka0 * kb1;
    const double zp = z - (1.0 - 1.0 / n);
    const double c0 = math::floor((ka1 * phi + kb1 * zp) / det);
    const double c1 = math::floor((-ka0 * phi - kb0 * zp) / det);
    f0 = static_cast<long long>(F0);
    f1 = static_cast<long long>(F1);
    cell = static_cast<long long>(F0 * c0 + F1 * c1);
  }

  KOKKOS_INLINE_FUNCTION int nearest(const Vec3& q) const {
    if (n <= 16) return brute_force_nearest(points, q);
    long long f0, f1, base;
    lattice(q, f0, f1, base);
    int best = -1;
    Real best_d2 = Real(1e30);
    auto consider = [&](long long i) {
      if (i < 0 || i >= n) return false;
      const Real d2 = length_squared(points(static_cast<int>(i)) - q);
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = static_cast<int>(i);
        return true;
      }
      return false;
    };
    const long long corner[4] = {0, f0, f1, f0 + f1};
    for (int s = 0; s < 4; ++s) consider(base + corner[s]);
    // The 4 lattice corners miss the nearest point near the poles and zone borders: walk
    // greedily over lattice neighbours (a local minimum there is the nearest point).
    const long long offsets[5] = {1, f1 - f0, f0, f1, f0 + f1};
    if (best < 0) consider(base < 0 ? 0 : (base >= n ? n - 1 : base));
    bool moved = true;
    while (moved) {
      moved = false;
      const long long at = best;
      for (int k = 0; k < 5; ++k) {
        moved = consider(at + offsets[k]) || moved;
        moved = consider(at - offsets[k]) || moved;
      }
    }
    return best;
  }

  // Flood fill over lattice neighbours from the nearest point. It also walks through points
  // just outside the cap (up to 1.5 r): a cap point can be linked to the others only via those.
  KOKKOS_INLINE_FUNCTION ViewNeighbors neighbors(const Vec3& q, Real radius) const {
    if (n <= 16) return brute_force_neighbors(points, q, radius);
    const int start = nearest(q);
    long long f0, f1, base;
    lattice(q, f0, f1, base);
    const long long offsets[5] = {1, f1 - f0, f0, f1, f0 + f1};
    const Real r2 = radius * radius, walk2 = Real(2.25) * r2;
    // Visited set: open addressing over a small table (the walk sees ~50 points).
    constexpr int kTable = 256, kMaxQueue = 2 * kMaxViewNeighbors;
    int table[kTable];
    for (int s = 0; s < kTable; ++s) table[s] = -1;
    auto first_visit = [&](int i) {
      unsigned h = (static_cast<unsigned>(i) * 2654435761u) >> 24;
      while (table[h] >= 0) {
        if (table[h] == i) return false;
        h = (h + 1u) & (kTable - 1);
      }
      table[h] = i;
      return true;
    };
    int queue[kMaxQueue];
    int head = 0, tail = 0, visited = 1;
    detail::NeighborCollector c;
    first_visit(start);
    queue[tail++] = start;
    const Real d0 = length_squared(points(start) - q);
    if (d0 <= r2) c.add(start, d0);
    while (head < tail) {
      const long long at = queue[head++];
      for (int k = 0; k < 10; ++k) {
        const long long i = k < 5 ? at + offsets[k] : at - offsets[k - 5];
        if (i < 0 || i >= n || visited >= kTable / 2 || !first_visit(static_cast<int>(i))) continue;
        ++visited;
        const Real d2 = length_squared(points(static_cast<int>(i)) - q);
        if (d2 <= r2) c.add(static_cast<int>(i), d2);
        if (d2 <= walk2 && tail < kMaxQueue) queue[tail++] = static_cast<int>(i);
      }
    }
    return detail::finish_neighbors(c, radius, start);
  }
};

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
Kokkos::View<Vec3*, MemorySpace> fibonacci_points(int n) {
  Kokkos::View<Vec3*, MemorySpace> pts("rtmini::sampling::fibonacci_points", n);
  auto h = Kokkos::create_mirror_view(pts);
  for (int i = 0; i < n; ++i) h(i) = fibonacci_point(i, n);
  Kokkos::deep_copy(pts, h);
  return pts;
}

template <class MemorySpace = Kokkos::DefaultExecutionSpace::memory_space>
FibonacciInverse<MemorySpace> build_fibonacci_inverse(int n) {
  FibonacciInverse<MemorySpace> f;
  f.n = n;
  f.points = fibonacci_points<MemorySpace>(n);
  return f;
}

}  // namespace rtmini
