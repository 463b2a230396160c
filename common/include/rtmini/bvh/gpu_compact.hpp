#pragma once
// Builds the 32-byte copy of a binary BVH's nodes (compact_node.hpp) on any Kokkos execution
// space: one grid for the tree from the root's two child boxes, then every node quantised
// independently (one thread per node) with lower planes rounded down and upper planes up,
// each checked against the exact box it must enclose.
#include <cmath>
#include <stdexcept>
#include <string>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

namespace detail {

// A grid whose 65536 planes per axis cover `box`: origin at its lower corner, the step the
// smallest power of two whose last plane decodes at or above its upper corner.
inline CompactGrid compact_grid(const Aabb& box) {
  CompactGrid g;
  const Real lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
  for (int k = 0; k < 3; ++k) {
    g.origin[k] = lo[k];
    const double extent = double(hi[k]) - double(lo[k]);
    int e = extent > 0 ? int(std::ceil(std::log2(extent / kCompactGridMax))) : 0;
    e = e < -120 ? -120 : e;  // a normal float step even for a flat axis
    g.step[k] = Real(std::ldexp(1.0, e));
    while (grid_plane(g, k, kCompactGridMax) < hi[k]) g.step[k] *= Real(2);
  }
  return g;
}

// The largest step count whose plane is at or below x (x inside the grid).
KOKKOS_INLINE_FUNCTION std::uint32_t count_below(const CompactGrid& g, int axis, Real x) {
  Real f = math::floor((x - g.origin[axis]) / g.step[axis]);
  f = f >= Real(0) ? (f <= Real(kCompactGridMax) ? f : Real(kCompactGridMax)) : Real(0);
  std::uint32_t q = static_cast<std::uint32_t>(f);
  while (q > 0 && grid_plane(g, axis, q) > x) --q;  // the division rounded up
  return q;
}

// The smallest step count whose plane is at or above x (x inside the grid).
KOKKOS_INLINE_FUNCTION std::uint32_t count_above(const CompactGrid& g, int axis, Real x) {
  Real f = math::ceil((x - g.origin[axis]) / g.step[axis]);
  f = f >= Real(0) ? (f <= Real(kCompactGridMax) ? f : Real(kCompactGridMax)) : Real(0);
  std::uint32_t q = static_cast<std::uint32_t>(f);
  while (q < kCompactGridMax && grid_plane(g, axis, q) < x) ++q;  // the division rounded down
  return q;
}

// Decoded child box k of a compact node.
KOKKOS_INLINE_FUNCTION Aabb compact_box(const CompactBvhNode& n, const CompactGrid& g, int k) {
  Aabb b;
  b.lo = Vec3(grid_plane(g, 0, n.q[0 + k]), grid_plane(g, 1, n.q[2 + k]),
              grid_plane(g, 2, n.q[4 + k]));
  b.hi = Vec3(grid_plane(g, 0, n.q[6 + k]), grid_plane(g, 1, n.q[8 + k]),
              grid_plane(g, 2, n.q[10 + k]));
  return b;
}

KOKKOS_INLINE_FUNCTION bool encloses(const Aabb& outer, const Aabb& inner) {
  return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
         outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

KOKKOS_INLINE_FUNCTION CompactBvhNode compact_node(const BvhNode& nd, const CompactGrid& g) {
  CompactBvhNode c;
  for (int k = 0; k < 2; ++k) {
    c.child[k] = nd.child[k];
    c.q[0 + k] = static_cast<std::uint16_t>(count_below(g, 0, nd.lo_x[k]));
    c.q[2 + k] = static_cast<std::uint16_t>(count_below(g, 1, nd.lo_y[k]));
    c.q[4 + k] = static_cast<std::uint16_t>(count_below(g, 2, nd.lo_z[k]));
    c.q[6 + k] = static_cast<std::uint16_t>(count_above(g, 0, nd.hi_x[k]));
    c.q[8 + k] = static_cast<std::uint16_t>(count_above(g, 1, nd.hi_y[k]));
    c.q[10 + k] = static_cast<std::uint16_t>(count_above(g, 2, nd.hi_z[k]));
  }
  return c;
}

}  // namespace detail

// Fills bvh.compact and bvh.grid from bvh.nodes. Throws std::runtime_error if a decoded box does
// not enclose its child (a child outside the root's boxes: no builder makes one).
template <class ExecSpace, class MemorySpace>
void add_compact_binary(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  const int n = static_cast<int>(bvh.nodes.extent(0));
  if (bvh.num_prims == 0 || n == 0) return;
  Kokkos::Profiling::pushRegion("rtmini::bvh::build::compact_binary");
  BvhNode root;
  Kokkos::deep_copy(space, Kokkos::View<BvhNode, Kokkos::HostSpace>(&root),
                    Kokkos::subview(bvh.nodes, 0));
  space.fence();
  Aabb box;
  for (int k = 0; k < 2; ++k)
    if (root.child[k] != kEmptyLeaf) box.expand(root.box(k));
  const CompactGrid g = detail::compact_grid(box);
  Kokkos::View<CompactBvhNode*, MemorySpace> compact(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::compact"), n);
  const auto nodes = bvh.nodes;
  int loose = 0;
  Kokkos::parallel_reduce(
      "rtmini::bvh::build::compact_nodes", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int i, int& bad) {
        const BvhNode nd = nodes(i);
        const CompactBvhNode c = detail::compact_node(nd, g);
        compact(i) = c;
        for (int k = 0; k < 2; ++k)
          if (nd.child[k] != kEmptyLeaf &&
              !detail::encloses(detail::compact_box(c, g, k), nd.box(k)))
            ++bad;
      },
      loose);
  Kokkos::Profiling::popRegion();
  if (loose != 0)
    throw std::runtime_error("compact BVH: " + std::to_string(loose) +
                             " child boxes outside the root's grid");
  bvh.compact = compact;
  bvh.grid = g;
}

}  // namespace rtmini::bvh
