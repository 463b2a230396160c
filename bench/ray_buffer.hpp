#pragma once
// The benchmark's rays, stored flat so rtmini and a peer trace the identical set.
#include <string>
#include <vector>

#include "rtmini/geometry/triangle.hpp"

namespace rtmini::bench {

struct PeerResult {
  double build_seconds = 0;
  double trace_seconds = 0;
  std::vector<int> result;  // per ray: prim id (closest) or 0/1 (any hit)
  std::string version;
};

// Traces `rays` with Embree 3 single-ray queries in an OpenMP loop.
PeerResult trace_with_embree(const std::vector<Triangle>& tris, const std::vector<Ray>& rays,
                             bool any_hit, int repeats);

}  // namespace rtmini::bench
