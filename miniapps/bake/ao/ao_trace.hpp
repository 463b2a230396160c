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

// Side n of the n x n grid of ray strata: n = floor(sqrt(rays)).
int stratum_side(int rays);

// Local direction (z = normal) of ray k of every sample point of instance `key`: stratum k of
// the n x n grid (n = stratum_side) with one jitter keyed by (seed, key, k), cosine-warped;
// indices beyond n^2 are plain random. Identical for every sample point of the instance, rank
// and pass split, so directions stay coherent across the points of an instance (the sample's
// passes). Keyed per instance: instances share their sample points (one least-squares
// factorisation serves them all) but not their rays, so identical instances under identical
// occluders do not repeat each other's noise; each instance's set stays fully stratified.
KOKKOS_INLINE_FUNCTION Vec3 ray_direction(std::uint64_t seed, std::uint32_t key, int k, int side) {
  float jx, jy;
  // Item ids with the top bit set are used by nothing else (sample_item: mesh << 40 | triangle).
  const std::uint64_t item =
      (std::uint64_t(1) << 63) | (std::uint64_t(key) << 32) | static_cast<std::uint32_t>(k);
  Rng(seed, item, 0u).uniform2(0, jx, jy);
  Real u1 = jx, u2 = jy;
  if (k < side * side) stratified_2d(k, side, Real(jx), Real(jy), u1, u2);
  return cosine_hemisphere(u1, u2);
}

// World-space receiver triangles, their random-number items (sample_item), ray keys (the
// receiver's instance id) and sample offsets on the device (for generation).
struct DeviceSamplePlan {
  Kokkos::View<Triangle*, MemSpace> tris;
  Kokkos::View<std::uint64_t*, MemSpace> items;
  Kokkos::View<std::uint32_t*, MemSpace> ray_keys;
  Kokkos::View<std::int64_t*, MemSpace> offsets;
};
// Formed on the device from the stored meshes already there (DeviceScene::meshes()) and the
// receivers' transforms, with the host's arithmetic: the same bits as the host expanding them.
DeviceSamplePlan upload_plan(const StoredMeshes& meshes, const AoScene& scene,
                             const SamplePlan& plan);
// The same, uploading the stored meshes first (tests).
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
