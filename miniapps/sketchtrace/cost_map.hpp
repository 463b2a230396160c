#pragma once
// The cost map of the `metric`, `chunks` and `bargain` strategies: one probe
// camera sample (full shadow sampling, no anti-aliasing, no stencil) per 4x4
// pixel block; the rays it traces estimate the block's cost per sample. Ranks
// share the probes and all-gather the map. `--cost-map FILE` keeps it: a later
// run with the same scene, parameters, camera and resolution reads it instead.
#include <string>

#include "renderer.hpp"
#include "rtmini/parallel/communicator.hpp"
#include "schedule.hpp"

namespace rtmini::sketch {

// `reused` tells whether the map came from `path` (empty path: always probe).
CostMap make_cost_map(const Renderer& renderer, const Communicator& comm, int width, int height,
                      const std::string& path, const std::string& signature, bool& reused);

}  // namespace rtmini::sketch
