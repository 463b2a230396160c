#pragma once
// Stratified jittered sample positions (Cook et al. 1984; distribution seed):
// n strata on a sqrt(n) x sqrt(n) grid when n is a perfect square, otherwise
// n-rooks (Latin hypercube) strata: x stratum = i, y stratum = an affine
// permutation of i keyed per pixel, so every row and column holds one sample.
#include <cstdint>

#include "rtmini/kokkos_compat.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::sketch {

KOKKOS_INLINE_FUNCTION int isqrt_exact(int n) {
  int r = static_cast<int>(math::sqrt(static_cast<double>(n)) + 0.5);
  return r * r == n ? r : 0;
}

KOKKOS_INLINE_FUNCTION int gcd(int a, int b) {
  while (b != 0) {
    const int t = a % b;
    a = b;
    b = t;
  }
  return a;
}

// A bijection of [0, n) chosen by `key`: i -> (a i + b) mod n with gcd(a, n) = 1.
KOKKOS_INLINE_FUNCTION int permute(int i, int n, std::uint32_t key) {
  if (n <= 1) return 0;
  int a = static_cast<int>(hash_u32(key) % static_cast<std::uint32_t>(n));
  if (a == 0) a = 1;
  while (gcd(a, n) != 1) a = a + 1 < n ? a + 1 : 1;
  const int b = static_cast<int>(hash_u32(key ^ 0x9e3779b9u) % static_cast<std::uint32_t>(n));
  return static_cast<int>((static_cast<long long>(a) * i + b) % n);
}

// Sample `index` of `count` strata in [0,1)^2, jittered by (u1, u2); `side` is
// isqrt_exact(count), for loops that hoist it.
template <class T>
KOKKOS_FORCEINLINE_FUNCTION void stratum_2d(int index, int count, int side, std::uint32_t key, T u1,
                                            T u2, T& x, T& y) {
  if (side > 0) {
    stratified_2d(index, side, u1, u2, x, y);
    return;
  }
  x = (T(index) + u1) / T(count);
  y = (T(permute(index, count, key)) + u2) / T(count);
}

template <class T>
KOKKOS_INLINE_FUNCTION void stratum_2d(int index, int count, std::uint32_t key, T u1, T u2, T& x,
                                       T& y) {
  stratum_2d(index, count, isqrt_exact(count), key, u1, u2, x, y);
}

// Guard against 1.0 after float rounding of (i + u) / n.
template <class T>
KOKKOS_INLINE_FUNCTION T below_one(T x) {
  return x < T(1) ? x : T(0.99999994f);
}

}  // namespace rtmini::sketch
