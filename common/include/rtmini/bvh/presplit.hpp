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
//
// The auto budget (the default) starts like a budget of 1 and then doubles the references while
// each doubling still removes kAutoStepMinGain of the summed box area that is left. Why that
// rule: a doubling costs twice the references (memory and build time grow about linearly with
// them) and adds about one level to the tree, while the leaf term, and with it the triangle
// tests per ray, falls by the area the doubling removes. On a flat fan of slivers each doubling
// halves it (tests per ray x references per triangle stays constant: results/bvh/slivers.md), so
// the budget grows to its ceiling; on an ordinary mesh the first step already fails the
// kPresplitMinGain check and the tree is the unsplit one, bit for bit. The doubling that does not
// remove its share is undone, so a mesh with a few slivers among ordinary triangles stops where
// the slivers are cut small enough.
#include <cstddef>
#include <vector>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// The default is auto (build_quality.hpp). A number gives a fixed budget: on a flat fan of
// slivers the tests per ray fall as 1 / (1 + budget) (results/bvh/slivers.md).
inline constexpr double kDefaultSplitBudget = kAutoSplitBudget;
// Splitting must remove at least this fraction of the summed box area to be kept.
inline constexpr double kPresplitMinGain = 0.1;
// Auto: each doubling of the references must remove this fraction of the summed box area left.
inline constexpr double kAutoStepMinGain = 0.25;
// Auto: at most this many references per triangle (on the 100K-sliver fan: ~70 tests per ray)
// and this many in all. The total bounds the memory: the whole SAH build peaks at about 250
// bytes per reference on the host (the pre-split parts and their undo record, the builder's
// items, the binary and the 8-wide trees: 3.2 GB for the fan's 12.8M references,
// results/bvh/slivers.md), so at most ~4 GB; the finished host tree keeps ~120 of them.
inline constexpr double kAutoMaxReferencesPerTriangle = 128;
inline constexpr std::size_t kAutoMaxReferences = std::size_t(1) << 24;
// Spatial splits (build_sah.cpp) under the auto budget use this fixed one.
inline constexpr double kSpatialSplitAutoBudget = 1.0;

// The caller's triangles, read in place by the host SAH build and the pre-splitting: a view of
// a std::vector or of a host array (the build's input is no longer copied into a vector first:
// 3.6 MB of copy and fresh pages per dragon build).
class TriangleSpan {
 public:
  // Implicit from a vector, so the callers that hold one pass it as before.
  TriangleSpan(const std::vector<Triangle>& v) : data_(v.data()), size_(v.size()) {}
  TriangleSpan(const Triangle* data, std::size_t size) : data_(data), size_(size) {}
  const Triangle& operator[](std::size_t i) const { return data_[i]; }
  std::size_t size() const { return size_; }
  const Triangle* begin() const { return data_; }
  const Triangle* end() const { return data_ + size_; }

 private:
  const Triangle* data_;
  std::size_t size_;
};

struct SplitReference {
  Aabb box;
  Vec3 centroid;  // the triangle's centroid when unsplit, else the centre of the part's box
  int prim;
};

// The references to build from: empty when splitting does not pay (build from the triangles
// as they are), else one or more per triangle, at most (1 + budget) x the triangle count (auto:
// see above). The same for any thread count.
std::vector<SplitReference> presplit_triangles(TriangleSpan tris, const Aabb& bounds,
                                               double budget);

}  // namespace rtmini::bvh
