#pragma once
// The BVH reports its own quality so the build-speed / trace-speed trade is
// measurable: normalised SAH cost, depth, leaf-size statistics.
#include <string>

#include "rtmini/bvh/build_sah.hpp"
#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

struct QualityReport {
  double sah_cost = 0;  // (Ct * sum SA(inner) + Ci * sum n * SA(leaf)) / SA(root), Ct = Ci = 1
  int max_depth = 0;
  int inner_nodes = 0;
  int leaves = 0;
  double mean_leaf_size = 0;
  int max_leaf_size = 0;
  int leaf_size_histogram[kMaxLeafSize + 1] = {};
  std::string to_string() const;
};

QualityReport measure_quality(const std::vector<BvhNode>& nodes, const Aabb& bounds);

template <class MemorySpace>
QualityReport measure_quality(const Bvh<MemorySpace>& bvh) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bvh.nodes);
  std::vector<BvhNode> nodes(h.data(), h.data() + (bvh.num_prims > 0 ? h.extent(0) : 0));
  return measure_quality(nodes, bvh.bounds);
}

}  // namespace rtmini::bvh
