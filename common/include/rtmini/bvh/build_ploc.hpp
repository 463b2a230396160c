#pragma once
// SAH-quality BVH build on any Kokkos execution space: PLOC (Meister & Bittner, "Parallel
// Locally-Ordered Clustering for Bounding Volume Hierarchy Construction", TVCG 2018). The
// triangles start as one cluster each, in Morton order (the LBVH's front end); every round each
// cluster finds its nearest neighbour among the kRadius clusters on either side (the one whose
// merged box has the smallest surface area), mutual neighbours merge into a new node at the
// lower position, and the survivors are compacted, keeping Morton order. Rounds repeat until one
// cluster is left. Each round's new nodes then restructure their treelets (treelet.hpp, Karras &
// Aila 2013): on the bunny the SAH cost drops from +10.7 % to +8.2 % of the host SAH build's, on
// the dragon from +5.7 % to +2.3 % (results/bvh/ploc_treelets.md). Subtrees cheaper as one leaf
// collapse into leaves (the LBVH's SAH rule), and the triangles are laid out in depth-first order
// so each leaf is an index range: the result has the LBVH's binary layout, so traversal and the
// wide collapses take it unchanged.
#include <string>

#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/treelet.hpp"

namespace rtmini::bvh {

// Clusters searched on either side (the paper's r; 16 gives near-sweep-SAH trees).
inline constexpr int kPlocRadius = 16;

namespace detail {

// Whether merging with candidate j (merged area `area`) beats the best so far for cluster i.
// Ties go to the pair with the smaller (min, max) positions: one total order over all pairs, so
// the globally closest pair is always mutual and every round merges at least once.
KOKKOS_INLINE_FUNCTION bool closer_pair(Real area, int i, int j, Real best_area, int best) {
  if (best < 0 || area < best_area) return true;
  if (best_area < area) return false;
  const int lo_j = i < j ? i : j, hi_j = i < j ? j : i;
  const int lo_b = i < best ? i : best, hi_b = i < best ? best : i;
  return lo_j < lo_b || (lo_j == lo_b && hi_j < hi_b);
}

}  // namespace detail

// Per-node build state; ids as in the LBVH: internal nodes 0 .. n - 2 (root 0), leaf k (sorted
// position k) -> (n - 1) + k.
template <class MemorySpace>
struct PlocNodes {
  Kokkos::View<Aabb*, MemorySpace> box;
  Kokkos::View<Real*, MemorySpace> cost;  // negative: cheaper as one leaf
  Kokkos::View<int*, MemorySpace> count, parent;
  Kokkos::View<int* [2], MemorySpace> kids;
};

template <class ExecSpace, class MemorySpace>
PlocNodes<MemorySpace> ploc_leaves(const ExecSpace& space,
                                   Kokkos::View<const Triangle*, MemorySpace> input,
                                   const MortonOrder<MemorySpace>& order) {
  const int n = static_cast<int>(input.extent(0)), ni = n - 1;
  PlocNodes<MemorySpace> out;
  auto alloc = [](const std::string& label) {
    return Kokkos::view_alloc(Kokkos::WithoutInitializing, label);
  };
  out.box = Kokkos::View<Aabb*, MemorySpace>(alloc("rtmini::bvh::ploc::box"), ni + n);
  out.cost = Kokkos::View<Real*, MemorySpace>(alloc("rtmini::bvh::ploc::cost"), ni + n);
  out.count = Kokkos::View<int*, MemorySpace>(alloc("rtmini::bvh::ploc::count"), ni + n);
  out.parent = Kokkos::View<int*, MemorySpace>(alloc("rtmini::bvh::ploc::parent"), ni + n);
  out.kids = Kokkos::View<int* [2], MemorySpace>(alloc("rtmini::bvh::ploc::kids"), ni);
  const auto box = out.box;
  const auto cost = out.cost;
  const auto count = out.count;
  const auto index = order.index;
  Kokkos::parallel_for(
      "rtmini::bvh::ploc::leaves", Kokkos::RangePolicy<ExecSpace>(space, 0, n),
      KOKKOS_LAMBDA(int k) {
        const Aabb b = triangle_box(input(index(k)));
        box(ni + k) = b;
        cost(ni + k) = b.surface_area();  // Ci = 1
        count(ni + k) = 1;
      });
  return out;
}

// The clustering rounds. Each round: nearest neighbours; then one scan counts, per position, the
// merges (new node ids, handed out downwards from n - 2 so the last merge is the root, 0) and the
// survivors (their new positions); then the merge-and-compact pass.
template <class ExecSpace, class MemorySpace>
void ploc_cluster(const ExecSpace& space, const PlocNodes<MemorySpace>& nodes_in, int n,
                  int* rounds) {
  using Policy = Kokkos::RangePolicy<ExecSpace>;
  const int ni = n - 1;
  auto alloc = [](const std::string& label) {
    return Kokkos::view_alloc(Kokkos::WithoutInitializing, label);
  };
  Kokkos::View<int*, MemorySpace> cur(alloc("rtmini::bvh::ploc::clusters"), n);
  Kokkos::View<int*, MemorySpace> next(alloc("rtmini::bvh::ploc::next"), n);
  Kokkos::View<Aabb*, MemorySpace> cur_box(alloc("rtmini::bvh::ploc::cluster_box"), n);
  Kokkos::View<Aabb*, MemorySpace> next_box(alloc("rtmini::bvh::ploc::next_box"), n);
  Kokkos::View<int*, MemorySpace> nn(alloc("rtmini::bvh::ploc::neighbour"), n);
  Kokkos::View<std::uint64_t*, MemorySpace> slots(alloc("rtmini::bvh::ploc::slots"), n);
  const PlocNodes<MemorySpace> nodes = nodes_in;
  Kokkos::parallel_for(
      "rtmini::bvh::ploc::start", Policy(space, 0, n), KOKKOS_LAMBDA(int i) {
        cur(i) = ni + i;
        cur_box(i) = nodes.box(ni + i);
      });
  int clusters = n, next_id = ni - 1;
  *rounds = 0;
  while (clusters > 1) {
    const int c = clusters;
    Kokkos::parallel_for(
        "rtmini::bvh::ploc::nearest", Policy(space, 0, c), KOKKOS_LAMBDA(int i) {
          const Aabb bi = cur_box(i);
          const int lo = i - kPlocRadius < 0 ? 0 : i - kPlocRadius;
          const int hi = i + kPlocRadius >= c ? c - 1 : i + kPlocRadius;
          int best = -1;
          Real best_area = 0;
          for (int j = lo; j <= hi; ++j) {
            if (j == i) continue;
            Aabb m = bi;
            m.expand(cur_box(j));
            const Real area = m.surface_area();
            if (detail::closer_pair(area, i, j, best_area, best)) {
              best = j;
              best_area = area;
            }
          }
          nn(i) = best;
        });
    // Per position: merges (high 32 bits) and survivors (low) before it.
    std::uint64_t totals = 0;
    Kokkos::parallel_scan(
        "rtmini::bvh::ploc::slots", Policy(space, 0, c),
        KOKKOS_LAMBDA(int i, std::uint64_t& running, bool final) {
          const int j = nn(i);
          const bool mutual = nn(j) == i;
          const std::uint64_t v =
              (mutual && i < j ? std::uint64_t(1) << 32 : 0) + (mutual && i > j ? 0 : 1);
          if (final) slots(i) = running;
          running += v;
        },
        totals);
    const int first_id = next_id;
    Kokkos::parallel_for(
        "rtmini::bvh::ploc::merge", Policy(space, 0, c), KOKKOS_LAMBDA(int i) {
          const int j = nn(i);
          const bool mutual = nn(j) == i;
          if (mutual && i > j) return;  // merged into j's new node
          const std::uint64_t s = slots(i);
          const int pos = static_cast<int>(s & 0xffffffffu);
          if (!mutual) {
            next(pos) = cur(i);
            next_box(pos) = cur_box(i);
            return;
          }
          const int id = first_id - static_cast<int>(s >> 32);
          const int l = cur(i), r = cur(j);
          Aabb b = cur_box(i);
          b.expand(cur_box(j));
          const int count = nodes.count(l) + nodes.count(r);
          nodes.kids(id, 0) = l;
          nodes.kids(id, 1) = r;
          nodes.parent(l) = id;
          nodes.parent(r) = id;
          nodes.box(id) = b;
          nodes.count(id) = count;
          nodes.cost(id) = subtree_cost(b.surface_area(), count, nodes.cost(l), nodes.cost(r));
          next(pos) = id;
          next_box(pos) = b;
        });
    const int merges = static_cast<int>(totals >> 32);
    // The round's new nodes (ids first_id - merges + 1 .. first_id) have final subtrees, built
    // in earlier rounds, and no two share a descendant: their treelets restructure in parallel.
    Kokkos::parallel_for(
        "rtmini::bvh::ploc::treelets", Policy(space, first_id - merges + 1, first_id + 1),
        KOKKOS_LAMBDA(int id) { restructure_treelet(nodes, id, ni); });
    next_id -= merges;
    clusters = static_cast<int>(totals & 0xffffffffu);
    std::swap(cur, next);
    std::swap(cur_box, next_box);
    ++*rounds;
  }
  space.fence();
}

// The triangles in depth-first (left first) order and the node records. A node's first triangle
// is the sum of the counts of the left siblings of it and its ancestors (a walk to the root);
// internal node v's record is v. Returns the depth of the deepest internal node.
template <class ExecSpace, class MemorySpace>
int ploc_emit(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> input,
              const MortonOrder<MemorySpace>& order, const PlocNodes<MemorySpace>& nodes,
              Bvh<MemorySpace>& bvh) {
  const int n = bvh.num_prims, ni = n - 1;
  const auto out_nodes = bvh.nodes;
  const auto tris = bvh.tris;
  const auto prim = bvh.prim;
  const auto index = order.index;
  const auto box = nodes.box;
  const auto cost = nodes.cost;
  const auto count = nodes.count;
  const auto parent = nodes.parent;
  const auto kids = nodes.kids;
  int depth = 0;
  Kokkos::parallel_reduce(
      "rtmini::bvh::ploc::emit", Kokkos::RangePolicy<ExecSpace>(space, 0, ni),
      KOKKOS_LAMBDA(int v, int& deepest) {
        int first = 0, d = 0;
        for (int u = v; u != 0; ++d) {
          const int p = parent(u);
          if (kids(p, 1) == u) first += count(kids(p, 0));
          u = p;
        }
        if (d > deepest) deepest = d;
        BvhNode record;
        for (int s = 0; s < 2; ++s) {
          const int c = kids(v, s);
          std::uint32_t ref;
          if (c >= ni) {
            const int t = static_cast<int>(index(c - ni));
            tris(first) = input(t);
            prim(first) = t;
            ref = make_leaf(static_cast<std::uint32_t>(first), 1);
          } else if (math::signbit(cost(c))) {
            ref =
                make_leaf(static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(count(c)));
          } else {
            ref = static_cast<std::uint32_t>(c);
          }
          record.set_child(s, box(c), ref);
          first += count(c);
        }
        out_nodes(v) = record;
      },
      Kokkos::Max<int>(depth));
  return depth;
}

// Wall-clock seconds of the PLOC phases (each fenced) and its rounds, when a caller asks.
struct PlocPhaseTimes {
  double front = 0;  // bounds, Morton codes and sort (the LBVH's)
  double cluster = 0, emit = 0;
  int rounds = 0;
};

// Falls back to the LBVH (and says so in quality) when the tree is deeper than traversal's
// stack allows (kStackSize; never seen on real meshes).
template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build_ploc(const ExecSpace& space,
                            Kokkos::View<const Triangle*, MemorySpace> input,
                            PlocPhaseTimes* times = nullptr) {
  const int n = static_cast<int>(input.extent(0));
  if (n < 2) return build_lbvh<ExecSpace, MemorySpace>(space, input);
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_ploc");
  Bvh<MemorySpace> bvh;
  bvh.num_prims = n;
  bvh.quality = BuildQuality::kPloc;
  bvh.nodes = Kokkos::View<BvhNode*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::nodes"), n - 1);
  bvh.tris = Kokkos::View<Triangle*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::tris"), n);
  bvh.prim = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::prim"), n);
  MortonOrder<MemorySpace> order;
  timed_phase(space, times ? &times->front : nullptr, [&] {
    const LbvhBounds bounds = scene_and_centroid_bounds(space, input);
    bvh.bounds = bounds.scene;
    order = morton_order(space, input, bounds.centroids);
    compat::sort_by_key(space, order.codes, order.index);
  });
  PlocNodes<MemorySpace> nodes;
  int rounds = 0, depth = 0;
  timed_phase(space, times ? &times->cluster : nullptr, [&] {
    nodes = ploc_leaves(space, input, order);
    ploc_cluster(space, nodes, n, &rounds);
  });
  timed_phase(space, times ? &times->emit : nullptr,
              [&] { depth = ploc_emit(space, input, order, nodes, bvh); });
  if (times) times->rounds += rounds;
  space.fence();
  Kokkos::Profiling::popRegion();
  if (depth + 1 >= kStackSize) return build_lbvh<ExecSpace, MemorySpace>(space, input);
  return bvh;
}

}  // namespace rtmini::bvh
