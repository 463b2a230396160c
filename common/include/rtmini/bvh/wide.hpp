#pragma once
// 8-wide BVH for CPU traversal: each node holds its eight children's boxes as
// structure-of-arrays lanes, so one node visit tests eight boxes with SIMD
// (the compiler vectorises the fixed-length lane loop). Built by collapsing
// the binary BVH (Wald et al., "Getting rid of packets", 2008: open the child
// of largest area until eight children are gathered); leaves are shared with
// the binary tree, so both layouts report identical hits.
#include <vector>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// Collapses a binary tree (host copy of its nodes) into 8-wide nodes, depth first.
std::vector<WideNode> collapse_to_wide(const std::vector<BvhNode>& binary);

}  // namespace rtmini::bvh
