#pragma once
// The Chef (the seed's per-rank baker): runs one vertex batch on the device. Iteration 0 is the
// base map (emission + direct diffuse light from every area light through S stratified shadow
// samples); iteration k adds reflective x the previous map seen along each viewpoint's mirror
// ray (and, with --gather-rays, diffuse x the previous map over the cosine hemisphere).
#include <cstdint>
#include <vector>

#include "bake_config.hpp"
#include "bake_scene.hpp"
#include "map_errors.hpp"
#include "map_reader.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"
#include "rtmini/sampling/sphere_grid.hpp"
#include "view_order.hpp"

namespace rtmini::bake {

// A mirror hit: primitive and barycentrics.
template <class T>
struct HitRecord {
  int prim = -1;
  T u = 0, v = 0;
};

// A traced mirror ray, kept after its first trace: geometry is static, so iterations >= 2
// only re-read the map at the same hit (a gather instead of a trace).
using CachedHit = HitRecord<float>;

// A hit (a traced record or a traversal's Hit: prim, u, v) as the float cache stores it.
template <class H>
KOKKOS_INLINE_FUNCTION CachedHit cached_hit(const H& h) {
  CachedHit c;
  c.prim = h.prim;
  c.u = static_cast<float>(h.u);
  c.v = static_cast<float>(h.v);
  return c;
}

// A mirror hit at full precision, traced once before the iterations (the owner-computes map
// needs every hit up front to know which remote colours a rank reads). The first mirror
// iteration shades from it, exactly as from a fresh trace; later ones read the float cache, as
// before. With Real = float (the default build) it is the float cache's record itself, and the
// cache is the traced hits (Chef::release_traced_hits), not a second copy.
using TracedHit = HitRecord<Real>;

// kTraced: shade from the traced hits (Chef::trace_mirror_hits).
enum class HitCacheMode { kOff, kFill, kUse, kTraced };

// What one rank's mirror rays cost and read: rays and BVH nodes of the trace; per iteration, the
// hits that need a viewpoint lookup (the hit triangle has a view-dependent vertex), the colour
// reads (three hit-triangle vertices per hit), those of view-dependent vertices (a weighted
// blend of ~8 viewpoints each) and those of vertices another rank owns.
struct ReadCount {
  std::int64_t rays = 0, nodes = 0;
  std::int64_t lookups = 0, reads = 0, view_reads = 0, remote_reads = 0;
};

// Per vertex of [begin, end), estimated from `samples` of its N mirror rays (viewpoints spread
// evenly over the sphere) and scaled to N; 0 for view-independent vertices: the hits that cost a
// viewpoint lookup and the BVH nodes the rays visit. The pilot of the cost balance (kitchen.cpp);
// adds the rays it traces to `rays`.
struct MirrorCostEstimate {
  std::vector<float> lookup_hits, nodes;
};
MirrorCostEstimate estimate_mirror_costs(const BakeSceneDevice& scene, const BakeConfig& config,
                                         std::int64_t begin, std::int64_t end, int samples,
                                         std::int64_t& rays);

// The views one rank's iteration reads and writes (its part of the distributed map): base
// colours, hit records (the float cache or the traced hits, whichever the iteration reads), the
// map's offsets and sparse halo tables, the previous map and the next. A Chef bakes another
// rank's pieces through them (node work sharing, node_share.hpp).
struct OwnerPart {
  Kokkos::View<Vec3*, MemSpace> base;
  Kokkos::View<CachedHit*, MemSpace> cache;
  Kokkos::View<TracedHit*, MemSpace> traced;
  Kokkos::View<std::int64_t*, MemSpace> map_offset;
  SparseColors sparse;     // with its halo
  FirstReads first_reads;  // the fused first mirror iteration only
  Kokkos::View<Vec3f*, MemSpace> prev, next;
};

// The storage order (view_order.hpp) on the device.
struct StorageOrder {
  Kokkos::View<int*, MemSpace> view;        // slot -> viewpoint
  Kokkos::View<const int*, MemSpace> slot;  // viewpoint -> slot
};

class Chef {
 public:
  // local_items: colour entries over all of this rank's batches (sizes the hit cache).
  Chef(const BakeSceneDevice& scene, const BakeConfig& config, std::int64_t local_items);

  // Base colours (emission + direct diffuse) of vertices [begin, end); returns shadow rays.
  std::int64_t bake_base(std::int64_t begin, std::int64_t end);

  // Where each vertex's colours sit in the maps given to bake_iteration / trace_reference
  // (MapLayout::device, and its sparse remote vertices if any); the scene's global offsets
  // until set.
  void set_map_offset(Kokkos::View<std::int64_t*, MemSpace> offset, SparseColors sparse = {}) {
    map_offset_ = offset;
    sparse_ = sparse;
  }
  // The next bake_iteration reads remote vertices from their base colours and flags what it
  // reads (FirstReads, map_reader.hpp); an empty FirstReads switches that off again.
  void set_first_reads(FirstReads first) { first_reads_ = first; }

  // Traces the mirror rays of vertices [begin, end) once and keeps the hits (and fills the hit
  // cache); returns the rays and the BVH nodes they visited.
  ReadCount trace_mirror_hits(std::int64_t begin, std::int64_t end, std::int64_t cache_offset);
  // The same into another rank's traced hits (a piece taken in a node-shared trace, NodeHits).
  ReadCount trace_mirror_hits_into(Kokkos::View<TracedHit*, MemSpace> traced, std::int64_t begin,
                                   std::int64_t end, std::int64_t cache_offset) const;
  // After trace_mirror_hits: flags in `read` every vertex the traced hits of vertices [begin,
  // end) read and counts their lookups and reads, those of vertices not `owned` as remote.
  ReadCount count_mirror_reads(std::int64_t begin, std::int64_t end, std::int64_t cache_offset,
                               Kokkos::View<const char*, MemSpace> owned,
                               Kokkos::View<char*, MemSpace> read) const;
  // After trace_mirror_hits: the traced hits of each vertex in [begin, end) that need a
  // viewpoint lookup (exact; estimate_mirror_costs samples them).
  std::vector<float> lookup_hits(std::int64_t begin, std::int64_t end,
                                 std::int64_t cache_offset) const;
  // The traced hits of all this rank's batches, in slot order, handed over (the Chef keeps none;
  // they move between ranks when the ownership changes after the trace), and their
  // replacement: `hits` become the traced hits of a rank whose batches hold hits.extent(0)
  // colour entries. Both stay in MemSpace.
  Kokkos::View<TracedHit*, MemSpace> take_traced_hits();
  void adopt_traced_hits(Kokkos::View<TracedHit*, MemSpace> hits);
  // After trace_mirror_hits and set_map_offset: flags in `items` (one per entry of the map
  // layout) every colour of a vertex that is not `owned` that the lookups at the traced hits
  // of vertices [begin, end) read: the remote colours this rank needs, entry by entry.
  void mark_read_items(std::int64_t begin, std::int64_t end, std::int64_t cache_offset,
                       Kokkos::View<const char*, MemSpace> owned,
                       Kokkos::View<char*, MemSpace> items) const;
  bool has_traced_hits() const { return traced_.extent(0) > 0; }
  // Whether iterations after the first read their hits from the float cache (--hit-cache, and
  // more than one iteration). The traced path fills it only when the traced hits have served
  // their iteration (release_traced_hits): until then it would hold the same hits again.
  bool caches_hits() const { return caches_hits_; }
  // The traced hits become the float hit cache (caches_hits only).
  void release_traced_hits();
  // Frees every hit record (after the last iteration).
  void release_hits() {
    traced_ = Kokkos::View<TracedHit*, MemSpace>();
    cache_ = Kokkos::View<CachedHit*, MemSpace>();
  }

  // Where a vertex keeps the colour of each viewpoint in the maps of bake_iteration and
  // trace_reference (view_order.hpp).
  const ViewOrder& view_order() const { return view_order_; }
  // The colours of vertices [begin, end) of `from` (storage order) into `to` in viewpoint
  // order, both laid out by the map offset: what leaves the iterations.
  void to_viewpoint_order(std::int64_t begin, std::int64_t end,
                          Kokkos::View<const Vec3f*, MemSpace> from,
                          Kokkos::View<Vec3f*, MemSpace> to) const;

  // Colours of iteration `it` for vertices [begin, end) into next (map-offset order), from
  // prev (every colour iteration it - 1 reads). cache_offset: the batch's first slot in the
  // rank's hit cache. Returns rays traced.
  std::int64_t bake_iteration(int it, std::int64_t begin, std::int64_t end,
                              std::int64_t cache_offset, HitCacheMode cache,
                              Kokkos::View<const Vec3f*, MemSpace> prev,
                              Kokkos::View<Vec3f*, MemSpace> next);

  // bake_iteration of another rank's vertices, through that rank's part (node_share.hpp); the
  // lookups, directions and scratch are this Chef's (the same on every rank).
  std::int64_t bake_iteration_of(const OwnerPart& part, int it, std::int64_t begin,
                                 std::int64_t end, std::int64_t cache_offset, HitCacheMode cache);
  // This rank's part as an iteration of `mode` reads it (prev and next are the caller's; the
  // halo is the sparse layout's).
  OwnerPart own_part(HitCacheMode mode) const;
  // Takes the shared copies of this rank's base colours and hit records (node_share.hpp): the
  // Chef's own are freed.
  void adopt_part(const OwnerPart& shared);

  // The traced reference (reference_tracer.hpp) of vertices [begin, end) into out (by the map
  // offset, in storage order): config.iterations mirror iterations, no map lookups. Needs bake_base
  // first. Returns mirror rays traced.
  std::int64_t trace_reference(std::int64_t begin, std::int64_t end,
                               Kokkos::View<Vec3f*, MemSpace> out);

  // Sums of the errors of `map` (all vertices) read along every direction of a reference with
  // ref_n Fibonacci viewpoints (colours vertex-major) with this Chef's lookup.
  ErrorSums lookup_errors(Kokkos::View<const Vec3f*, MemSpace> map,
                          Kokkos::View<const Vec3f*, MemSpace> reference, int ref_n) const;

  // Per-vertex base colours (emission + direct light; filled for baked batches only).
  Kokkos::View<Vec3*, MemSpace> base() const { return base_; }

  // Bytes of the hit records held now (the traced hits, or the cache made of them; one view
  // when both are float), for the summary's account of what is resident.
  std::int64_t hit_bytes() const {
    const std::int64_t traced = static_cast<std::int64_t>(traced_.span() * sizeof(TracedHit));
    const bool same = static_cast<const void*>(cache_.data()) == traced_.data();
    return traced + (same ? 0 : static_cast<std::int64_t>(cache_.span() * sizeof(CachedHit)));
  }

  static std::int64_t hit_cache_bytes(std::int64_t items) {
    return items * static_cast<std::int64_t>(sizeof(CachedHit));
  }

 private:
  BakeSceneDevice scene_;
  BakeConfig config_;
  Kokkos::View<Vec3*, MemSpace> base_;    // per vertex (only this rank's are filled)
  Kokkos::View<Vec3*, MemSpace> gather_;  // per vertex, current iteration's diffuse gather
  Kokkos::View<CachedHit*, MemSpace> cache_;
  Kokkos::View<TracedHit*, MemSpace> traced_;
  Kokkos::View<std::int64_t*, MemSpace> map_offset_;
  SparseColors sparse_;
  FirstReads first_reads_;
  std::int64_t local_items_ = 0;
  bool caches_hits_ = false;
  ViewOrder view_order_;
  StorageOrder order_;
  // The lookup config_.lookup names (the others stay empty), and for a hemisphere map its
  // structure over the stored half and its images (HemisphereMap).
  SphereGrid<MemSpace> grid_, mirrored_grid_;
  FibonacciKdTree<MemSpace> kdtree_, mirrored_;
  FibonacciInverse<MemSpace> inverse_;

  // f(lookup) with the lookup config_.lookup names: each kernel is compiled once per lookup.
  template <class F>
  decltype(auto) with_lookup(F&& f) const {
    if (config_.lookup == Lookup::kGrid) return f(grid_);
    if (config_.lookup == Lookup::kKdTree) return f(kdtree_);
    return f(inverse_);
  }
  HemisphereMap hemisphere_map() const;
};

}  // namespace rtmini::bake
