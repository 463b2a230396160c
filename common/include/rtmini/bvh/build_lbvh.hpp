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

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build_lbvh(const ExecSpace& space,
                            Kokkos::View<const Triangle*, MemorySpace> input) {
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_lbvh");
  using Policy = Kokkos::RangePolicy<ExecSpace>;
  const int n = static_cast<int>(input.extent(0));
  Bvh<MemorySpace> bvh;
  bvh.num_prims = n;
  bvh.quality = BuildQuality::kLbvh;
  const int num_nodes = n > 1 ? n - 1 : 1;
  bvh.nodes = Kokkos::View<BvhNode*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::nodes"), num_nodes);
  bvh.tris = Kokkos::View<Triangle*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::tris"), n);
  bvh.prim = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::prim"), n);
  if (n == 0) {
    Kokkos::Profiling::popRegion();
    return bvh;
  }

  // 1. Scene and centroid bounds.
  Real cmin[3], cmax[3], smin[3], smax[3];
  for (int a = 0; a < 3; ++a) {
    Kokkos::parallel_reduce(
        "rtmini::bvh::build::centroid_min", Policy(space, 0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Triangle& t = input(i);
          const Real c = (t.a[a] + t.b[a] + t.c[a]) / Real(3);
          if (c < m) m = c;
        },
        Kokkos::Min<Real>(cmin[a]));
    Kokkos::parallel_reduce(
        "rtmini::bvh::build::centroid_max", Policy(space, 0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Triangle& t = input(i);
          const Real c = (t.a[a] + t.b[a] + t.c[a]) / Real(3);
          if (c > m) m = c;
        },
        Kokkos::Max<Real>(cmax[a]));
    Kokkos::parallel_reduce(
        "rtmini::bvh::build::bounds_min", Policy(space, 0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Triangle& t = input(i);
          m = math::fmin(m, math::fmin(t.a[a], math::fmin(t.b[a], t.c[a])));
        },
        Kokkos::Min<Real>(smin[a]));
    Kokkos::parallel_reduce(
        "rtmini::bvh::build::bounds_max", Policy(space, 0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Triangle& t = input(i);
          m = math::fmax(m, math::fmax(t.a[a], math::fmax(t.b[a], t.c[a])));
        },
        Kokkos::Max<Real>(smax[a]));
  }
  bvh.bounds.lo = Vec3(smin[0], smin[1], smin[2]);
  bvh.bounds.hi = Vec3(smax[0], smax[1], smax[2]);
  const Vec3 lo(cmin[0], cmin[1], cmin[2]);
  const Vec3 ext(cmax[0] - cmin[0], cmax[1] - cmin[1], cmax[2] - cmin[2]);
  const Vec3 inv_ext(ext.x > 0 ? 1 / ext.x : 0, ext.y > 0 ? 1 / ext.y : 0,
                     ext.z > 0 ? 1 / ext.z : 0);

  // 2. Morton keys, sorted.
  Kokkos::View<std::uint64_t*, MemorySpace> keys(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::keys"), n);
  Kokkos::parallel_for(
      "rtmini::bvh::build::morton", Policy(space, 0, n), KOKKOS_LAMBDA(int i) {
        const Triangle& t = input(i);
        const Vec3 c = (t.a + t.b + t.c) * (Real(1) / Real(3));
        keys(i) = detail::morton_key((c - lo) * inv_ext, static_cast<std::uint32_t>(i));
      });
  compat::sort(space, keys);

  auto tris = bvh.tris;
  auto prim = bvh.prim;
  auto nodes = bvh.nodes;
  Kokkos::parallel_for(
      "rtmini::bvh::build::reorder", Policy(space, 0, n), KOKKOS_LAMBDA(int i) {
        const int p = static_cast<int>(keys(i) & 0xffffffffULL);
        prim(i) = p;
        tris(i) = input(p);
      });

  if (n == 1) {
    Kokkos::parallel_for(
        "rtmini::bvh::build::single", Policy(space, 0, 1), KOKKOS_LAMBDA(int) {
          Aabb box;
          box.expand(tris(0).a);
          box.expand(tris(0).b);
          box.expand(tris(0).c);
          nodes(0).set_child(0, box, make_leaf(0, 1));
          nodes(0).set_child(1, Aabb(), kEmptyLeaf);
        });
    space.fence();
    Kokkos::Profiling::popRegion();
    return bvh;
  }

  // 3. Karras hierarchy: internal node i covers sorted range [first, last].
  // Children are encoded as node ids: internal j -> j, leaf k -> (n - 1) + k.
  const int ni = n - 1;
  Kokkos::View<int* [2], MemorySpace> kids(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::children"), ni);
  Kokkos::View<int* [2], MemorySpace> range(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::range"), ni);
  Kokkos::View<int*, MemorySpace> parent(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::parent"), ni + n);
  Kokkos::parallel_for(
      "rtmini::bvh::build::hierarchy", Policy(space, 0, ni), KOKKOS_LAMBDA(int i) {
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

  // 4. Bottom-up boxes and SAH costs; the second child to arrive at a node
  // finishes it (the first one stops), so every node is done exactly once.
  Kokkos::View<Aabb*, MemorySpace> box(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::boxes"), ni + n);
  Kokkos::View<Real*, MemorySpace> cost(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::cost"), ni + n);
  Kokkos::View<int*, MemorySpace> arrivals("rtmini::bvh::build::arrivals", ni);
  Kokkos::parallel_for(
      "rtmini::bvh::build::refit", Policy(space, 0, n), KOKKOS_LAMBDA(int k) {
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
          // A negative cost marks "collapse into one leaf" (the magnitude is the cost).
          cost(node) = (count <= kMaxLeafSize && leaf <= split) ? -leaf : split;
          Kokkos::memory_fence();
          if (node == 0) break;
          node = parent(node);
        }
      });

  // 5. Emit traversal nodes. Collapsed subtrees become leaf ranges; nodes
  // inside collapsed subtrees are written too but never reached.
  Kokkos::parallel_for(
      "rtmini::bvh::build::emit", Policy(space, 0, ni), KOKKOS_LAMBDA(int i) {
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
          const Aabb cb = box(c);
          nodes(i).set_child(k, cb, ref);
        }
      });
  space.fence();
  Kokkos::Profiling::popRegion();
  return bvh;
}

}  // namespace rtmini::bvh
