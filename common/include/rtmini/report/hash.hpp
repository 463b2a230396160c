#pragma once
// Verification hashes that do not depend on thread count, rank count or the
// order in which a parallel reduction combines terms: each item contributes
// mix(item id, value) and the contributions are added modulo 2^64.
#include <cstdint>
#include <cstdio>
#include <string>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

// SplitMix64 finaliser (Steele, Lea, Flood, "Fast splittable pseudorandom number generators",
// 2014).
KOKKOS_INLINE_FUNCTION std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

KOKKOS_INLINE_FUNCTION std::uint64_t hash_term(std::uint64_t item, std::uint64_t value) {
  return mix64(mix64(item) ^ value);
}

inline std::string hash_hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// FNV-1a over bytes, for hashing a finished file or buffer in order.
inline std::uint64_t fnv1a(const void* data, std::size_t n,
                           std::uint64_t h = 0xcbf29ce484222325ULL) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ULL;
  return h;
}

}  // namespace rtmini
