#pragma once
// Collapses the binary BVH into compressed 8-wide nodes (gpu_wide.hpp) on any Kokkos execution
// space, top-down one level at a time: every node of a level gathers its children by opening the
// inner child of largest surface area until eight are gathered (Wald et al. 2008, as the host's
// wide.cpp does), a scan over the level gives each node its children's and triangles' places, and
// a second pass writes the quantised nodes. Levels are laid out breadth first, so the layout does
// not depend on thread timing. The leaf triangles are copied into wide-leaf order.
#include <utility>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

namespace detail {

// A wide node's children before quantisation: binary child references and their (padded) boxes.
struct GatheredChildren {
  std::uint32_t ref[kQuantizedWidth];
  Aabb box[kQuantizedWidth];
  int count = 0;

  KOKKOS_INLINE_FUNCTION int inner_count() const {
    int m = 0;
    for (int c = 0; c < count; ++c) m += is_leaf(ref[c]) ? 0 : 1;
    return m;
  }
  KOKKOS_INLINE_FUNCTION int triangle_count() const {
    int m = 0;
    for (int c = 0; c < count; ++c) m += is_leaf(ref[c]) ? int(leaf_count(ref[c])) : 0;
    return m;
  }
  KOKKOS_INLINE_FUNCTION Aabb bounds() const {
    Aabb b;
    for (int c = 0; c < count; ++c) b.expand(box[c]);
    return b;
  }
};

// The children of binary node `root`, opened greedily by surface area up to eight.
template <class NodeView>
KOKKOS_INLINE_FUNCTION GatheredChildren gather_children(const NodeView& nodes, std::uint32_t root) {
  GatheredChildren g;
  auto append_children_of = [&](std::uint32_t binary, int replace) {
    const BvhNode& nd = nodes(binary);
    for (int k = 0; k < 2; ++k) {
      if (nd.child[k] == kEmptyLeaf) continue;
      const int at = replace >= 0 ? replace : g.count++;
      replace = -1;
      g.ref[at] = nd.child[k];
      g.box[at] = nd.box(k);
    }
  };
  append_children_of(root, -1);
  while (g.count < kQuantizedWidth) {
    int best = -1;
    Real best_area = Real(-1);
    for (int c = 0; c < g.count; ++c) {
      if (is_leaf(g.ref[c])) continue;
      const Real a = g.box[c].surface_area();
      if (a > best_area) {
        best_area = a;
        best = c;
      }
    }
    if (best < 0) break;
    append_children_of(g.ref[best], best);
  }
  return g;
}

// slot_child[s] = the gathered child placed in slot s, or -1. Slot s is the corner of the node
// whose bit a is set for the high side of axis a; each child goes greedily to the free corner
// its centroid lies furthest towards, so rays of octant o meet near children first in the
// order s = i ^ o.
KOKKOS_INLINE_FUNCTION void assign_slots(const GatheredChildren& g, const Aabb& node_box,
                                         int slot_child[kQuantizedWidth]) {
  const Vec3 center = node_box.center();
  bool child_done[kQuantizedWidth] = {};
  for (int s = 0; s < kQuantizedWidth; ++s) slot_child[s] = -1;
  for (int round = 0; round < g.count; ++round) {
    int best_c = -1, best_s = -1;
    Real best = Real(0);
    for (int c = 0; c < g.count; ++c) {
      if (child_done[c]) continue;
      const Vec3 d = g.box[c].center() - center;
      for (int s = 0; s < kQuantizedWidth; ++s) {
        if (slot_child[s] >= 0) continue;
        const Real score = ((s & 1) ? d.x : -d.x) + ((s & 2) ? d.y : -d.y) + ((s & 4) ? d.z : -d.z);
        if (best_c < 0 || score > best) {
          best = score;
          best_c = c;
          best_s = s;
        }
      }
    }
    slot_child[best_s] = best_c;
    child_done[best_c] = true;
  }
}

// The largest float at or below x (equal to x when Real is float).
KOKKOS_INLINE_FUNCTION float float_at_or_below(Real x) {
  const float f = static_cast<float>(x);
  if (Real(f) <= x) return f;
  const std::uint32_t b = compat::bit_cast<std::uint32_t>(f);
  if (f > 0) return compat::bit_cast<float>(b - 1u);
  if (f < 0) return compat::bit_cast<float>(b + 1u);
  return compat::bit_cast<float>(0x80000001u);  // -denorm_min
}

// The finest power-of-two step whose 255th grid line still reaches hi from origin.
KOKKOS_INLINE_FUNCTION std::uint32_t choose_exponent(float origin, Real hi) {
  const Real ext = hi - Real(origin);
  int e = ext > Real(0) ? static_cast<int>(math::ceil(math::log2(ext / Real(255)))) : -126;
  e = e < -126 ? -126 : (e > 127 ? 127 : e);
  while (e < 127 && decode_plane(origin, grid_step(std::uint32_t(e + 127)), 255u) < hi) ++e;
  while (e > -126 && decode_plane(origin, grid_step(std::uint32_t(e + 126)), 255u) >= hi) --e;
  return static_cast<std::uint32_t>(e + 127);
}

// The highest grid line at or below lo (round outward: the decoded box encloses the child).
KOKKOS_INLINE_FUNCTION std::uint8_t quantize_below(Real lo, float origin, Real step) {
  Real guess = math::floor((lo - Real(origin)) / step);
  int q = guess < Real(0) ? 0 : (guess > Real(255) ? 255 : static_cast<int>(guess));
  while (q > 0 && decode_plane(origin, step, std::uint32_t(q)) > lo) --q;
  while (q < 255 && decode_plane(origin, step, std::uint32_t(q + 1)) <= lo) ++q;
  return static_cast<std::uint8_t>(q);
}

// The lowest grid line at or above hi.
KOKKOS_INLINE_FUNCTION std::uint8_t quantize_above(Real hi, float origin, Real step) {
  Real guess = math::ceil((hi - Real(origin)) / step);
  int q = guess < Real(0) ? 0 : (guess > Real(255) ? 255 : static_cast<int>(guess));
  while (q < 255 && decode_plane(origin, step, std::uint32_t(q)) < hi) ++q;
  while (q > 0 && decode_plane(origin, step, std::uint32_t(q - 1)) >= hi) --q;
  return static_cast<std::uint8_t>(q);
}

// Per-level sizes packed in one scan value: inner children above bit 32, triangles below.
KOKKOS_INLINE_FUNCTION std::uint64_t pack_level_sizes(const GatheredChildren& g) {
  return std::uint64_t(g.inner_count()) << 32 | std::uint64_t(g.triangle_count());
}

// The quantised node for gathered children; inner children's binary ids go to next(child_offset
// + rank), leaf triangles are copied to wide-leaf order from tri_base.
template <class BvhT, class IdView>
KOKKOS_INLINE_FUNCTION QuantizedWideNode
emit_quantized_node(const BvhT& bvh, const GatheredChildren& g, std::uint32_t child_base,
                    std::uint32_t child_offset, std::uint32_t tri_base, const IdView& next) {
  QuantizedWideNode out{};
  const Aabb nb = g.bounds();
  int slot_child[kQuantizedWidth];
  assign_slots(g, nb, slot_child);
  const Real lo[3] = {nb.lo.x, nb.lo.y, nb.lo.z}, hi[3] = {nb.hi.x, nb.hi.y, nb.hi.z};
  Real step[3];
  for (int a = 0; a < 3; ++a) {
    out.origin[a] = float_at_or_below(lo[a]);
    const std::uint32_t biased = choose_exponent(out.origin[a], hi[a]);
    out.exponent[a] = static_cast<std::uint8_t>(biased);
    step[a] = grid_step(biased);
  }
  out.child_base = child_base + child_offset;
  out.tri_base = tri_base;
  std::uint32_t inner = 0, tri = 0;
  for (int s = 0; s < kQuantizedWidth; ++s) {
    const int c = slot_child[s];
    if (c < 0) {  // unused slot: an inverted box, and no triangles
      for (int a = 0; a < 3; ++a) {
        out.q[a][s] = 255;
        out.q[3 + a][s] = 0;
      }
      continue;
    }
    const Aabb& b = g.box[c];
    const Real clo[3] = {b.lo.x, b.lo.y, b.lo.z}, chi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int a = 0; a < 3; ++a) {
      out.q[a][s] = quantize_below(clo[a], out.origin[a], step[a]);
      out.q[3 + a][s] = quantize_above(chi[a], out.origin[a], step[a]);
    }
    const std::uint32_t ref = g.ref[c];
    if (!is_leaf(ref)) {
      out.inner_mask = static_cast<std::uint8_t>(out.inner_mask | (1u << s));
      next(child_offset + inner++) = static_cast<int>(ref);
      continue;
    }
    const std::uint32_t first = leaf_first(ref), count = leaf_count(ref);
    out.tri_offset[s] = static_cast<std::uint8_t>(tri);
    out.tri_count[s] = static_cast<std::uint8_t>(count);
    for (std::uint32_t t = 0; t < count; ++t) {
      bvh.qwide_tris(tri_base + tri + t) = bvh.tris(first + t);
      bvh.qwide_prim(tri_base + tri + t) = bvh.prim(first + t);
    }
    tri += count;
  }
  return out;
}

}  // namespace detail

// Adds the compressed 8-wide copy (bvh.qwide*) of a built binary tree, on `space`. Called by
// build() for device memory; host callers (tests) may call it to traverse that layout there too.
template <class ExecSpace, class MemorySpace>
void add_quantized_wide(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  if (bvh.num_prims == 0) return;
  Kokkos::Profiling::pushRegion("rtmini::bvh::build::collapse_quantized_wide");
  using Policy = Kokkos::RangePolicy<ExecSpace>;
  const int capacity = static_cast<int>(bvh.nodes.extent(0));  // >= wide nodes: each owns one
  Kokkos::View<QuantizedWideNode*, MemorySpace> wide(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::qwide_build"), capacity);
  bvh.qwide_tris = Kokkos::View<Triangle*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::qwide_tris"), bvh.num_prims);
  bvh.qwide_prim = Kokkos::View<int*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::qwide_prim"), bvh.num_prims);
  Kokkos::View<int*, MemorySpace> level("rtmini::bvh::build::qwide_level", capacity);
  Kokkos::View<int*, MemorySpace> next(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::qwide_next"), capacity);
  Kokkos::View<std::uint64_t*, MemorySpace> offsets(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::build::qwide_offsets"),
      capacity);
  const Bvh<MemorySpace> src = bvh;  // the lambdas capture the views, not the host object
  const auto nodes = bvh.nodes;
  int count = 1;  // the root level: binary node 0
  std::uint32_t level_base = 0, tri_cursor = 0;
  while (count > 0) {
    Kokkos::parallel_for(
        "rtmini::bvh::build::qwide_sizes", Policy(space, 0, count), KOKKOS_LAMBDA(int i) {
          offsets(i) = detail::pack_level_sizes(
              detail::gather_children(nodes, static_cast<std::uint32_t>(level(i))));
        });
    std::uint64_t total = 0;
    Kokkos::parallel_scan(
        "rtmini::bvh::build::qwide_offsets", Policy(space, 0, count),
        KOKKOS_LAMBDA(int i, std::uint64_t& running, bool final) {
          const std::uint64_t v = offsets(i);
          if (final) offsets(i) = running;
          running += v;
        },
        total);
    const std::uint32_t child_base = level_base + static_cast<std::uint32_t>(count);
    const std::uint32_t tris_here = tri_cursor, base_here = level_base;
    Kokkos::parallel_for(
        "rtmini::bvh::build::qwide_emit", Policy(space, 0, count), KOKKOS_LAMBDA(int i) {
          const auto g = detail::gather_children(nodes, static_cast<std::uint32_t>(level(i)));
          const std::uint64_t o = offsets(i);
          wide(base_here + i) = detail::emit_quantized_node(
              src, g, child_base, static_cast<std::uint32_t>(o >> 32),
              tris_here + static_cast<std::uint32_t>(o & 0xffffffffu), next);
        });
    level_base = child_base;
    tri_cursor += static_cast<std::uint32_t>(total & 0xffffffffu);
    count = static_cast<int>(total >> 32);
    std::swap(level, next);
  }
  bvh.qwide = Kokkos::View<QuantizedWideNode*, MemorySpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::qwide"), level_base);
  Kokkos::deep_copy(space, bvh.qwide, Kokkos::subview(wide, Kokkos::make_pair(0u, level_base)));
  space.fence();
  Kokkos::Profiling::popRegion();
}

}  // namespace rtmini::bvh
