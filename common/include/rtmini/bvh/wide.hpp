#pragma once
// 8-wide BVH for CPU traversal: each node holds its eight children's boxes as
// structure-of-arrays lanes, so one node visit tests eight boxes with SIMD. Leaves hold their
// triangles as SIMD lanes (TriangleLanes): a binary subtree of at most kWideLeafMerge
// triangles may become one such leaf. Built from the binary BVH by the SAH-optimal collapse
// of Ylitie et al. ("Efficient incoherent ray traversal on GPUs through compressed wide BVHs",
// HPG 2017): a dynamic programme over the binary tree picks, for every subtree, the cheapest
// way to spend up to eight slots of its wide parent (one slot as a leaf or a node, or its two
// children sharing the slots). Unlike the paper's per-triangle leaf cost, a leaf costs one SIMD
// test whatever its count (3 or 8 lanes cost the same), as a node visit does. The greedy collapse
// it replaces (Wald et al. 2008: open the child of largest area until eight) took 9.1 node visits
// per dragon AO ray, this one 8.7 (results/bvh/README.md). Every triangle keeps its caller's
// index, so both layouts report identical hits.
#include <vector>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

inline constexpr int kWideLeafMerge = kMaxLeafSize;
// SAH costs of the collapse per unit of area: a wide node visit and a SIMD leaf test. Equal
// costs measured as well as leaf costs of 0.7, 1.3, 1.5, 2 and 3 (dragon AO and primary rays,
// within the noise; higher leaf costs make more, smaller leaves).
inline constexpr double kWideNodeCost = 1.0;
inline constexpr double kWideLeafCost = 1.0;

struct WideBvh {
  std::vector<WideNode> nodes;
  std::vector<TriangleLanes> leaves;  // blocks: one full leaf or two compact ones (bvh.hpp)
};

// Collapses a binary tree (host copies of its nodes, and its triangles and prim ids in leaf
// order) into 8-wide nodes, depth first. Subtrees of at most `merge` triangles (contiguous in
// leaf order) may become one leaf.
WideBvh collapse_to_wide(const std::vector<BvhNode>& binary, const Triangle* tris, const int* prim,
                         int merge = kWideLeafMerge);

// Adds `delta` to the prim ids of every leaf that nodes [0, count) reference in `blocks` (trees
// appended into one array, whose ids become global).
void offset_leaf_prims(const WideNode* nodes, std::size_t count, TriangleLanes* blocks, int delta);

}  // namespace rtmini::bvh
