#pragma once
// Parallel linear BVH build on any Kokkos execution space, in four passes: scene and centroid
// bounds (one fused reduction) -> Morton codes of the centroids -> sort by code -> hierarchy,
// boxes, SAH-driven collapse of small subtrees into leaves and the node records, all in one
// bottom-up pass (Apetrei, "Fast and Simple Agglomerative LBVH Construction", 2014): each
// triangle's thread climbs while it is the second child to arrive at a node. The tree is
// Karras' radix tree over the sorted codes (HPG 2012), built without its top-down split search.
// Collapsed subtrees are contiguous in Morton order, so a leaf is a plain index range.
#include <Kokkos_Timer.hpp>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

namespace detail {

// Spread the low 21 bits of x so there are two zero bits between each.
KOKKOS_INLINE_FUNCTION std::uint64_t spread_bits_21(std::uint64_t x) {
  x &= 0x1fffffULL;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// 30-bit Morton code (10 bits per axis) of a point in the unit cube.
KOKKOS_INLINE_FUNCTION std::uint32_t morton_code(const Vec3& unit) {
  auto q = [](Real x) {
    const Real c = x < Real(0) ? Real(0) : (x > Real(1) ? Real(1) : x);
    return static_cast<std::uint64_t>(c * Real(1023));
  };
  return static_cast<std::uint32_t>(spread_bits_21(q(unit.x)) << 2 |
                                    spread_bits_21(q(unit.y)) << 1 | spread_bits_21(q(unit.z)));
}

// The Morton code above a 32-bit index: a unique sort key (the host-side block ordering in
// bake's kitchen sorts these).
KOKKOS_INLINE_FUNCTION std::uint64_t morton_key(const Vec3& unit, std::uint32_t index) {
  return std::uint64_t(morton_code(unit)) << 32 | index;
}

// How high in the radix tree the split between sorted positions i and i + 1 sits: the larger,
// the higher (Apetrei 2014 compares the codes' XOR instead of Karras' common-prefix length).
// Equal codes are told apart by their positions, below every real code difference, so every
// split has its own level and the tree is unique.
template <class CodeView>
KOKKOS_INLINE_FUNCTION std::uint64_t split_level(const CodeView& codes, int i) {
  return std::uint64_t(codes(i) ^ codes(i + 1)) << 32 |
         (static_cast<std::uint32_t>(i) ^ static_cast<std::uint32_t>(i + 1));
}

}  // namespace detail

// Scene bounds (for the BVH) and centroid bounds (for the Morton grid) of the input.
struct LbvhBounds {
  Aabb scene, centroids;
};

// Both boxes in one pass over the triangles: twelve minima in one fused reduction (the maxima
// as minima of negated values), instead of one reduction per plane.
template <class ExecSpace, class MemorySpace>
LbvhBounds scene_and_centroid_bounds(const ExecSpace& space,
                                     Kokkos::View<const Triangle*, MemorySpace> input) {
  const int n = static_cast<int>(input.extent(0));
  Real m[12];
  using M = Kokkos::Min<Real>;
  Kokkos::parallel_reduce(
      "rtmini::bvh::build::bounds", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int i, Real& slx, Real& sly, Real& slz, Real& shx, Real& shy, Real& shz,
                    Real& clx, Real& cly, Real& clz, Real& chx, Real& chy, Real& chz) {
        const Triangle& t = input(i);
        const Vec3 lo = vmin(t.a, vmin(t.b, t.c)), hi = vmax(t.a, vmax(t.b, t.c));
        const Vec3 c = (t.a + t.b + t.c) / Real(3);
        slx = math::fmin(slx, lo.x);
        sly = math::fmin(sly, lo.y);
        slz = math::fmin(slz, lo.z);
        shx = math::fmin(shx, -hi.x);
        shy = math::fmin(shy, -hi.y);
        shz = math::fmin(shz, -hi.z);
        clx = math::fmin(clx, c.x);
        cly = math::fmin(cly, c.y);
        clz = math::fmin(clz, c.z);
        chx = math::fmin(chx, -c.x);
        chy = math::fmin(chy, -c.y);
        chz = math::fmin(chz, -c.z);
      },
      M(m[0]), M(m[1]), M(m[2]), M(m[3]), M(m[4]), M(m[5]), M(m[6]), M(m[7]), M(m[8]), M(m[9]),
      M(m[10]), M(m[11]));
  LbvhBounds b;
  b.scene.lo = Vec3(m[0], m[1], m[2]);
  b.scene.hi = Vec3(-m[3], -m[4], -m[5]);
  b.centroids.lo = Vec3(m[6], m[7], m[8]);
  b.centroids.hi = Vec3(-m[9], -m[10], -m[11]);
  return b;
}

// The triangles' Morton codes on the centroid box's grid, sorted, and the input index of each
// (ascending among equal codes).
template <class MemorySpace>
struct MortonOrder {
  Kokkos::View<std::uint32_t*, MemorySpace> codes, index;
};

template <class ExecSpace, class MemorySpace>
MortonOrder<MemorySpace> morton_order(const ExecSpace& space,
                                      Kokkos::View<const Triangle*, MemorySpace> input,
                                      const Aabb& centroids) {
  const int n = static_cast<int>(input.extent(0));
  const Vec3 lo = centroids.lo, ext = centroids.hi - centroids.lo;
  const Vec3 inv_ext(ext.x > 0 ? 1 / ext.x : 0, ext.y > 0 ? 1 / ext.y : 0,
                     ext.z > 0 ? 1 / ext.z : 0);
  MortonOrder<MemorySpace> out;
  out.codes = Kokkos::View<std::uint32_t*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::codes"), n);
  out.index = Kokkos::View<std::uint32_t*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::order"), n);
  const auto codes = out.codes;
  const auto index = out.index;
  Kokkos::parallel_for(
      "rtmini::bvh::build::morton", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int i) {
        const Triangle& t = input(i);
        const Vec3 c = (t.a + t.b + t.c) * (Real(1) / Real(3));
        codes(i) = detail::morton_code((c - lo) * inv_ext);
        index(i) = static_cast<std::uint32_t>(i);
      });
  return out;
}

// A one-triangle tree: the root's second slot is empty.
template <class ExecSpace, class MemorySpace>
void emit_single_leaf(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
                      Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  auto prim = bvh.prim;
  auto nodes = bvh.nodes;
  Kokkos::parallel_for(
      "rtmini::bvh::build::single", Kokkos::RangePolicy<ExecSpace>(space, 0, 1),
      KOKKOS_LAMBDA(int) {
        tris(0) = input(0);
        prim(0) = 0;
        Aabb box;
        box.expand(tris(0).a);
        box.expand(tris(0).b);
        box.expand(tris(0).c);
        nodes(0).set_child(0, box, make_leaf(0, 1));
        nodes(0).set_child(1, Aabb(), kEmptyLeaf);
      });
}

// SAH cost (Ct = Ci = 1) of a finished node of `count` triangles whose children cost `left` and
// `right` (magnitudes: a negative cost marks a subtree cheaper as one leaf).
KOKKOS_INLINE_FUNCTION Real subtree_cost(Real area, int count, Real left, Real right) {
  constexpr Real kTraversalCost = 1, kTriangleCost = 1;
  const Real split = kTraversalCost * area + math::fabs(left) + math::fabs(right);
  const Real leaf = kTriangleCost * Real(count) * area;
  return (count <= kMaxLeafSize && leaf <= split) ? -leaf : split;
}

KOKKOS_INLINE_FUNCTION Aabb triangle_box(const Triangle& t) {
  Aabb b;
  b.expand(t.a);
  b.expand(t.b);
  b.expand(t.c);
  return b;
}

// The hierarchy, boxes, costs and node records in one bottom-up pass. Internal node i is the
// split between sorted positions i and i + 1; a node covering [lo, hi] hangs below whichever of
// its bounding splits (lo - 1 or hi) is lower in the tree. Its thread writes its box, cost and
// id, then swaps its outer endpoint into the parent: the first to arrive stops there, the second
// learns the parent's whole range and finishes it, so every node is finished exactly once, after
// both children. Node ids: internal i, leaf k -> (n - 1) + k. Traversal starts at node record 0,
// so the root's record goes there and internal node i's to record i + 1 (the root's own record
// slot holds a copy of it): n records. Collapsed subtrees become leaf ranges; records inside them
// are written too but never reached.
template <class ExecSpace, class MemorySpace>
void build_hierarchy(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
                     const MortonOrder<MemorySpace>& order, Bvh<MemorySpace>& bvh) {
  const int n = bvh.num_prims, ni = n - 1;  // n >= 2
  Kokkos::View<Aabb*, MemorySpace> box(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::boxes"), ni + n);
  Kokkos::View<Real*, MemorySpace> cost(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::cost"), ni + n);
  Kokkos::View<int* [2], MemorySpace> kids(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::children"), ni);
  Kokkos::View<int* [2], MemorySpace> range(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::range"), ni);
  Kokkos::View<int*, MemorySpace> handoff(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::handoff"), ni);
  Kokkos::deep_copy(space, handoff, -1);
  const auto codes = order.codes;
  const auto index = order.index;
  const auto tris = bvh.tris;
  const auto prim = bvh.prim;
  const auto nodes = bvh.nodes;
  Kokkos::parallel_for(
      "rtmini::bvh::build::hierarchy", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int k) {
        const int p = static_cast<int>(index(k));
        const Triangle t = input(p);
        tris(k) = t;
        prim(k) = p;
        const Aabb leaf_box = triangle_box(t);
        int node = ni + k, lo = k, hi = k;
        box(node) = leaf_box;
        cost(node) = leaf_box.surface_area();  // Ci = 1
        while (true) {
          const bool left_child = lo == 0 || (hi != ni && detail::split_level(codes, hi) <
                                                              detail::split_level(codes, lo - 1));
          const int parent = left_child ? hi : lo - 1;
          kids(parent, left_child ? 0 : 1) = node;
          Kokkos::memory_fence();
          const int other = Kokkos::atomic_exchange(&handoff(parent), left_child ? lo : hi);
          if (other < 0) return;  // the sibling finishes the parent
          Kokkos::memory_fence();
          if (left_child)
            hi = other;
          else
            lo = other;
          node = parent;
          range(node, 0) = lo;
          range(node, 1) = hi;
          const int l = kids(node, 0), r = kids(node, 1);
          Aabb nb = box(l);
          nb.expand(box(r));
          box(node) = nb;
          cost(node) = subtree_cost(nb.surface_area(), hi - lo + 1, cost(l), cost(r));
          BvhNode record;
          for (int s = 0; s < 2; ++s) {
            const int c = kids(node, s);
            std::uint32_t ref;
            if (c >= ni)
              ref = make_leaf(static_cast<std::uint32_t>(c - ni), 1);
            else if (math::signbit(cost(c)))
              ref = make_leaf(static_cast<std::uint32_t>(range(c, 0)),
                              static_cast<std::uint32_t>(range(c, 1) - range(c, 0) + 1));
            else
              ref = static_cast<std::uint32_t>(c + 1);
            record.set_child(s, box(c), ref);
          }
          nodes(node + 1) = record;
          if (lo == 0 && hi == ni) {
            nodes(0) = record;
            return;
          }
        }
      });
}

// Wall-clock seconds of the LBVH phases (each fenced), when a caller asks for them.
struct LbvhPhaseTimes {
  double bounds = 0, morton = 0, sort = 0, hierarchy = 0;
};

// Runs `phase` and, when `seconds` is given, adds its fenced wall time there.
template <class ExecSpace, class Fn>
void timed_phase(const ExecSpace& space, double* seconds, const Fn& phase) {
  if (!seconds) {
    phase();
    return;
  }
  Kokkos::Timer timer;
  phase();
  space.fence();
  *seconds += timer.seconds();
}

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build_lbvh(const ExecSpace& space,
                            Kokkos::View<const Triangle*, MemorySpace> input,
                            LbvhPhaseTimes* times = nullptr) {
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_lbvh");
  const int n = static_cast<int>(input.extent(0));
  Bvh<MemorySpace> bvh;
  bvh.num_prims = n;
  bvh.quality = BuildQuality::kLbvh;
  bvh.nodes = Kokkos::View<BvhNode*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::nodes"), n > 1 ? n : 1);
  bvh.tris = Kokkos::View<Triangle*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::tris"), n);
  bvh.prim = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::prim"), n);
  LbvhBounds bounds;
  if (n > 0) {
    timed_phase(space, times ? &times->bounds : nullptr,
                [&] { bounds = scene_and_centroid_bounds(space, input); });
    bvh.bounds = bounds.scene;
  }
  if (n == 1) {
    emit_single_leaf(space, input, bvh);
  } else if (n > 1) {
    MortonOrder<MemorySpace> order;
    timed_phase(space, times ? &times->morton : nullptr,
                [&] { order = morton_order(space, input, bounds.centroids); });
    timed_phase(space, times ? &times->sort : nullptr,
                [&] { compat::sort_by_key(space, order.codes, order.index); });
    timed_phase(space, times ? &times->hierarchy : nullptr,
                [&] { build_hierarchy(space, input, order, bvh); });
  }
  space.fence();
  Kokkos::Profiling::popRegion();
  return bvh;
}

}  // namespace rtmini::bvh
