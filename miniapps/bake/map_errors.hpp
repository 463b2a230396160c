#pragma once
// Error of a baked map against a reference map of the same scene (issue 7), per vertex and
// reference viewpoint, over RGB. The reference is typically `bake --trace-reference`: the
// colours traced directly along every viewpoint (reference_tracer.hpp). It may have another
// N than the map: the map is then read along each reference direction with the bake's lookup
// (the ~8 nearest viewpoints, as a renderer reads it), so a dense reference measures the
// map between its viewpoints too. With the same N the stored colours are also compared
// viewpoint by viewpoint.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::bake {

// Sums over compared values (entries x RGB), from which MapErrors follows.
struct ErrorSums {
  double abs = 0, sq = 0, rel = 0, ref = 0, view_dependent_sq = 0, max_abs = 0;
  std::int64_t entries = 0, view_dependent = 0;
};

struct MapErrors {
  std::int64_t entries = 0;          // vertices x reference viewpoints
  double mean_abs = 0;               // mean over entries and RGB of |map - ref|
  double rmse = 0;                   // sqrt(mean of (map - ref)^2)
  double rel_mse = 0;                // mean of (map - ref)^2 / (ref^2 + 1e-2), as for images
  double max_abs = 0;                // largest |map - ref| of any entry and channel
  double mean_reference = 0;         // mean reference value (scale of the errors above)
  std::int64_t view_dependent = 0;   // entries of vertices with N colours in the map
  double view_dependent_rmse = 0;    // RMSE over those entries only (0 if none)
  double view_independent_rmse = 0;  // RMSE over the other entries (0 if none)
};

// Adds one entry's colours to the sums.
inline void add_error(ErrorSums& s, const Vec3& map, const Vec3& ref, bool view_dependent) {
  const double a[3] = {double(map.x), double(map.y), double(map.z)};
  const double b[3] = {double(ref.x), double(ref.y), double(ref.z)};
  for (int c = 0; c < 3; ++c) {
    const double d = a[c] - b[c], ad = d < 0 ? -d : d;
    s.abs += ad;
    s.sq += d * d;
    s.rel += d * d / (b[c] * b[c] + 1e-2);
    s.ref += b[c];
    if (ad > s.max_abs) s.max_abs = ad;
    if (view_dependent) s.view_dependent_sq += d * d;
  }
  ++s.entries;
  if (view_dependent) ++s.view_dependent;
}

MapErrors errors_from_sums(const ErrorSums& s);

struct ReferenceMap {
  int viewpoints = 0;         // N of the reference
  std::vector<Vec3f> colors;  // vertex v, viewpoint i at v N + i
};

// Reads a baked .bs map as a reference for `mesh`: the same vertices (count and positions)
// and the same N >= 1 viewpoints at every vertex in the bake's Fibonacci order; anything else
// is an InputError naming the file.
ReferenceMap read_reference_map(const std::string& path, const Mesh& mesh);

// Stored colours against a reference of the same N, viewpoint by viewpoint. The map has the
// layout of BakeSceneHost: vertex v owns [offset[v], offset[v+1]), one colour for all
// viewpoints when that range has one entry.
MapErrors compare_stored(const std::vector<Vec3f>& map, const std::vector<std::int64_t>& offset,
                         const ReferenceMap& reference);

}  // namespace rtmini::bake
