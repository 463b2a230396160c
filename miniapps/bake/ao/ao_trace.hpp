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
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
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

// A point of the unit square, [0, 1)^2.
struct SquarePoint {
  Real x, y;
};

// Per-ray-index points of the unit square: ray k uses stratum k of an n x n grid
// (n = floor(sqrt(rays))) with one jitter per k; indices beyond n^2 are plain random.
// Identical for every sample, rank and pass split.
std::vector<SquarePoint> stratum_table(int rays, std::uint64_t seed);

// Rays are keyed per instance: every sample point of instance `key` shifts the table by the
// same random offset modulo 1 (a Cranley-Patterson rotation, so each instance's set stays an
// unbiased stratified one) before the cosine warp. Instances share their sample points (one
// least-squares factorisation serves them all) but not their rays, so identical instances
// under identical occluders do not repeat each other's noise.
KOKKOS_INLINE_FUNCTION SquarePoint ray_key_shift(std::uint64_t seed, std::uint32_t key) {
  float a, b;
  // Item ids with the top bit set are used by nothing else (sample_item, stratum_table).
  Rng(seed, (std::uint64_t(1) << 63) | key, 0u).uniform2(0, a, b);
  return {Real(a), Real(b)};
}

// Local direction (z = normal) of ray `u` of the table shifted by `shift`.
KOKKOS_INLINE_FUNCTION Vec3 keyed_direction(const SquarePoint& u, const SquarePoint& shift) {
  Real x = u.x + shift.x, y = u.y + shift.y;
  if (x >= Real(1)) x -= Real(1);
  if (y >= Real(1)) y -= Real(1);
  return cosine_hemisphere(x, y);
}

// World-space receiver triangles, their random-number items (sample_item), ray keys (the
// receiver's instance id) and sample offsets on the device (for generation).
struct DeviceSamplePlan {
  Kokkos::View<Triangle*, MemSpace> tris;
  Kokkos::View<std::uint64_t*, MemSpace> items;
  Kokkos::View<std::uint32_t*, MemSpace> ray_keys;
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

// Occluded-ray counts for explicit points and unit normals (tests, probes), with ray key 0
// (or `keys`, one per point, when given).
std::vector<std::uint16_t> trace_points(const OcclusionQuery& query,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals,
                                        const TraceSettings& settings,
                                        const std::vector<std::uint32_t>& keys = {});

}  // namespace rtmini::ao
