#pragma once
// The `--cost-map FILE` format (HDF5): attributes app = "sketchtrace-cost-map",
// signature, width, height, stride, and the dataset /cost ([grid_h * grid_w] floats).
// Kept apart from cost_map.cpp (which probes with the renderer) so the reader has no
// Kokkos dependency: the fuzz sub-build (tests/fuzz) compiles it on its own.
#include <cstddef>
#include <string>
#include <vector>

namespace rtmini::sketch {

// The identity of a map: what it was probed for.
struct CostMapKey {
  std::string signature;  // scene + parameters
  int width = 0, height = 0, stride = 0;
};

// False when there is no file at `path` (or `path` is empty) or it was probed for
// another key: the caller probes again and replaces it. True with `cost` filled when
// the map matches and holds exactly `cells` values. A corrupt file or one of the wrong
// size is an InputError (exit 2), never used; a path naming something other than a regular
// file is an IoError (exit 3: it could not be replaced either).
bool read_cost_map_file(const std::string& path, const CostMapKey& key, std::size_t cells,
                        std::vector<float>& cost);

void write_cost_map_file(const std::string& path, const CostMapKey& key,
                         const std::vector<float>& cost);

}  // namespace rtmini::sketch
