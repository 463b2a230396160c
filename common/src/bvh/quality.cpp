#include "rtmini/bvh/quality.hpp"

#include <sstream>
#include <utility>
#include <vector>

namespace rtmini::bvh {

QualityReport measure_quality(const std::vector<BvhNode>& nodes, const Aabb& bounds) {
  QualityReport q;
  if (nodes.empty()) return q;
  const double root_area = bounds.surface_area() > 0 ? bounds.surface_area() : 1.0;
  double cost = bounds.surface_area();  // the root itself is traversed
  long long prims = 0;
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 1}};
  while (!stack.empty()) {
    const auto [id, depth] = stack.back();
    stack.pop_back();
    ++q.inner_nodes;
    if (depth > q.max_depth) q.max_depth = depth;
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t c = nodes[id].child[k];
      const double area = nodes[id].box(k).surface_area();
      if (c == kEmptyLeaf) continue;
      if (is_leaf(c)) {
        const int count = static_cast<int>(leaf_count(c));
        ++q.leaves;
        prims += count;
        ++q.leaf_size_histogram[count];
        if (count > q.max_leaf_size) q.max_leaf_size = count;
        cost += count * area;
        if (depth + 1 > q.max_depth) q.max_depth = depth + 1;
      } else {
        cost += area;
        stack.push_back({c, depth + 1});
      }
    }
  }
  q.sah_cost = cost / root_area;
  q.mean_leaf_size = q.leaves > 0 ? static_cast<double>(prims) / q.leaves : 0.0;
  return q;
}

std::string QualityReport::to_string() const {
  std::ostringstream os;
  os << "SAH cost " << sah_cost << ", depth " << max_depth << ", " << inner_nodes
     << " inner nodes, " << leaves << " leaves (mean " << mean_leaf_size << ", max "
     << max_leaf_size << ")";
  return os.str();
}

}  // namespace rtmini::bvh
