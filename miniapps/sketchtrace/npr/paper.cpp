#include "paper.hpp"

#include <cmath>

#include "rtmini/report/hash.hpp"
#include "rtmini/sampling/rng.hpp"

namespace rtmini::npr {

void make_paper(const NprConfig& config, PaperParams& params, PermutationView& perm) {
  const std::uint64_t seed = mix64(config.seed ^ 0x7061706572ULL);
  params.scale = config.paper_scale;
  params.octaves = config.paper_octaves;
  params.levels = config.paper_levels;
  params.strength = config.paper_strength;
  perm = PermutationView("rtmini::sketchtrace::npr::paper_perm", params.octaves, 2 * kPermSize);
  auto host = Kokkos::create_mirror_view(perm);
  for (int o = 0; o < params.octaves; ++o) {
    // Fisher-Yates with counter-based draws: a pure function of (seed, octave).
    int table[kPermSize];
    for (int i = 0; i < kPermSize; ++i) table[i] = i;
    for (int i = kPermSize - 1; i > 0; --i) {
      const float u =
          Rng(seed, static_cast<std::uint64_t>(o), static_cast<std::uint32_t>(i)).uniform(0u);
      const int j = static_cast<int>(u * float(i + 1));
      const int t = table[i];
      table[i] = table[j];
      table[j] = t;
    }
    for (int i = 0; i < 2 * kPermSize; ++i) host(o, i) = table[i & (kPermSize - 1)];
    const Rng r(seed, static_cast<std::uint64_t>(o), 0xffffffffu);
    const double angle = 2.0 * math::kPi * r.uniform(0u);
    params.cos_a[o] = static_cast<float>(std::cos(angle));
    params.sin_a[o] = static_cast<float>(std::sin(angle));
    params.off_x[o] = float(kPermSize) * r.uniform(1u);
    params.off_y[o] = float(kPermSize) * r.uniform(2u);
    // A non-integer z slice so the lattice zeros of the 3D noise are avoided.
    params.off_z[o] = float(kPermSize) * r.uniform(3u);
  }
  Kokkos::deep_copy(perm, host);
}

}  // namespace rtmini::npr
