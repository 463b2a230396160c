#pragma once
// --write-workload: the bench's triangles, rays and rtmini's answers in one flat file, so that
// a peer built outside this project (tinybvh or ArborX on a GPU, results/gpu/README.md) traces
// the identical rays and its answers can be compared ray by ray. Little-endian:
//   char[8]  "RTMWORK1"
//   uint32   any_hit (1: answers are 0/1 "blocked"; 0: closest-hit triangle index or -1)
//   uint32   reserved (0)
//   uint64   T triangles, uint64 R rays
//   T x float32[9]  vertices a, b, c (x y z each)
//   R x float32[8]  origin, direction, tmin, tmax
//   R x int32       rtmini's answer
// Always float32: a double build (RTMINI_DOUBLE) writes its values rounded.
#include <cstdint>
#include <string>

#include "rtmini/geometry/ray.hpp"
#include "rtmini/geometry/triangle.hpp"

namespace rtmini::bench {

struct WorkloadView {
  const Triangle* tris = nullptr;
  std::uint64_t num_tris = 0;
  const Ray* rays = nullptr;
  const int* answers = nullptr;
  std::uint64_t num_rays = 0;
  bool any_hit = false;
};

// The file's size for T triangles and R rays.
std::int64_t workload_file_bytes(std::uint64_t num_tris, std::uint64_t num_rays);

// Writes `w` to `path` atomically (io/atomic_file.hpp); IoError on failure.
void write_workload(const std::string& path, const WorkloadView& w);

}  // namespace rtmini::bench
