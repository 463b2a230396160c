#pragma once
// Checkpoint/restart of a render (docs/architecture.md §6): rank 0 keeps the pixels finished
// so far and writes them, atomically, to an HDF5 file; a restart renders only the others.
// Pixels depend only on (scene, parameters, seed, pixel), so a resumed render is
// bit-identical to an uninterrupted one. The file carries a signature of the
// parameters and the content hash of every input file, and refuses a restart with different
// ones.
#include <cstdint>
#include <string>
#include <vector>

#include "pixel_result.hpp"

namespace rtmini::sketch {

struct Checkpoint {
  int width = 0, height = 0;
  std::string signature;            // parameters + scene, as JSON text
  std::string inputs;               // every input file's content hash (io/input_files.hpp)
  std::vector<std::uint8_t> done;   // [width * height], 1 = finished
  std::vector<PixelResult> pixels;  // [width * height], valid where done
};

void write_checkpoint(const std::string& path, const Checkpoint& c);
// InputError when the file is unreadable or not a sketchtrace checkpoint.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace rtmini::sketch
