#pragma once
// SAH-quality build: top-down binned SAH (Wald, "On fast construction of
// SAH-based bounding volume hierarchies", 2007) on the host, 16 bins on all
// three axes, leaves of up to kMaxLeafSize when splitting does not pay.
// Slivers are pre-split first when that pays (presplit.hpp): a triangle may
// then sit in several leaves, at most once per leaf.
// Slower to build than the LBVH but traces faster; the result is copied to
// the memory space of the caller's choice.
#include <vector>

#include "rtmini/bvh/bvh.hpp"
#include "rtmini/bvh/presplit.hpp"

namespace rtmini::bvh {

struct HostBvh {
  std::vector<BvhNode> nodes;
  std::vector<Triangle> tris;
  std::vector<int> prim;
  Aabb bounds;
  int references = 0;  // items the build sorted: triangles plus extra pre-split parts
};

// split_budget: extra pre-split references allowed, as a fraction of the triangle count
// (0: never split).
HostBvh build_sah_host(const std::vector<Triangle>& input,
                       double split_budget = kDefaultSplitBudget);

template <class MemorySpace>
Bvh<MemorySpace> upload(const HostBvh& h, BuildQuality quality) {
  Bvh<MemorySpace> bvh;
  bvh.num_prims = static_cast<int>(h.tris.size());
  bvh.bounds = h.bounds;
  bvh.quality = quality;
  bvh.nodes = Kokkos::View<BvhNode*, MemorySpace>("rtmini::bvh::nodes", h.nodes.size());
  bvh.tris = Kokkos::View<Triangle*, MemorySpace>("rtmini::bvh::tris", h.tris.size());
  bvh.prim = Kokkos::View<int*, MemorySpace>("rtmini::bvh::prim", h.prim.size());
  Kokkos::deep_copy(bvh.nodes, compat::host_view(h.nodes.data(), h.nodes.size()));
  Kokkos::deep_copy(bvh.tris, compat::host_view(h.tris.data(), h.tris.size()));
  Kokkos::deep_copy(bvh.prim, compat::host_view(h.prim.data(), h.prim.size()));
  return bvh;
}

}  // namespace rtmini::bvh
