#pragma once
// Pre-splitting of long thin triangles before the SAH build (Ernst & Greiner 2007, "Early split
// clipping"; planes on a power-of-two grid of the scene box as in Dammertz & Keller 2008, "The
// edge volume heuristic"). A diagonal sliver's bounding box is mostly empty space, so every ray
// through that space tests it; no object split can fix that, since each triangle has one box.
// Here such a triangle becomes several references, each with the box of the part of the
// triangle inside one grid cell; the builder sorts the references like triangles, and a leaf
// stores the triangle itself (each reference tests the whole triangle, so hits are unchanged).
//
// When it is used: the sum of the references' box areas over the root's area is the number of
// triangle boxes a random ray crosses (the leaf term of the surface-area heuristic with one
// triangle per leaf). Splitting is kept only when it lowers that sum by kPresplitMinGain or
// more within the budget; ordinary meshes, whose triangles fill their boxes, keep their trees.
#include <vector>

#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// Extra references allowed, as a fraction of the triangle count. On a flat fan of slivers the
// tests per ray fall only as 1 / (1 + budget) (results/bvh/slivers.md), so 1.0 halves them at
// twice the tree size, paid only by scenes where splitting is kept.
inline constexpr double kDefaultSplitBudget = 1.0;
// Splitting must remove at least this fraction of the summed box area to be kept.
inline constexpr double kPresplitMinGain = 0.1;

struct SplitReference {
  Aabb box;
  Vec3 centroid;  // the triangle's centroid when unsplit, else the centre of the part's box
  int prim;
};

// The references to build from: empty when splitting does not pay (build from the triangles
// as they are), else one or more per triangle, at most (1 + budget) x the triangle count.
std::vector<SplitReference> presplit_triangles(const std::vector<Triangle>& tris,
                                               const Aabb& bounds, double budget);

}  // namespace rtmini::bvh
