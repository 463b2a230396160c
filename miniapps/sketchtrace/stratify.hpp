#pragma once
// Stratified jittered sample positions (Cook et al. 1984; distribution seed):
// n strata on a jittered grid of two near-equal sides when n factors so (every
// square, and e.g. 8, 12, 32), otherwise n-rooks (Latin hypercube) strata with a
// hashed row permutation keyed per pixel. permute() (affine) decorrelates sample
// indices between dimensions.
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

// A bijection of [0, n) chosen by `key` with no lattice structure: rounds of xor,
// odd multiply and xorshift (each a bijection of [0, 2^b)) on the smallest power of
// two >= n, cycle-walking until the value falls in [0, n).
KOKKOS_INLINE_FUNCTION int hashed_permute(int i, int n, std::uint32_t key) {
  if (n <= 1) return 0;
  std::uint32_t mask = static_cast<std::uint32_t>(n - 1);
  mask |= mask >> 1;
  mask |= mask >> 2;
  mask |= mask >> 4;
  mask |= mask >> 8;
  mask |= mask >> 16;
  const std::uint32_t k1 = hash_u32(key), k2 = hash_u32(key ^ 0x85ebca6bu);
  std::uint32_t x = static_cast<std::uint32_t>(i);
  do {
    x = (x ^ k1) & mask;
    x = (x * 0x2545f491u) & mask;
    x ^= x >> 3;
    x = (x + k2) & mask;
    x = (x * 0x9e3779b1u) & mask;
    x ^= x >> 5;
    x = (x * 0x68e31da5u) & mask;
    x ^= x >> 2;
  } while (x >= static_cast<std::uint32_t>(n));
  return static_cast<int>(x);
}

// How `count` strata tile [0,1)^2: a cols x rows jittered grid when count factors
// into two sides of at most 4:1 (squares, 8 = 4 x 2, 32 = 8 x 4, 12 = 4 x 3), otherwise
// (primes, 2, 22, ...) n-rooks: cols = rows = 0.
struct StrataShape {
  int cols = 0, rows = 0;
};

KOKKOS_INLINE_FUNCTION StrataShape strata_shape(int count) {
  int w = static_cast<int>(math::sqrt(static_cast<double>(count)) + 1e-9);
  while (w > 1 && count % w != 0) --w;
  StrataShape s;
  if (w >= 2 && count / w <= 4 * w) {
    s.cols = count / w;
    s.rows = w;
  }
  return s;
}

// Sample `index` of `count` strata in [0,1)^2, jittered by (u1, u2); `shape` is
// strata_shape(count), for loops that hoist it. n-rooks: x stratum = index, y stratum
// = a hashed permutation of it keyed per pixel, so every row and column holds one sample.
template <class T>
KOKKOS_FORCEINLINE_FUNCTION void stratum_2d(int index, int count, StrataShape shape,
                                            std::uint32_t key, T u1, T u2, T& x, T& y) {
  if (shape.cols > 0) {
    x = (T(index % shape.cols) + u1) / T(shape.cols);
    y = (T(index / shape.cols) + u2) / T(shape.rows);
    return;
  }
  x = (T(index) + u1) / T(count);
  y = (T(hashed_permute(index, count, key)) + u2) / T(count);
}

template <class T>
KOKKOS_INLINE_FUNCTION void stratum_2d(int index, int count, std::uint32_t key, T u1, T u2, T& x,
                                       T& y) {
  stratum_2d(index, count, strata_shape(count), key, u1, u2, x, y);
}

// Guard against 1.0 after float rounding of (i + u) / n.
template <class T>
KOKKOS_INLINE_FUNCTION T below_one(T x) {
  return x < T(1) ? x : T(0.99999994f);
}

}  // namespace rtmini::sketch
