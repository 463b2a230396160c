#pragma once
// Counter-based random numbers (Salmon et al., "Parallel Random Numbers: As
// Easy as 1, 2, 3", SC'11): Philox4x32-10 from Random123. A draw is a pure
// function of (run seed, item id, sample index, dimension), so results never
// depend on rank count, thread count, scheduling or restarts (docs/architecture.md §4).
#if defined(__CUDACC__)
// Random123 marks its CUDA functions __device__ only; Kokkos code calls them
// from __host__ __device__ functions, and its trap-based assert is device asm.
#ifndef R123_CUDA_DEVICE
#define R123_CUDA_DEVICE __host__ __device__
#endif
#ifndef R123_ASSERT
#define R123_ASSERT(x)
#endif
#endif
#include <Random123/philox.h>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

class Rng {
 public:
  // item: pixel or vertex (or sample point) id; sample: sample index within the item.
  KOKKOS_INLINE_FUNCTION Rng(std::uint64_t seed, std::uint64_t item, std::uint32_t sample) {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    ctr_ = {{static_cast<std::uint32_t>(item), static_cast<std::uint32_t>(item >> 32), sample, 0u}};
  }

  // Four independent 32-bit words for dimension block `dim4` (dimensions 4*dim4 .. 4*dim4+3).
  KOKKOS_FORCEINLINE_FUNCTION r123::Philox4x32::ctr_type block(std::uint32_t dim4) const {
    r123::Philox4x32::ctr_type c = ctr_;
    c.v[3] = dim4;
    return r123::Philox4x32()(c, key_);
  }

  // Uniform float in [0, 1) for a given dimension; 24 random bits.
  KOKKOS_INLINE_FUNCTION float uniform(std::uint32_t dim) const {
    return to_unit(block(dim >> 2).v[dim & 3u]);
  }

  // Two uniforms for dimensions (2*pair, 2*pair+1) from one Philox call.
  KOKKOS_FORCEINLINE_FUNCTION void uniform2(std::uint32_t pair, float& a, float& b) const {
    const auto r = block(pair >> 1);
    const unsigned o = (pair & 1u) * 2u;
    a = to_unit(r.v[o]);
    b = to_unit(r.v[o + 1]);
  }

  KOKKOS_INLINE_FUNCTION static float to_unit(std::uint32_t x) {
    return static_cast<float>(x >> 8) * (1.0f / 16777216.0f);
  }

 private:
  r123::Philox4x32::key_type key_;
  r123::Philox4x32::ctr_type ctr_;
};

}  // namespace rtmini
