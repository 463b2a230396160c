#pragma once
// Device helpers shared by the Chef's kernels and the convergence test: the mirror direction
// of a viewpoint, and reading the previous iteration's map at a ray hit.
#include <cstdint>

#include "bake_scene.hpp"
#include "rtmini/sampling/fibonacci_hemisphere.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {

// The side of vertex normal n that a mirror ray for viewpoint direction d leaves from: n for
// one-sided mirrors (the default; mirror_direction folds a viewpoint behind to the front), -n
// for a viewpoint behind a two-sided mirror (`--two-sided`), which then reflects on its back.
KOKKOS_INLINE_FUNCTION Vec3 mirror_normal(const Vec3& d, const Vec3& n, bool two_sided) {
  return two_sided && dot(d, n) > Real(0) ? -n : n;
}

// Mirror ray of viewpoint direction d (camera ray into the vertex) about the vertex normal n.
// A viewpoint behind the surface is shaded as its mirror image in the tangent plane (README:
// continuous at grazing, and every mirror ray leaves on the front side).
KOKKOS_INLINE_FUNCTION Vec3 mirror_direction(const Vec3& d, const Vec3& n) {
  const Real dn = dot(d, n);
  const Vec3 front = dn > Real(0) ? d - n * (Real(2) * dn) : d;
  return normalize(reflect(front, n));
}

// A hemisphere map (`--directions hemisphere`, one-sided only): a view-dependent vertex stores
// N/2 viewpoints, the front half of the N Fibonacci points in its frame view_frame(-normal)
// (fibonacci_hemisphere.hpp). Empty views (stored == 0): every vertex has the N shared ones.
struct HemisphereMap {
  Kokkos::View<const Vec3*, MemSpace> normal;  // per vertex: the frame's -z
  Kokkos::View<const Vec3*, MemSpace> points;  // the N Fibonacci points
  int stored = 0;                              // N/2; 0: a full-sphere map
  // The stored points and their mirror images (build_mirrored_kdtree or _grid, whichever the
  // lookup is): one query per vertex instead of two near the horizon. Both empty (n = 0, the sf
  // lookup): two queries with the map's own lookup.
  FibonacciKdTree<MemSpace> mirrored;
  SphereGrid<MemSpace> mirrored_grid;

  KOKKOS_INLINE_FUNCTION bool on() const { return stored > 0; }
  KOKKOS_INLINE_FUNCTION ViewFrame frame(std::int64_t v) const { return view_frame(-normal(v)); }
  // Camera-ray direction of vertex v's viewpoint `view` (points: the N Fibonacci directions).
  KOKKOS_INLINE_FUNCTION Vec3 direction(std::int64_t v, int view) const {
    return on() ? frame(v).to_world(points(view)) : points(view);
  }
  // Vertex v's viewpoints near direction dir: in its frame, folded to the front (the fold of
  // mirror_direction), among the stored half and its mirror images.
  template <class LookupT>
  KOKKOS_INLINE_FUNCTION ViewNeighbors neighbors(const LookupT& lookup, std::int64_t v,
                                                 const Vec3& dir, Real radius) const {
    Vec3 q = frame(v).to_local(dir);
    q.z = math::fabs(q.z);
    if (mirrored_grid.n > 0) return mirrored_neighbors(mirrored_grid, q, radius, stored);
    if (mirrored.n > 0) return mirrored_neighbors(mirrored, q, radius, stored);
    return hemisphere_neighbors(lookup, points, q, radius, stored);
  }
};

// Where a rank keeps the colours of the vertices it reads but does not own (MapLayout,
// map_exchange.hpp). Entries below map_colors are the rank's map (`prev`, double-buffered);
// those from map_colors on are its halo, held once, apart from the map, in the exchange's
// receive buffer (`halo`): the halo is read during an iteration and written only between
// iterations, so it needs no second buffer (stored with the map, it was held twice, plus the
// exchange's copy). A remote view-dependent vertex keeps only the viewpoints its lookups read:
// at 16 ranks a rank's mirror lookups read about 1 in 12 of a remote vertex's N colours. Such a
// sparse vertex v keeps the slots (view_order.hpp) whose bits are set in its mask words
// mask[span(v).mask_at ...], in slot order from span(v).start; kept(w) counts the kept slots
// before word w. Empty views: every vertex dense, in `prev` at the map's own offsets.
//
// Where a vertex's colours sit is one record (ColorSpan), read once per vertex read: as three
// tables (the scene's offsets for the count, the first entries, the mask words) a rank of two
// missed L1 34 % more often in MapReader::read than one rank reading its plain offsets
// (cachegrind, rooms SIDE 50, N = 200, K = 3: 41.8 M against 31.3 M per rank).
struct ColorSpan {
  std::int64_t start = 0;     // first entry: in the map, or from map_colors on in the halo
  std::int32_t count = 0;     // the vertex's colours: 1, or its stored viewpoints
  std::int32_t mask_at = -1;  // first mask word of a sparse vertex; -1: dense
};

struct SparseColors {
  Kokkos::View<const ColorSpan*, MemSpace> span;  // per vertex
  Kokkos::View<const std::uint64_t*, MemSpace> mask;
  Kokkos::View<const std::int32_t*, MemSpace> kept;
  std::int64_t map_colors = 0;                // entries from here on are in `halo`
  Kokkos::View<const Vec3f*, MemSpace> halo;  // MapExchange::halo()

  KOKKOS_INLINE_FUNCTION bool empty() const { return span.extent(0) == 0; }
};

// The entry of slot j among the kept ones (bit j of the vertex's mask words).
KOKKOS_INLINE_FUNCTION std::int64_t sparse_entry(std::int64_t first, std::int64_t word_at,
                                                 const std::uint64_t* mask,
                                                 const std::int32_t* kept, int j) {
  const std::int64_t w = word_at + (j >> 6);
  const std::uint64_t below = mask[w] & ((std::uint64_t(1) << (j & 63)) - 1);
  return first + kept[w] + compat::popcount64(below);
}

// The first mirror iteration of a rank whose sparse halo is not planned yet (kitchen.cpp,
// "fused halo plan"). Its previous map is the base map, whose N colours of a vertex are all
// Vec3f(base colour): a remote vertex is read from its one fetched base colour (the same bits
// the exchanged entries would hold, so the same sums), and every viewpoint a lookup reads is
// flagged: the read set that fixes the sparse layout, found by the iteration itself instead
// of by a second pass over the same lookups.
struct FirstReads {
  Kokkos::View<const char*, MemSpace> owned;       // per vertex; empty: not the first iteration
  Kokkos::View<const Vec3f*, MemSpace> base;       // per vertex: Vec3f(base), remote ones
  Kokkos::View<const std::int64_t*, MemSpace> at;  // per vertex + 1: offsets of `flags`
  Kokkos::View<char*, MemSpace> flags;             // per slot of a present vertex: read

  KOKKOS_INLINE_FUNCTION bool remote(int vert) const { return owned.extent(0) > 0 && !owned(vert); }
  KOKKOS_INLINE_FUNCTION Vec3 read(int vert, int j) const {
    flags(at(vert) + j) = 1;  // every writer writes 1: no ordering needed
    return Vec3(base(vert));
  }
};

// Where one vertex's colours of the previous map sit, resolved once per vertex read (not once
// per viewpoint): its first entry, in the map or in the halo, and for a sparse halo vertex its
// mask words and kept counts (sparse_entry, with the word offset already applied).
struct VertexColors {
  const Vec3f* first = nullptr;
  const std::uint64_t* mask = nullptr;  // null: dense, slot j at first[j]
  const std::int32_t* kept = nullptr;
  int count = 0;  // 1: view-independent

  KOKKOS_INLINE_FUNCTION Vec3 operator()(int j) const {
    if (mask == nullptr) return Vec3(first[j]);
    return Vec3(first[sparse_entry(0, 0, mask, kept, j)]);
  }
};

// nb's viewpoints turned into the slots where a vertex keeps their colours (storage order,
// view_order.hpp). An empty table: the map is in viewpoint order (a map read from a file).
KOKKOS_INLINE_FUNCTION void to_slots(const Kokkos::View<const int*, MemSpace>& slot,
                                     ViewNeighbors& nb) {
  if (slot.extent(0) == 0) return;
  for (int j = 0; j < nb.count; ++j) nb.index[j] = slot(nb.index[j]);
}

// Colour of the previous map seen along `dir` at a hit: the hit triangle's three vertex
// colours, each looked up at `dir` among its nearest viewpoints, mixed barycentrically.
template <class LookupT>
struct MapReader {
  Kokkos::View<int* [3], MemSpace> tri_vertices;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<const Vec3f*, MemSpace> prev;
  Kokkos::View<Vec3*, MemSpace> emissive;
  LookupT lookup;
  Real radius;
  Vec3 background;
  SparseColors sparse;       // empty: prev is laid out by color_offset
  FirstReads first_reads;    // remote vertices of the fused first iteration (empty: none)
  HemisphereMap hemisphere;  // off: every view-dependent vertex has the N shared viewpoints
  Kokkos::View<const int*, MemSpace> slot{};  // viewpoint -> storage slot (to_slots)

  // Vertex vert's colours in the previous map: in prev at color_offset, or with a halo, in prev
  // (an owned vertex) or the halo (a remote one); a vertex never spans both.
  KOKKOS_INLINE_FUNCTION VertexColors colors_of(int vert) const {
    if (sparse.empty()) {
      const std::int64_t first = color_offset(vert);
      return {prev.data() + first, nullptr, nullptr,
              static_cast<int>(color_offset(vert + 1) - first)};
    }
    const ColorSpan s = sparse.span(vert);
    const Vec3f* p = s.start < sparse.map_colors
                         ? prev.data() + s.start
                         : sparse.halo.data() + (s.start - sparse.map_colors);
    if (s.mask_at < 0) return {p, nullptr, nullptr, s.count};
    return {p, sparse.mask.data() + s.mask_at, sparse.kept.data() + s.mask_at, s.count};
  }

  // without_emission: the diffuse gather already has the lights through its shadow rays, so
  // it reads only the light that the hit surface reflects (no double counting).
  KOKKOS_INLINE_FUNCTION Vec3 read(int prim, Real u, Real v, const Vec3& dir,
                                   bool without_emission = false) const {
    if (prim < 0) return background;
    const Real w[3] = {Real(1) - u - v, u, v};
    ViewNeighbors nb;
    bool have_nb = false;
    Vec3 sum(Real(0));
    for (int k = 0; k < 3; ++k) {
      const int vert = tri_vertices(prim, k);
      const VertexColors colors = colors_of(vert);
      const bool remote = first_reads.remote(vert);
      if (colors.count == 1) {
        sum += (remote ? first_reads.read(vert, 0) : colors(0)) * w[k];
        continue;
      }
      if (hemisphere.on()) {  // each vertex has its own frame
        nb = hemisphere.neighbors(lookup, vert, dir, radius);
        to_slots(slot, nb);
      } else if (!have_nb) {
        nb = lookup.neighbors(dir, radius);
        to_slots(slot, nb);
        have_nb = true;
      }
      // Two loops: the flag stores of the fused first iteration (char stores, which may alias
      // anything) would otherwise make every read of the loop reload the views.
      Vec3 c(Real(0));
      if (remote) {
        for (int j = 0; j < nb.count; ++j) c += first_reads.read(vert, nb.index[j]) * nb.weight[j];
      } else {
        for (int j = 0; j < nb.count; ++j) c += colors(nb.index[j]) * nb.weight[j];
      }
      sum += c * w[k];
    }
    if (without_emission) {
      for (int k = 0; k < 3; ++k) sum -= emissive(tri_vertices(prim, k)) * w[k];
    }
    return sum;
  }
};

}  // namespace rtmini::bake
