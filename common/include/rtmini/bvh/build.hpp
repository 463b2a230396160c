#pragma once
// One entry point for both builders.
#include <vector>

#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/build_sah.hpp"
#include "rtmini/bvh/wide.hpp"

namespace rtmini::bvh {

// Adds the 8-wide copy used by host traversal when the tree lives in host memory.
template <class MemorySpace>
void add_wide_nodes(Bvh<MemorySpace>& bvh) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    if (bvh.num_prims == 0) return;
    Kokkos::Profiling::pushRegion("rtmini::bvh::build::collapse_wide");
    std::vector<BvhNode> binary(bvh.nodes.data(), bvh.nodes.data() + bvh.nodes.extent(0));
    const std::vector<WideNode> wide = collapse_to_wide(binary);
    bvh.wide = Kokkos::View<WideNode*, MemorySpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bvh::wide"), wide.size());
    for (std::size_t i = 0; i < wide.size(); ++i) bvh.wide(i) = wide[i];
    Kokkos::Profiling::popRegion();
  }
}

// Zero-area triangles become the point (a, a, a): the watertight test gives U = V = W = 0
// there, so no ray hits them, whatever rounding the shear adds (issue 7, stability).
template <class ExecSpace, class MemorySpace>
void collapse_zero_area(const ExecSpace& space, Bvh<MemorySpace>& bvh) {
  auto tris = bvh.tris;
  Kokkos::parallel_for(
      "rtmini::bvh::build::collapse_zero_area",
      Kokkos::RangePolicy<ExecSpace>(space, std::int64_t(0),
                                     static_cast<std::int64_t>(tris.extent(0))),
      KOKKOS_LAMBDA(const std::int64_t i) {
        const Triangle t = tris(i);
        if (is_zero_area(t.a, t.b, t.c)) tris(i) = Triangle{t.a, t.a, t.a};
      });
  space.fence();
}

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> tris,
                       BuildQuality quality) {
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
  add_wide_nodes(out);
  return out;
}

}  // namespace rtmini::bvh
