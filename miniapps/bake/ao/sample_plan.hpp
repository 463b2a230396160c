#pragma once
// Where the AO sample points go (the sample's scheme): a minimum per face, the
// rest spread by area, each at random barycentrics (u = 1 - sqrt(r1),
// v = r2 sqrt(r1)). Point s is a pure function of (seed, s), so any rank can
// generate any range and the host can regenerate them for the mapping.
#include <cstdint>
#include <vector>

#include "ao_scene.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::ao {

struct SamplePlan {
  std::vector<int> receivers;  // instance ids receiving samples, in scene order
  std::vector<std::int64_t>
      tri_base;  // receiver r owns global triangles [tri_base[r], tri_base[r+1])
  std::vector<std::int64_t>
      vertex_base;  // receiver r owns output vertices [vertex_base[r], vertex_base[r+1])
  std::vector<std::int64_t> offsets;  // global triangle g owns samples [offsets[g], offsets[g+1])
  std::vector<double> areas;          // world-space area of each global triangle
  std::int64_t total_samples() const { return offsets.empty() ? 0 : offsets.back(); }
  std::int64_t total_vertices() const { return vertex_base.empty() ? 0 : vertex_base.back(); }
  std::int64_t total_triangles() const { return tri_base.empty() ? 0 : tri_base.back(); }
};

// total = max(requested, min_per_face * triangles); triangle g gets min_per_face plus
// floor(E * C_g / A) - floor(E * C_{g-1} / A) of the E extra points (C: running area,
// A: total area), which hands out exactly E points in proportion to area.
SamplePlan plan_samples(const AoScene& scene, std::int64_t requested, int min_per_face);

// Barycentrics (u, v) of the 2nd and 3rd vertex for sample point `id`.
KOKKOS_INLINE_FUNCTION void sample_barycentrics(std::uint64_t seed, std::int64_t id, Real& u,
                                                Real& v) {
  float r1, r2;
  Rng(seed, static_cast<std::uint64_t>(id), 0u).uniform2(0, r1, r2);
  uniform_triangle(Real(r1), Real(r2), u, v);
}

}  // namespace rtmini::ao
