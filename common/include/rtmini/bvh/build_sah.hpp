#pragma once
// SAH-quality build: top-down binned SAH (Wald, "On fast construction of
// SAH-based bounding volume hierarchies", 2007) on the host, 16 bins on all
// three axes, leaves of up to kMaxLeafSize when splitting does not pay.
// Slivers are cut by spatial splits where the SAH says they pay (Stich et al.
// 2009, build_sah.cpp), or else pre-split when that pays (presplit.hpp): a
// triangle may then sit in several leaves, at most once per leaf.
// Slower to build than the LBVH but traces faster; the result is copied to
// the memory space of the caller's choice.
#include <algorithm>
#include <string>
#include <vector>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/bvh/bvh.hpp"
#include "rtmini/bvh/presplit.hpp"

namespace rtmini::bvh {

struct HostBvh {
  std::vector<BvhNode> nodes;
  std::vector<Triangle> tris;
  std::vector<int> prim;
  Aabb bounds;
  int references = 0;           // items in the leaves: triangles plus extra split parts
  bool spatial_splits = false;  // whether the build tried spatial splits
};

// Whether a build asked for `s` tries spatial splits on these triangles.
bool uses_spatial_splits(TriangleSpan input, SpatialSplits s);

inline constexpr SpatialSplits kDefaultSpatialSplits = SpatialSplits::kAuto;

// How the SAH's triangle term counts a leaf's triangles, after the traversal that will read the
// tree. The host's 8-wide traversal tests a compact leaf's four lanes at once, so it counts them
// in blocks of four (half the binary nodes, a faster build). A device's binary traversal tests
// one triangle at a time: larger leaves cost it 17-29 % of its AO rate on the H200
// (results/gpu/README.md, 2026-11-29), so it counts single triangles.
enum class SahLeafCost { kBlocksOfFour, kPerTriangle };

// split_budget: extra references allowed (pre-split parts, or those added by spatial splits), as
// a fraction of the triangle count (0: never split), or kAutoSplitBudget (presplit.hpp).
// Builds with split references always count single triangles (build_sah.cpp).
HostBvh build_sah_host(TriangleSpan input, double split_budget = kDefaultSplitBudget,
                       SpatialSplits spatial_splits = kDefaultSpatialSplits,
                       SahLeafCost leaf_cost = SahLeafCost::kBlocksOfFour);

// compat::upload, except that host memory is filled by a plain copy: the Kokkos fill and
// deep_copy are parallel regions whose spin-waits cost more than the copy itself when the
// machine is loaded (measured: results/bvh/slivers.md).
template <class T, class MemorySpace>
Kokkos::View<T*, MemorySpace> upload_vector(const std::string& label, const std::vector<T>& v) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    Kokkos::View<T*, MemorySpace> out(Kokkos::view_alloc(Kokkos::WithoutInitializing, label),
                                      v.size());
    std::copy(v.begin(), v.end(), out.data());
    return out;
  } else {
    return compat::upload<MemorySpace>(label, v);
  }
}

template <class MemorySpace>
Bvh<MemorySpace> upload(const HostBvh& h, BuildQuality quality) {
  Bvh<MemorySpace> bvh;
  bvh.num_prims = static_cast<int>(h.tris.size());
  bvh.bounds = h.bounds;
  bvh.quality = quality;
  bvh.nodes = upload_vector<BvhNode, MemorySpace>("rtmini::bvh::nodes", h.nodes);
  bvh.tris = upload_vector<Triangle, MemorySpace>("rtmini::bvh::tris", h.tris);
  bvh.prim = upload_vector<int, MemorySpace>("rtmini::bvh::prim", h.prim);
  return bvh;
}

}  // namespace rtmini::bvh
