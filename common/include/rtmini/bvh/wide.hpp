#pragma once
// 8-wide BVH for CPU traversal: each node holds its eight children's boxes as
// structure-of-arrays lanes, so one node visit tests eight boxes with SIMD
// (the compiler vectorises the fixed-length lane loop). Built by collapsing
// the binary BVH (Wald et al., "Getting rid of packets", 2008: open the child
// of largest area until eight children are gathered). Leaves hold their
// triangles as SIMD lanes (TriangleLanes); a binary subtree of at most
// kWideLeafMerge triangles becomes one such leaf, since one SIMD leaf test
// costs about the same as a node visit whatever its count. Every triangle
// keeps its caller's index, so both layouts report identical hits.
#include <vector>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

inline constexpr int kWideLeafMerge = kMaxLeafSize;

struct WideBvh {
  std::vector<WideNode> nodes;
  std::vector<TriangleLanes> leaves;
};

// Collapses a binary tree (host copies of its nodes, and its triangles and prim ids in leaf
// order) into 8-wide nodes, depth first. Subtrees of at most `merge` triangles become one leaf.
WideBvh collapse_to_wide(const std::vector<BvhNode>& binary, const Triangle* tris, const int* prim,
                         int merge = kWideLeafMerge);

}  // namespace rtmini::bvh
