#pragma once
// Parallel linear BVH build on any Kokkos execution space, in four passes: scene and centroid
// bounds (one fused reduction) -> Morton codes of the centroids -> sort by code -> hierarchy,
// boxes, SAH-driven collapse of small subtrees into leaves and the node records, all in one
// bottom-up pass (Apetrei, "Fast and Simple Agglomerative LBVH Construction", 2014): each
// triangle's thread climbs while it is the second child to arrive at a node. The tree is
// Karras' radix tree over the sorted codes (HPG 2012), built without its top-down split search.
// Collapsed subtrees are contiguous in Morton order, so a leaf is a plain index range.
#include <Kokkos_Timer.hpp>
#include <algorithm>

#include "rtmini/bvh/bvh.hpp"
#include "rtmini/bvh/scratch_arena.hpp"

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

// Bits of a Morton code (10 per axis in the classic code).
inline constexpr int kMortonBits = 30;

// 30-bit Morton code (10 bits per axis) of a point in the unit cube.
KOKKOS_INLINE_FUNCTION std::uint32_t morton_code(const Vec3& unit) {
  auto q = [](Real x) {
    const Real c = x < Real(0) ? Real(0) : (x > Real(1) ? Real(1) : x);
    return static_cast<std::uint64_t>(c * Real(1023));
  };
  return static_cast<std::uint32_t>(spread_bits_21(q(unit.x)) << 2 |
                                    spread_bits_21(q(unit.y)) << 1 | spread_bits_21(q(unit.z)));
}

// Spreads the low bits of `value` onto the set bits of `mask`, lowest first (a software
// parallel bit deposit): the code bits one axis owns in an adaptive Morton code.
KOKKOS_INLINE_FUNCTION std::uint32_t deposit_bits(std::uint32_t value, std::uint32_t mask) {
  std::uint32_t out = 0;
  for (std::uint32_t bit = 1; mask != 0u; bit <<= 1) {
    const std::uint32_t lowest = mask & (~mask + 1u);
    if (value & bit) out |= lowest;
    mask &= mask - 1u;
  }
  return out;
}

// The 30 code bits shared out among the axes so that the grid's cells are as near cubes as the
// bits allow (Vinkler, Bittner, Havran, "Extended Morton codes for high performance bounding
// volume hierarchy construction", HPG 2017): each bit in turn goes to the axis whose cell is
// then the longest (ties to x, then y), and the long axes' extra bits go on top. The classic
// code gives every axis 10 bits of its own extent, so on a flat scene (a building of rooms:
// 25 x 3 x 25) a cell is 8 times taller than wide and the splits below the rooms' level cut
// floors and walls into thin slabs; here that scene's x and z take 11 bits, y 8. Only on scenes
// this flat (kAdaptiveMortonAspect); elsewhere, and whenever every axis gets 10 bits, the codes
// are bit for bit the classic ones.
struct MortonAxes {
  std::uint32_t mask[3] = {0u, 0u, 0u};  // the code bits of x, y and z
  int bits[3] = {0, 0, 0};
  bool classic = true;  // 10 bits each, interleaved x, y, z from the top: morton_code()
};

// Below this ratio of the longest extent to the shortest, the classic code stays: on the bundled
// meshes of ratio 2-3 (dragon, teapot, cow) the adaptive one built trees of 2-4 % higher SAH
// cost (results/bake/distributed.md, eighth round); the rooms scene gains from 8 rooms (5.8) on.
inline constexpr double kAdaptiveMortonAspect = 4.0;

inline MortonAxes morton_axes(const Vec3& extent) {
  MortonAxes axes;
  for (int a = 0; a < 3; ++a) {
    axes.mask[a] = std::uint32_t(spread_bits_21(0x3ffu) << (2 - a));
    axes.bits[a] = 10;
  }
  double cell[3] = {double(extent.x), double(extent.y), double(extent.z)};
  const double longest = std::max(cell[0], std::max(cell[1], cell[2]));
  const double shortest = std::min(cell[0], std::min(cell[1], cell[2]));
  if (!(longest > kAdaptiveMortonAspect * shortest)) return axes;
  axes = MortonAxes{};
  for (int b = 0; b < 30; ++b) {  // how many bits each axis gets
    int a = 0;
    for (int k = 1; k < 3; ++k)
      if (cell[k] > cell[a]) a = k;
    ++axes.bits[a];
    cell[a] *= 0.5;
  }
  // Where they go: the axes with the most bits left first (ties x, y, z), so the extra bits of
  // the long axes come on top and the rest is the classic interleave.
  int left[3] = {axes.bits[0], axes.bits[1], axes.bits[2]};
  for (int b = 29; b >= 0; --b) {
    int a = 0;
    for (int k = 1; k < 3; ++k)
      if (left[k] > left[a]) a = k;
    axes.mask[a] |= 1u << b;
    --left[a];
  }
  for (int a = 0; a < 3; ++a)
    axes.classic = axes.classic && axes.mask[a] == std::uint32_t(spread_bits_21(0x3ffu) << (2 - a));
  return axes;
}

// The adaptive code of a point in the unit cube (each axis scaled by its own extent).
KOKKOS_INLINE_FUNCTION std::uint32_t adaptive_morton_code(const Vec3& unit,
                                                          const MortonAxes& axes) {
  const Real u[3] = {unit.x, unit.y, unit.z};
  std::uint32_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const Real c = u[a] < Real(0) ? Real(0) : (u[a] > Real(1) ? Real(1) : u[a]);
    const Real top = Real((std::uint64_t(1) << axes.bits[a]) - 1u);
    code |= deposit_bits(static_cast<std::uint32_t>(c * top), axes.mask[a]);
  }
  return code;
}

// Triangles whose box is longer, on some axis, than this fraction of the centroid box's longest
// side sort before all others (kSmallTriangleBit): the tree's top split sets them apart, as an
// SAH build would, instead of leaving them in the leaf of their centroid's cell, where their box
// (a lamp over a whole building of rooms, say) widens every box above it to their size, and
// every ray that starts in the building then visits that chain of nodes.
inline constexpr Real kLargeTriangleFraction = Real(0.25);
// Above the 30 bits of the code: set for every triangle that is not large. When none is large,
// or all are, every code has the same top bit and the tree is the one of the code alone.
inline constexpr std::uint32_t kSmallTriangleBit = 1u << 30;
// The bits the sort must order: the code's and the small-triangle bit above them.
inline constexpr int kSortKeyBits = kMortonBits + 1;
static_assert(kSmallTriangleBit == 1u << (kSortKeyBits - 1), "the sort covers the top bit");

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

// The triangles' Morton codes on the centroid box's grid (adaptive: MortonAxes; large triangles
// first: kSmallTriangleBit), sorted, and the input index of each (ascending among equal codes).
template <class MemorySpace>
struct MortonOrder {
  Kokkos::View<std::uint32_t*, MemorySpace> codes, index;
};

// Each triangle's Morton code on the centroid box's grid and its own index (the order before the
// sort). `reset`, where given, is set to all ones in the same pass (the LBVH hierarchy pass's
// exchange slots, kNoHandoff: one kernel launch fewer than a deep_copy).
template <class ExecSpace, class MemorySpace>
void write_morton_codes(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
                        const Aabb& centroids, Kokkos::View<std::uint32_t*, MemorySpace> codes,
                        Kokkos::View<std::uint32_t*, MemorySpace> index,
                        Kokkos::View<std::uint64_t*, MemorySpace> reset) {
  const int n = static_cast<int>(input.extent(0));
  const int nr = static_cast<int>(reset.extent(0));
  const Vec3 lo = centroids.lo, ext = centroids.hi - centroids.lo;
  const Vec3 inv_ext(ext.x > 0 ? 1 / ext.x : 0, ext.y > 0 ? 1 / ext.y : 0,
                     ext.z > 0 ? 1 / ext.z : 0);
  const detail::MortonAxes axes = detail::morton_axes(ext);
  const Real large_side =
      detail::kLargeTriangleFraction * math::fmax(ext.x, math::fmax(ext.y, ext.z));
  Kokkos::parallel_for(
      "rtmini::bvh::build::morton", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int i) {
        const Triangle& t = input(i);
        const Vec3 c = (t.a + t.b + t.c) * (Real(1) / Real(3));
        const Vec3 unit = (c - lo) * inv_ext;
        const std::uint32_t code =
            axes.classic ? detail::morton_code(unit) : detail::adaptive_morton_code(unit, axes);
        const Vec3 side = vmax(t.a, vmax(t.b, t.c)) - vmin(t.a, vmin(t.b, t.c));
        const bool large = math::fmax(side.x, math::fmax(side.y, side.z)) > large_side;
        codes(i) = code | (large ? 0u : detail::kSmallTriangleBit);
        index(i) = static_cast<std::uint32_t>(i);
        if (i < nr) reset(i) = ~std::uint64_t(0);
      });
}

// The unsorted codes and order in arrays of their own (the PLOC builder's).
template <class ExecSpace, class MemorySpace>
MortonOrder<MemorySpace> morton_order(const ExecSpace& space,
                                      Kokkos::View<const Triangle*, MemorySpace> input,
                                      const Aabb& centroids) {
  const int n = static_cast<int>(input.extent(0));
  MortonOrder<MemorySpace> out;
  out.codes = Kokkos::View<std::uint32_t*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::codes"), n);
  out.index = Kokkos::View<std::uint32_t*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::order"), n);
  write_morton_codes(space, input, centroids, out.codes, out.index,
                     Kokkos::View<std::uint64_t*, MemorySpace>());
  return out;
}

// The temporaries of one LBVH build in one allocation (scratch_arena.hpp): the Morton codes and
// triangle order twice (the radix sort ping-pongs between the halves; compat::sort_pairs) and the
// sort's own storage, then the hierarchy pass's per-node arrays (boxes and costs of all 2n - 1
// nodes, the exchange slots of the n - 1 internal ones).
template <class MemorySpace>
struct LbvhScratch {
  Kokkos::View<std::uint32_t*, MemorySpace> codes[2], index[2];
  Kokkos::View<unsigned char*, MemorySpace> sort_temp;
  Kokkos::View<Aabb*, MemorySpace> box;
  Kokkos::View<Real*, MemorySpace> cost;
  Kokkos::View<std::uint64_t*, MemorySpace> handoff;

  LbvhScratch(int n, std::size_t sort_bytes) {
    const int ni = n - 1;
    for (int half = 0; half < 2; ++half) {
      arena_.add(codes[half], n);
      arena_.add(index[half], n);
    }
    arena_.add(sort_temp, sort_bytes);
    arena_.add(box, ni + n);
    arena_.add(cost, ni + n);
    arena_.add(handoff, ni);
    arena_.allocate("rtmini::bvh::build::lbvh_scratch");
  }
  LbvhScratch(const LbvhScratch&) = delete;  // the arena points the members above
  LbvhScratch& operator=(const LbvhScratch&) = delete;

 private:
  ScratchArena<MemorySpace> arena_;
};

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

// The exchange slot of an internal node: the first child to arrive leaves its node id (high 32
// bits) and its range's outer end (low 32 bits); the second takes both in the same atomic
// exchange, so it needs no children array and no load of one before the sibling's box.
inline constexpr std::uint64_t kNoHandoff = ~std::uint64_t(0);

KOKKOS_INLINE_FUNCTION std::uint64_t pack_handoff(int node, int end) {
  return std::uint64_t(static_cast<std::uint32_t>(node)) << 32 | static_cast<std::uint32_t>(end);
}

// A node record's reference to child `c` covering sorted positions [lo, hi]: a one-triangle
// leaf, a leaf range where the subtree is cheaper as one leaf (negative cost), else internal
// node c's record.
KOKKOS_INLINE_FUNCTION std::uint32_t child_reference(int c, int lo, int hi, Real cost, int ni) {
  if (c >= ni) return make_leaf(static_cast<std::uint32_t>(c - ni), 1);
  if (math::signbit(cost))
    return make_leaf(static_cast<std::uint32_t>(lo), static_cast<std::uint32_t>(hi - lo + 1));
  return static_cast<std::uint32_t>(c + 1);
}

// The hierarchy, boxes, costs and node records in one bottom-up pass. Internal node i is the
// split between sorted positions i and i + 1; a node covering [lo, hi] hangs below whichever of
// its bounding splits (lo - 1 or hi) is lower in the tree. Its thread writes its box and cost,
// then swaps its id and outer end into the parent's slot: the first to arrive stops there, the
// second learns its sibling and the parent's whole range and finishes it, so every node is
// finished exactly once, after both children. Parent i's children cover [lo, i] and [i + 1, hi],
// so a collapsed child's leaf range needs no array either. Node ids: internal i, leaf k ->
// (n - 1) + k. Traversal starts at node record 0, so the root's record goes there and internal
// node i's to record i + 1 (the root's own record slot holds a copy of it): n records. Collapsed
// subtrees become leaf ranges; records inside them are written too but never reached.
// The climbing thread reloads its own child's box and cost beside the sibling's rather than
// carrying them in registers: on sm_90 this kernel needs 32 registers (64 warps per SM; it is
// bound by the latency of each step), the register-carrying version of b9a7b46 took 38.
// The scratch's exchange slots must hold kNoHandoff (write_morton_codes resets them).
template <class ExecSpace, class MemorySpace>
void build_hierarchy(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
                     const MortonOrder<MemorySpace>& order, const LbvhScratch<MemorySpace>& scratch,
                     Bvh<MemorySpace>& bvh) {
  const int n = bvh.num_prims, ni = n - 1;  // n >= 2
  const auto box = scratch.box;
  const auto cost = scratch.cost;
  const auto handoff = scratch.handoff;
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
          Kokkos::memory_fence();
          const std::uint64_t other =
              Kokkos::atomic_exchange(&handoff(parent), pack_handoff(node, left_child ? lo : hi));
          if (other == kNoHandoff) return;  // the sibling finishes the parent
          Kokkos::memory_fence();
          const int sibling = static_cast<int>(other >> 32);
          const int end = static_cast<int>(other & 0xffffffffu);
          const int l = left_child ? node : sibling, r = left_child ? sibling : node;
          if (left_child)
            hi = end;
          else
            lo = end;
          node = parent;
          const Aabb lb = box(l), rb = box(r);
          const Real lc = cost(l), rc = cost(r);
          Aabb nb = lb;
          nb.expand(rb);
          box(node) = nb;
          cost(node) = subtree_cost(nb.surface_area(), hi - lo + 1, lc, rc);
          BvhNode record;
          record.set_child(0, lb, child_reference(l, lo, node, lc, ni));
          record.set_child(1, rb, child_reference(r, node + 1, hi, rc, ni));
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
  {  // the tree's own three arrays in one allocation, which bvh.storage keeps
    ScratchArena<MemorySpace> arena;
    arena.add(bvh.nodes, n > 1 ? n : 1);
    arena.add(bvh.tris, n);
    arena.add(bvh.prim, n);
    bvh.storage = arena.allocate("rtmini::bvh::lbvh");
  }
  LbvhBounds bounds;
  if (n > 0) {
    timed_phase(space, times ? &times->bounds : nullptr,
                [&] { bounds = scene_and_centroid_bounds(space, input); });
    bvh.bounds = bounds.scene;
  }
  if (n == 1) {
    emit_single_leaf(space, input, bvh);
  } else if (n > 1) {
    const LbvhScratch<MemorySpace> scratch(
        n, compat::sort_pairs_temp_bytes<ExecSpace>(n, detail::kSortKeyBits));
    timed_phase(space, times ? &times->morton : nullptr, [&] {
      write_morton_codes(space, input, bounds.centroids, scratch.codes[0], scratch.index[0],
                         scratch.handoff);
    });
    MortonOrder<MemorySpace> order;
    timed_phase(space, times ? &times->sort : nullptr, [&] {
      const int half = compat::sort_pairs(space, scratch.codes, scratch.index, scratch.sort_temp,
                                          detail::kSortKeyBits);
      order = {scratch.codes[half], scratch.index[half]};
    });
    timed_phase(space, times ? &times->hierarchy : nullptr,
                [&] { build_hierarchy(space, input, order, scratch, bvh); });
  }
  space.fence();
  Kokkos::Profiling::popRegion();
  return bvh;
}

}  // namespace rtmini::bvh
