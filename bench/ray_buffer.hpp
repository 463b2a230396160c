#pragma once
// The benchmark's rays, stored flat so rtmini and a peer trace the identical set.
#include <memory>
#include <string>
#include <vector>

#include "rtmini/geometry/triangle.hpp"

namespace rtmini::bench {

// Embree 3 on the benchmark's triangles, single-ray queries in an OpenMP loop. The bench calls
// build() and trace() alternately with its own passes, so machine load hits both alike.
class EmbreePeer {
 public:
  explicit EmbreePeer(const std::vector<Triangle>& tris);
  ~EmbreePeer();
  EmbreePeer(const EmbreePeer&) = delete;
  EmbreePeer& operator=(const EmbreePeer&) = delete;

  // (Re)builds the scene; returns the seconds it took.
  double build();
  // Traces `rays`, one by one (rtcIntersect1 / rtcOccluded1) or in packets of 8 consecutive rays
  // (rtcIntersect8 / rtcOccluded8); result per ray: prim id (closest) or 0/1 (any hit). Returns
  // the seconds.
  double trace(const std::vector<Ray>& rays, bool any_hit, std::vector<int>& result,
               bool packets = false) const;
  std::string version() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  const std::vector<Triangle>& tris_;
};

}  // namespace rtmini::bench
