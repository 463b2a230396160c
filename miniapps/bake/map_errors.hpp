#pragma once
// Error of a baked map against a reference map of the same scene and viewpoints (issue 7): per
// vertex and viewpoint, over RGB. The reference is typically `bake --trace-reference`, the
// colours traced directly along every viewpoint (reference_tracer.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::bake {

struct MapErrors {
  std::int64_t entries = 0;         // vertices x viewpoints
  double mean_abs = 0;              // mean over entries and RGB of |map - ref|
  double rmse = 0;                  // sqrt(mean of (map - ref)^2)
  double rel_mse = 0;               // mean of (map - ref)^2 / (ref^2 + 1e-2), as for images
  double max_abs = 0;               // largest |map - ref| of any entry and channel
  double mean_reference = 0;        // mean reference value (scale of the errors above)
  std::int64_t view_dependent = 0;  // entries of vertices with N colours in the map
  double view_dependent_rmse = 0;   // RMSE over those entries only (0 if none)
};

// Colours of a baked .bs map at `path`, vertex-major (vertex v, viewpoint i at v N + i). The
// map must have the vertices of `mesh` (same count and positions) and N = `viewpoints` per
// vertex in the bake's Fibonacci order; anything else is an InputError naming the file.
std::vector<Vec3f> read_reference_map(const std::string& path, const Mesh& mesh, int viewpoints);

// Compares a bake's colours (layout of BakeSceneHost: vertex v owns [offset[v], offset[v+1]),
// one colour for all viewpoints when that range has one entry) with a reference laid out as
// read_reference_map returns it.
MapErrors compare_maps(const std::vector<Vec3f>& map, const std::vector<std::int64_t>& offset,
                       const std::vector<Vec3f>& reference, int viewpoints);

}  // namespace rtmini::bake
