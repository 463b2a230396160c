#pragma once
// Where a view-dependent vertex keeps its colours: storage order. The N (or N/2) colours of a
// vertex sit in a direction-coherent order of its viewpoints, slot s holding viewpoint order[s],
// not in the Fibonacci order that files, checkpoints and the verification hash use. A lookup
// blends the ~8 viewpoints nearest one direction; in Fibonacci order they lie up to ~N/8
// entries apart (7.9 cache lines of a vertex's block per lookup at N = 200), in the coherent
// order mostly side by side (4.6 lines; results/bake/viewpoint_lines.py). The lookups stay in
// viewpoint indices and their sums in the same order, so no colour changes: only where it sits.
// The iterations work in storage order; the map is put in viewpoint order when it leaves them
// (checkpoint, output, comparison) and back into storage order when a restart reads it.
#include <cstdint>
#include <vector>

#include "rtmini/geometry/vec.hpp"

namespace rtmini::bake {

struct ViewOrder {
  std::vector<int> order;  // slot -> viewpoint
  std::vector<int> slot;   // viewpoint -> slot
};

// The first `stored` of n Fibonacci viewpoints (n, or n/2 for a hemisphere map) sorted into
// about sqrt(n/2) latitude bands, each walked in longitude, alternating direction (a
// serpentine), so consecutive slots are close on the sphere.
ViewOrder coherent_view_order(int n, int stored);

// A map's colours (vertex v at [offset[v], offset[v+1]): one colour, or one per stored viewpoint)
// from storage order to viewpoint order, and back, in place.
void to_viewpoint_order(const ViewOrder& o, const std::vector<std::int64_t>& offset,
                        std::vector<Vec3f>& colors);
void to_storage_order(const ViewOrder& o, const std::vector<std::int64_t>& offset,
                      std::vector<Vec3f>& colors);

}  // namespace rtmini::bake
