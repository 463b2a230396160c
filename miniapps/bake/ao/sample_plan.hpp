#pragma once
// Where the AO sample points go (the sample's scheme): a minimum per face, the
// rest spread by area, each at random barycentrics (u = 1 - sqrt(r1),
// v = r2 sqrt(r1)). Point k of triangle t of stored mesh m is a pure function of
// (seed, m, t, k): any rank can generate any range, the host regenerates them for
// the mapping, and instances of one mesh with the same per-triangle counts get
// the same barycentrics (so their least-squares systems share one factorization).
#include <cstdint>
#include <vector>

#include "ao_scene.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::ao {

// Random-number item of triangle `tri` of stored mesh `mesh` (40 bits of triangle index).
KOKKOS_INLINE_FUNCTION std::uint64_t sample_item(int mesh, std::int64_t tri) {
  return (static_cast<std::uint64_t>(mesh) << 40) | static_cast<std::uint64_t>(tri);
}

// Barycentrics (u, v) of the 2nd and 3rd vertex for point `sample` of triangle `item`.
KOKKOS_INLINE_FUNCTION void sample_barycentrics(std::uint64_t seed, std::uint64_t item,
                                                std::int64_t sample, Real& u, Real& v) {
  float r1, r2;
  Rng(seed, item, static_cast<std::uint32_t>(sample)).uniform2(0, r1, r2);
  uniform_triangle(Real(r1), Real(r2), u, v);
}

struct SamplePlan {
  std::vector<int> receivers;  // instance ids receiving samples, in scene order
  std::vector<int> meshes;     // stored mesh of each receiver
  std::vector<std::int64_t>
      tri_base;  // receiver r owns global triangles [tri_base[r], tri_base[r+1])
  std::vector<std::int64_t>
      vertex_base;  // receiver r owns output vertices [vertex_base[r], vertex_base[r+1])
  std::vector<std::int64_t> offsets;  // global triangle g owns samples [offsets[g], offsets[g+1])
  std::vector<double> areas;          // world-space area of each global triangle
  // Area of each global triangle / mean triangle area of its receiver. Taken in
  // object space when the receiver's transform is a similarity, so instances of
  // one mesh under rigid (or equally scaled) transforms have bit-identical values.
  std::vector<double> relative_areas;
  std::int64_t total_samples() const { return offsets.empty() ? 0 : offsets.back(); }
  std::int64_t total_vertices() const { return vertex_base.empty() ? 0 : vertex_base.back(); }
  std::int64_t total_triangles() const { return tri_base.empty() ? 0 : tri_base.back(); }
  std::int64_t sample_count(std::int64_t g) const { return offsets[g + 1] - offsets[g]; }
  // Random-number item of global triangle g of receiver r.
  std::uint64_t item(std::size_t r, std::int64_t g) const {
    return sample_item(meshes[r], g - tri_base[r]);
  }
};

// total = max(requested, min_per_face * triangles). The E extra points go to
// receivers by area: receivers of one mesh under similarities of one scale form
// a class, classes get floor(E * C_c / A) - floor(E * C_{c-1} / A) (C: running
// area, A: total), a class splits its share evenly (the first members take the
// remainder), and a receiver hands its share to its triangles the same way by
// relative area. Exact total; identical instances get identical counts.
SamplePlan plan_samples(const AoScene& scene, std::int64_t requested, int min_per_face);

}  // namespace rtmini::ao
