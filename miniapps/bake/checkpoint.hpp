#pragma once
// Bake checkpoints (HDF5): the complete colour map after an iteration, the iteration number
// and a hash of every parameter that changes the result. Written atomically by rank 0 after
// each all-gather; --restart validates the hash and the map size, then resumes with the next
// iteration. The random streams are keyed by (seed, vertex, sample), so a resumed run
// produces the same bytes as an uninterrupted one.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"

namespace rtmini::bake {

struct Checkpoint {
  int iteration = -1;  // last completed iteration
  std::string parameter_hash;
  std::int64_t vertices = 0;
  int viewpoints = 0;
  std::vector<Vec3f> colors;
};

void write_checkpoint(const std::string& path, const Checkpoint& cp);

// InputError ("path: reason") when the file is not a bake checkpoint or was written for other
// parameters or another scene.
Checkpoint read_checkpoint(const std::string& path, const std::string& expected_hash,
                           std::int64_t expected_colors);

}  // namespace rtmini::bake
