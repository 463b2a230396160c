#pragma once
// Evaluating AO at sample points: cosine-weighted hemisphere rays, shot in
// passes whose directions are coherent across samples (one jittered stratum
// per ray index, shared by every sample and rotated into its frame, as in the
// OptiX Prime baking sample), batch by batch so device memory stays bounded.
#include <cstdint>
#include <vector>

#include "device_scene.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/timer.hpp"
#include "sample_plan.hpp"

namespace rtmini::ao {

struct TraceSettings {
  int rays = 64;
  int passes = 1;
  std::int64_t batch = 2000000;
  std::uint64_t seed = 1;
  Real offset = 0;            // along the normal, world units
  Real max_distance = 1;      // world units
  Real coordinate_bound = 1;  // largest |world coordinate|, for offset_ray_origin
};

// Per-ray-index local directions (z = normal): ray k uses stratum k of an n x n
// grid (n = floor(sqrt(rays))) with one jitter per k; indices beyond n^2 are
// plain random. Identical for every sample, rank and pass split.
std::vector<Vec3> direction_table(int rays, std::uint64_t seed);

// World-space receiver triangles, their random-number items (sample_item) and
// sample offsets on the device (for generation).
struct DeviceSamplePlan {
  Kokkos::View<Triangle*, MemSpace> tris;
  Kokkos::View<std::uint64_t*, MemSpace> items;
  Kokkos::View<std::int64_t*, MemSpace> offsets;
};
DeviceSamplePlan upload_plan(const AoScene& scene, const SamplePlan& plan);

// Occluded-ray counts for sample points [first, last), in order. Timer phases:
// "samples" (point generation) and "rays" (tracing), summed over batches. `progress` (may be
// null) counts ray passes, their rays being the cost for the ETA; it is finished here.
std::vector<std::uint16_t> trace_samples(const OcclusionQuery& query, const DeviceSamplePlan& plan,
                                         const TraceSettings& settings, std::int64_t first,
                                         std::int64_t last, PhaseTimer& timer,
                                         ProgressLine* progress = nullptr);

// Occluded-ray counts for explicit points and unit normals (tests, probes).
std::vector<std::uint16_t> trace_points(const OcclusionQuery& query,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals,
                                        const TraceSettings& settings);

}  // namespace rtmini::ao
