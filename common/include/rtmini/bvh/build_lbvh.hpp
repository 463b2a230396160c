#pragma once
// Parallel linear BVH build on any Kokkos execution space:
// Morton codes of centroids -> sort -> Karras hierarchy ("Maximizing Parallelism
// in the Construction of BVHs, Octrees, and k-d Trees", HPG 2012) -> bottom-up
// boxes with atomic counters -> SAH-driven collapse of small subtrees into leaves
// (contiguous in Morton order, so a collapsed subtree is a plain index range).
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

// 30-bit Morton code (10 bits per axis) of a point in the unit cube. The sort
// key puts it above the 32-bit primitive index, so keys are unique and the
// Karras split search never meets equal keys.
KOKKOS_INLINE_FUNCTION std::uint64_t morton_key(const Vec3& unit, std::uint32_t index) {
  auto q = [](Real x) {
    const Real c = x < Real(0) ? Real(0) : (x > Real(1) ? Real(1) : x);
    return static_cast<std::uint64_t>(c * Real(1023));
  };
  const std::uint64_t m =
      spread_bits_21(q(unit.x)) << 2 | spread_bits_21(q(unit.y)) << 1 | spread_bits_21(q(unit.z));
  return m << 32 | index;
}

KOKKOS_INLINE_FUNCTION int clz64(std::uint64_t x) {
  int n = 0;
  if (x == 0) return 64;
  while (!(x & 0x8000000000000000ULL)) {
    x <<= 1;
    ++n;
  }
  return n;
}

template <class KeyView>
KOKKOS_INLINE_FUNCTION int delta(const KeyView& keys, int n, int i, int j) {
  if (j < 0 || j >= n) return -1;
  return clz64(keys(i) ^ keys(j));
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

// Morton keys of the centroids on the centroid box's grid, sorted.
template <class ExecSpace, class MemorySpace>
Kokkos::View<std::uint64_t*, MemorySpace> sorted_morton_keys(
    const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
    const Aabb& centroids) {
  const int n = static_cast<int>(input.extent(0));
  const Vec3 lo = centroids.lo, ext = centroids.hi - centroids.lo;
  const Vec3 inv_ext(ext.x > 0 ? 1 / ext.x : 0, ext.y > 0 ? 1 / ext.y : 0,
                     ext.z > 0 ? 1 / ext.z : 0);
  Kokkos::View<std::uint64_t*, MemorySpace> keys(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::keys"), n);
  Kokkos::parallel_for(
      "rtmini::bvh::build::morton", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int i) {
        const Triangle& t = input(i);
        const Vec3 c = (t.a + t.b + t.c) * (Real(1) / Real(3));
        keys(i) = detail::morton_key((c - lo) * inv_ext, static_cast<std::uint32_t>(i));
      });
  compat::sort(space, keys);
  return keys;
}

// The triangles and their ids in key order (the order leaves index).
template <class ExecSpace, class MemorySpace>
void reorder_by_keys(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
                     Kokkos::View<const std::uint64_t*, MemorySpace> keys, Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  auto prim = bvh.prim;
  Kokkos::parallel_for(
      "rtmini::bvh::build::reorder",
      Kokkos::RangePolicy<ExecSpace>(space, 0, static_cast<int>(keys.extent(0))),
      KOKKOS_LAMBDA(int i) {
        const int p = static_cast<int>(keys(i) & 0xffffffffULL);
        prim(i) = p;
        tris(i) = input(p);
      });
}

// A one-triangle tree: the root's second slot is empty.
template <class ExecSpace, class MemorySpace>
void emit_single_leaf(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  auto nodes = bvh.nodes;
  Kokkos::parallel_for(
      "rtmini::bvh::build::single", Kokkos::RangePolicy<ExecSpace>(space, 0, 1),
      KOKKOS_LAMBDA(int) {
        Aabb box;
        box.expand(tris(0).a);
        box.expand(tris(0).b);
        box.expand(tris(0).c);
        nodes(0).set_child(0, box, make_leaf(0, 1));
        nodes(0).set_child(1, Aabb(), kEmptyLeaf);
      });
}

// The binary radix tree over sorted keys (Karras 2012): internal node i covers sorted range
// [range(i, 0), range(i, 1)]; children are node ids, internal j -> j, leaf k -> (n - 1) + k.
template <class MemorySpace>
struct RadixTree {
  Kokkos::View<int*[2], MemorySpace> kids, range;
  Kokkos::View<int*, MemorySpace> parent;  // of every node id
};

template <class ExecSpace, class MemorySpace>
RadixTree<MemorySpace> karras_hierarchy(const ExecSpace& space,
                                        Kokkos::View<const std::uint64_t*, MemorySpace> keys) {
  const int n = static_cast<int>(keys.extent(0)), ni = n - 1;
  RadixTree<MemorySpace> tree;
  tree.kids = Kokkos::View<int* [2], MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::children"), ni);
  tree.range = Kokkos::View<int* [2], MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::range"), ni);
  tree.parent = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::parent"), ni + n);
  const auto kids = tree.kids;
  const auto range = tree.range;
  const auto parent = tree.parent;
  Kokkos::parallel_for(
      "rtmini::bvh::build::hierarchy", Kokkos::RangePolicy<ExecSpace>(space, 0, ni),
      KOKKOS_LAMBDA(int i) {
        const int d = detail::delta(keys, n, i, i + 1) > detail::delta(keys, n, i, i - 1) ? 1 : -1;
        const int dmin = detail::delta(keys, n, i, i - d);
        int lmax = 2;
        while (detail::delta(keys, n, i, i + lmax * d) > dmin) lmax *= 2;
        int l = 0;
        for (int t = lmax / 2; t >= 1; t /= 2)
          if (detail::delta(keys, n, i, i + (l + t) * d) > dmin) l += t;
        const int j = i + l * d;
        const int dnode = detail::delta(keys, n, i, j);
        int s = 0;
        for (int t = (l + 1) / 2;; t = (t + 1) / 2) {
          if (detail::delta(keys, n, i, i + (s + t) * d) > dnode) s += t;
          if (t == 1) break;
        }
        const int gamma = i + s * d + (d < 0 ? -1 : 0);
        const int first = i < j ? i : j, last = i < j ? j : i;
        const int left = first == gamma ? ni + gamma : gamma;
        const int right = last == gamma + 1 ? ni + gamma + 1 : gamma + 1;
        kids(i, 0) = left;
        kids(i, 1) = right;
        range(i, 0) = first;
        range(i, 1) = last;
        parent(left) = i;
        parent(right) = i;
      });
  return tree;
}

// Boxes and SAH costs of every node id, bottom up; the second child to arrive at a node
// finishes it (the first one stops), so every node is done exactly once. A negative cost marks
// a subtree cheaper as one leaf (the magnitude is the cost).
template <class MemorySpace>
struct SubtreeCosts {
  Kokkos::View<Aabb*, MemorySpace> box;
  Kokkos::View<Real*, MemorySpace> cost;
};

template <class ExecSpace, class MemorySpace>
SubtreeCosts<MemorySpace> refit_with_costs(const ExecSpace& space, const Bvh<MemorySpace>& bvh,
                                           const RadixTree<MemorySpace>& tree) {
  const int n = bvh.num_prims, ni = n - 1;
  SubtreeCosts<MemorySpace> out;
  out.box = Kokkos::View<Aabb*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::boxes"), ni + n);
  out.cost = Kokkos::View<Real*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::cost"), ni + n);
  Kokkos::View<int*, MemorySpace> arrivals("rtmini::bvh::build::arrivals", ni);
  const auto box = out.box;
  const auto cost = out.cost;
  const auto tris = bvh.tris;
  const auto kids = tree.kids;
  const auto range = tree.range;
  const auto parent = tree.parent;
  Kokkos::parallel_for(
      "rtmini::bvh::build::refit", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int k) {
        constexpr Real kTraversalCost = 1, kTriangleCost = 1;
        Aabb b;
        b.expand(tris(k).a);
        b.expand(tris(k).b);
        b.expand(tris(k).c);
        box(ni + k) = b;
        cost(ni + k) = kTriangleCost * b.surface_area();
        int node = parent(ni + k);
        Kokkos::memory_fence();
        while (true) {
          if (Kokkos::atomic_fetch_add(&arrivals(node), 1) == 0) break;
          Kokkos::memory_fence();
          const int l = kids(node, 0), r = kids(node, 1);
          Aabb nb = box(l);
          nb.expand(box(r));
          box(node) = nb;
          const Real sa = nb.surface_area();
          const int count = range(node, 1) - range(node, 0) + 1;
          const Real split = kTraversalCost * sa + math::fabs(cost(l)) + math::fabs(cost(r));
          const Real leaf = kTriangleCost * count * sa;
          cost(node) = (count <= kMaxLeafSize && leaf <= split) ? -leaf : split;
          Kokkos::memory_fence();
          if (node == 0) break;
          node = parent(node);
        }
      });
  return out;
}

// Traversal nodes. Collapsed subtrees become leaf ranges; nodes inside collapsed subtrees are
// written too but never reached.
template <class ExecSpace, class MemorySpace>
void emit_binary_nodes(const ExecSpace& space, const RadixTree<MemorySpace>& tree,
                       const SubtreeCosts<MemorySpace>& sub, Bvh<MemorySpace>& bvh) {
  const int ni = bvh.num_prims - 1;
  const auto nodes = bvh.nodes;
  const auto kids = tree.kids;
  const auto range = tree.range;
  const auto box = sub.box;
  const auto cost = sub.cost;
  Kokkos::parallel_for(
      "rtmini::bvh::build::emit", Kokkos::RangePolicy<ExecSpace>(space, 0, ni),
      KOKKOS_LAMBDA(int i) {
        for (int k = 0; k < 2; ++k) {
          const int c = kids(i, k);
          std::uint32_t ref;
          if (c >= ni) {
            ref = make_leaf(static_cast<std::uint32_t>(c - ni), 1);
          } else if (math::signbit(cost(c))) {
            ref = make_leaf(static_cast<std::uint32_t>(range(c, 0)),
                            static_cast<std::uint32_t>(range(c, 1) - range(c, 0) + 1));
          } else {
            ref = static_cast<std::uint32_t>(c);
          }
          nodes(i).set_child(k, box(c), ref);
        }
      });
}

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build_lbvh(const ExecSpace& space,
                            Kokkos::View<const Triangle*, MemorySpace> input) {
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_lbvh");
  const int n = static_cast<int>(input.extent(0));
  Bvh<MemorySpace> bvh;
  bvh.num_prims = n;
  bvh.quality = BuildQuality::kLbvh;
  bvh.nodes = Kokkos::View<BvhNode*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::nodes"), n > 1 ? n - 1 : 1);
  bvh.tris = Kokkos::View<Triangle*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::tris"), n);
  bvh.prim = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::prim"), n);
  if (n > 0) {
    const LbvhBounds bounds = scene_and_centroid_bounds(space, input);
    bvh.bounds = bounds.scene;
    const auto keys = sorted_morton_keys(space, input, bounds.centroids);
    reorder_by_keys<ExecSpace, MemorySpace>(space, input, keys, bvh);
    if (n == 1) {
      emit_single_leaf(space, bvh);
    } else {
      const auto tree = karras_hierarchy<ExecSpace, MemorySpace>(space, keys);
      const auto sub = refit_with_costs(space, bvh, tree);
      emit_binary_nodes(space, tree, sub, bvh);
    }
    space.fence();
  }
  Kokkos::Profiling::popRegion();
  return bvh;
}

}  // namespace rtmini::bvh
