#pragma once
// Paper grain (hand-drawn seed §6): fractal sum of Perlin's improved gradient
// noise (Perlin, "Improving Noise", SIGGRAPH 2002), discretised to a few levels.
// The seed's shader repeated visibly; a 256-entry permutation makes the lattice
// periodic with 256 cells, so here every octave has its own seeded permutation,
// rotation and offset: no lattice period lines up with the image axes.
#include <cstdint>

#include "npr.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::npr {

inline constexpr int kMaxOctaves = 8;
inline constexpr int kPermSize = 256;

using PermutationView =
    Kokkos::View<int**, Kokkos::LayoutRight, Kokkos::DefaultExecutionSpace::memory_space>;

struct PaperParams {
  float scale = 1.f;  // pixels per lattice cell, coarsest octave
  int octaves = 1;
  int levels = 2;
  float strength = 0.f;
  float cos_a[kMaxOctaves] = {}, sin_a[kMaxOctaves] = {};
  float off_x[kMaxOctaves] = {}, off_y[kMaxOctaves] = {}, off_z[kMaxOctaves] = {};
};

// Per-octave seeded permutations (perm(o, i), i < 2 * kPermSize, second half
// repeating the first as in Perlin's reference) and the octaves' rotations/offsets.
void make_paper(const NprConfig& config, PaperParams& params, PermutationView& perm);

namespace detail {
KOKKOS_INLINE_FUNCTION float fade(float t) { return t * t * t * (t * (t * 6.f - 15.f) + 10.f); }
KOKKOS_INLINE_FUNCTION float lerp(float t, float a, float b) { return a + t * (b - a); }
// Dot product with one of the 12 cube-edge gradients (4 repeated), chosen by hash h.
KOKKOS_INLINE_FUNCTION float grad(int h, float x, float y, float z) {
  const int k = h & 15;
  const float u = k < 8 ? x : y;
  const float v = k < 4 ? y : (k == 12 || k == 14 ? x : z);
  return ((k & 1) ? -u : u) + ((k & 2) ? -v : v);
}
}  // namespace detail

// Improved noise at (x, y, z) with permutation row `o`; in about [-1, 1], 0 on the lattice.
template <class Perm>
KOKKOS_INLINE_FUNCTION float improved_noise(const Perm& perm, int o, float x, float y, float z) {
  const float fx = math::floor(x), fy = math::floor(y), fz = math::floor(z);
  const int X = static_cast<int>(fx) & (kPermSize - 1);
  const int Y = static_cast<int>(fy) & (kPermSize - 1);
  const int Z = static_cast<int>(fz) & (kPermSize - 1);
  x -= fx;
  y -= fy;
  z -= fz;
  const float u = detail::fade(x), v = detail::fade(y), w = detail::fade(z);
  const int A = perm(o, X) + Y, AA = perm(o, A) + Z, AB = perm(o, A + 1) + Z;
  const int B = perm(o, X + 1) + Y, BA = perm(o, B) + Z, BB = perm(o, B + 1) + Z;
  using detail::grad;
  using detail::lerp;
  return lerp(
      w,
      lerp(v, lerp(u, grad(perm(o, AA), x, y, z), grad(perm(o, BA), x - 1, y, z)),
           lerp(u, grad(perm(o, AB), x, y - 1, z), grad(perm(o, BB), x - 1, y - 1, z))),
      lerp(v, lerp(u, grad(perm(o, AA + 1), x, y, z - 1), grad(perm(o, BA + 1), x - 1, y, z - 1)),
           lerp(u, grad(perm(o, AB + 1), x, y - 1, z - 1),
                grad(perm(o, BB + 1), x - 1, y - 1, z - 1))));
}

// Normalised fractal sum (gain 1/2, lacunarity 2) at pixel centre (px, py).
KOKKOS_INLINE_FUNCTION float paper_fbm(const PaperParams& p, const PermutationView& perm, float px,
                                       float py) {
  float sum = 0.f, amp = 1.f, norm = 0.f, freq = 1.f / p.scale;
  for (int o = 0; o < p.octaves; ++o) {
    const float x = px * freq, y = py * freq;
    const float rx = p.cos_a[o] * x - p.sin_a[o] * y + p.off_x[o];
    const float ry = p.sin_a[o] * x + p.cos_a[o] * y + p.off_y[o];
    sum += amp * improved_noise(perm, o, rx, ry, p.off_z[o]);
    norm += amp;
    amp *= 0.5f;
    freq *= 2.f;
  }
  return sum / norm;
}

// Typical magnitude of paper_fbm (measured standard deviation is about 0.2);
// the discretisation spreads +-kPaperSpread over the levels.
inline constexpr float kPaperSpread = 0.5f;

// Paper reflectance factor in [1 - strength, 1] at pixel (x, y), `levels` distinct values.
KOKKOS_INLINE_FUNCTION float paper_factor(const PaperParams& p, const PermutationView& perm, int x,
                                          int y) {
  const float n = paper_fbm(p, perm, float(x) + 0.5f, float(y) + 0.5f);
  const float t = math::clamp(0.5f + n / (2.f * kPaperSpread), 0.f, 0.99999f);
  const float q = math::floor(t * float(p.levels)) / float(p.levels - 1);
  return 1.f - p.strength * (1.f - q);
}

}  // namespace rtmini::npr
