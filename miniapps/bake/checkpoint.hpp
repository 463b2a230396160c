#pragma once
// Bake checkpoints (HDF5): the complete colour map after an iteration, the iteration number,
// a hash of every parameter that changes the result and the content hash of every input file.
// Written atomically by rank 0 after each all-gather; --restart validates the inputs, the
// hash and the map size, then resumes with the next iteration. The random streams are keyed by
// (seed, vertex, sample), so a resumed run produces the same bytes as an uninterrupted one.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/io/input_files.hpp"

namespace rtmini::bake {

struct Checkpoint {
  int iteration = -1;  // last completed iteration
  std::string parameter_hash;
  std::string inputs;  // every input file's content hash (io/input_files.hpp)
  std::int64_t vertices = 0;
  int viewpoints = 0;
  std::vector<Vec3f> colors;
};

void write_checkpoint(const std::string& path, const Checkpoint& cp);

// InputError ("path: reason") when the file is not a bake checkpoint or was written for other
// parameters; naming the input when an input file's content differs from `inputs`.
Checkpoint read_checkpoint(const std::string& path, const std::string& expected_hash,
                           const std::vector<InputFileHash>& inputs, std::int64_t expected_colors);

}  // namespace rtmini::bake
