#pragma once
// One entry point for both builders.
#include <vector>

#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/build_sah.hpp"
#include "rtmini/bvh/gpu_collapse.hpp"
#include "rtmini/bvh/wide.hpp"

namespace rtmini::bvh {

// Adds the 8-wide copy used by host traversal when the tree lives in host memory.
template <class MemorySpace>
void add_wide_nodes(Bvh<MemorySpace>& bvh) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    if (bvh.num_prims == 0) return;
    Kokkos::Profiling::pushRegion("rtmini::bvh::build::collapse_wide");
    std::vector<BvhNode> binary(bvh.nodes.data(), bvh.nodes.data() + bvh.nodes.extent(0));
    const WideBvh wide = collapse_to_wide(binary, bvh.tris.data(), bvh.prim.data());
    bvh.wide = Kokkos::View<WideNode*, MemorySpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::wide"), wide.nodes.size());
    for (std::size_t i = 0; i < wide.nodes.size(); ++i) bvh.wide(i) = wide.nodes[i];
    bvh.leaves = Kokkos::View<TriangleLanes*, MemorySpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::wide_leaves"),
        wide.leaves.size());
    for (std::size_t i = 0; i < wide.leaves.size(); ++i) bvh.leaves(i) = wide.leaves[i];
    Kokkos::Profiling::popRegion();
  }
}

// Runs fn(i) for every index of `view` on `space`, then fences.
template <class ExecSpace, class ViewT, class Fn>
void for_each_index(const ExecSpace& space, const char* label, const ViewT& view, const Fn& fn) {
  Kokkos::parallel_for(label,
                       Kokkos::RangePolicy<ExecSpace>(space, std::int64_t(0),
                                                      static_cast<std::int64_t>(view.extent(0))),
                       fn);
  space.fence();
}

// Zero-area triangles become the point (a, a, a): the watertight test gives U = V = W = 0
// there, so no ray hits them, whatever rounding the shear adds (issue 7, stability).
template <class ExecSpace, class MemorySpace>
void collapse_zero_area(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  for_each_index(
      space, "rtmini::bvh::build::collapse_zero_area", tris, KOKKOS_LAMBDA(const std::int64_t i) {
        const Triangle t = tris(i);
        if (is_zero_area(t.a, t.b, t.c)) tris(i) = Triangle{t.a, t.a, t.a};
      });
}

// Every child box grows outward by about four float ulps (relative 4.8e-7, plus 1e-30 at zero).
// A ray with a zero direction component whose origin lies exactly in the plane of a box face
// would otherwise get (face - origin) * (1 / 0) = 0 * huge = 0 as that slab's far distance and
// miss a box whose triangles it hits on that face (issue 7); inside a padded box its origin is
// strictly within the slab. The padding is conservative: the triangle test decides every hit.
KOKKOS_INLINE_FUNCTION Real pad_below(Real x) {
  return x - (math::fabs(x) * Real(4.8e-7) + Real(1e-30));
}
KOKKOS_INLINE_FUNCTION Real pad_above(Real x) {
  return x + (math::fabs(x) * Real(4.8e-7) + Real(1e-30));
}

template <class ExecSpace, class MemorySpace>
void pad_node_boxes(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto nodes = bvh.nodes;
  for_each_index(
      space, "rtmini::bvh::build::pad_boxes", nodes, KOKKOS_LAMBDA(const std::int64_t i) {
        BvhNode& n = nodes(i);
        for (int k = 0; k < 2; ++k) {
          if (n.child[k] == kEmptyLeaf) continue;  // its empty box stays empty
          n.lo_x[k] = pad_below(n.lo_x[k]);
          n.lo_y[k] = pad_below(n.lo_y[k]);
          n.lo_z[k] = pad_below(n.lo_z[k]);
          n.hi_x[k] = pad_above(n.hi_x[k]);
          n.hi_y[k] = pad_above(n.hi_y[k]);
          n.hi_z[k] = pad_above(n.hi_z[k]);
        }
      });
}

// Whether build() adds the compressed wide layout (gpu_wide.hpp) that devices trace closest hits
// with; callers that only ask any-hit queries skip its build.
enum class QuantizedWide { kOnDevices, kNever };

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> tris,
                       BuildQuality quality,
                       QuantizedWide quantized_wide = QuantizedWide::kOnDevices) {
  Bvh<MemorySpace> out;
  if (quality == BuildQuality::kLbvh) {
    out = build_lbvh<ExecSpace, MemorySpace>(space, tris);
  } else {
    Kokkos::Profiling::pushRegion("rtmini::bvh::build_sah");
    auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
    std::vector<Triangle> v(host.data(), host.data() + host.extent(0));
    out = upload<MemorySpace>(build_sah_host(v), BuildQuality::kSah);
    Kokkos::Profiling::popRegion();
  }
  collapse_zero_area(space, out);
  pad_node_boxes(space, out);
  add_wide_nodes(out);
  // Devices trace closest hits in the compressed 8-wide layout; the host keeps its SIMD layout
  // unless asked (add_quantized_wide).
  if constexpr (!Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    if (quantized_wide == QuantizedWide::kOnDevices) add_quantized_wide(space, out);
  }
  return out;
}

}  // namespace rtmini::bvh
