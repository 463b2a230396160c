#pragma once
// One entry point for the builders (LBVH, PLOC, host SAH).
#include <algorithm>
#include <vector>

#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/build_ploc.hpp"
#include "rtmini/bvh/build_sah.hpp"
#include "rtmini/bvh/finish.hpp"
#include "rtmini/bvh/gpu_collapse.hpp"
#include "rtmini/bvh/host_pages.hpp"
#include "rtmini/bvh/wide.hpp"

namespace rtmini::bvh {

// Adds the 8-wide copy used by host traversal when the tree lives in host memory, collapsed
// from host copies of the finished binary tree.
template <class MemorySpace>
void add_wide_nodes(Bvh<MemorySpace>& bvh, const std::vector<BvhNode>& binary, const Triangle* tris,
                    const int* prim) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    if (bvh.num_prims == 0) return;
    Kokkos::Profiling::pushRegion("rtmini::bvh::build::collapse_wide");
    const WideBvh wide = collapse_to_wide(binary, tris, prim);
    bvh.wide = huge_page_view<WideNode, MemorySpace>("rtmini::bvh::wide", wide.nodes.size());
    std::copy(wide.nodes.begin(), wide.nodes.end(), bvh.wide.data());
    bvh.leaves =
        huge_page_view<TriangleLanes, MemorySpace>("rtmini::bvh::wide_leaves", wide.leaves.size());
    std::copy(wide.leaves.begin(), wide.leaves.end(), bvh.leaves.data());
    Kokkos::Profiling::popRegion();
  }
}

template <class MemorySpace>
void add_wide_nodes(Bvh<MemorySpace>& bvh) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    std::vector<BvhNode> binary(bvh.nodes.data(), bvh.nodes.data() + bvh.nodes.extent(0));
    add_wide_nodes(bvh, binary, bvh.tris.data(), bvh.prim.data());
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

template <class ExecSpace, class MemorySpace>
void collapse_zero_area(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  for_each_index(
      space, "rtmini::bvh::build::collapse_zero_area", tris,
      KOKKOS_LAMBDA(const std::int64_t i) { tris(i) = point_if_zero_area(tris(i)); });
}

template <class ExecSpace, class MemorySpace>
void pad_node_boxes(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto nodes = bvh.nodes;
  for_each_index(
      space, "rtmini::bvh::build::pad_boxes", nodes,
      KOKKOS_LAMBDA(const std::int64_t i) { pad_child_boxes(nodes(i)); });
}

// Whether build() adds the compressed wide layout (gpu_wide.hpp) that devices trace closest hits
// with; callers that only ask any-hit queries skip its build.
enum class QuantizedWide { kOnDevices, kNever };

// The SAH build runs on the host and returns a finished tree (zero-area triangles as points,
// padded boxes: the same functions as the kernels above), so no device kernel runs for it.
template <class MemorySpace>
Bvh<MemorySpace> build_sah(Kokkos::View<const Triangle*, MemorySpace> tris, double split_budget,
                           SpatialSplits spatial_splits) {
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_sah");
  // (host memory: the caller's view itself, read in place)
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
  constexpr bool on_host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible;
  const HostBvh h = build_sah_host(TriangleSpan(host.data(), host.extent(0)), split_budget,
                                   spatial_splits,
                                   on_host ? SahLeafCost::kBlocksOfFour : SahLeafCost::kPerTriangle);
  Bvh<MemorySpace> out = upload<MemorySpace>(h, BuildQuality::kSah);
  add_wide_nodes(out, h.nodes, h.tris.data(), h.prim.data());
  Kokkos::Profiling::popRegion();
  return out;
}

// split_budget (SAH only): extra references for slivers (pre-split parts or spatial splits), as
// a fraction of the triangle count; 0 builds from the triangles as they are, kAutoSplitBudget
// (the default) grows it while the SAH says it pays (presplit.hpp). spatial_splits (SAH only):
// build_quality.hpp.
template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> tris,
                       BuildQuality quality,
                       QuantizedWide quantized_wide = QuantizedWide::kOnDevices,
                       double split_budget = kDefaultSplitBudget,
                       SpatialSplits spatial_splits = kDefaultSpatialSplits) {
  Bvh<MemorySpace> out;
  if (quality == BuildQuality::kSah) {
    out = build_sah<MemorySpace>(tris, split_budget, spatial_splits);
  } else {
    out = quality == BuildQuality::kPloc ? build_ploc<ExecSpace, MemorySpace>(space, tris)
                                         : build_lbvh<ExecSpace, MemorySpace>(space, tris);
    collapse_zero_area(space, out);
    pad_node_boxes(space, out);
    add_wide_nodes(out);
  }
  // Devices trace closest hits in the compressed 8-wide layout; the host keeps its SIMD layout
  // unless asked (add_quantized_wide).
  if constexpr (!Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    if (quantized_wide == QuantizedWide::kOnDevices) add_quantized_wide(space, out);
  }
  return out;
}

}  // namespace rtmini::bvh
