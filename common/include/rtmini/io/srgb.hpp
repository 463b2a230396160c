#pragma once
// The one place for the sRGB transfer function (IEC 61966-2-1): 8-bit PPM/PNG are
// stored sRGB-encoded, everything in memory is linear. Device-callable for NPR passes.
#include <cstdint>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

// Linear [0,1] -> sRGB-encoded [0,1] (input clamped to [0,1]; NaN maps to 0).
template <class T>
KOKKOS_INLINE_FUNCTION T srgb_encode(T linear) {
  const T x = linear > T(0) ? (linear < T(1) ? linear : T(1)) : T(0);
  return x <= T(0.0031308) ? T(12.92) * x : T(1.055) * math::pow(x, T(1) / T(2.4)) - T(0.055);
}

// sRGB-encoded [0,1] -> linear [0,1].
template <class T>
KOKKOS_INLINE_FUNCTION T srgb_decode(T encoded) {
  const T x = encoded > T(0) ? (encoded < T(1) ? encoded : T(1)) : T(0);
  return x <= T(0.04045) ? x / T(12.92) : math::pow((x + T(0.055)) / T(1.055), T(2.4));
}

// Linear value to an 8-bit sRGB code, rounded to nearest.
KOKKOS_INLINE_FUNCTION std::uint8_t srgb_encode_8bit(float linear) {
  return static_cast<std::uint8_t>(srgb_encode(linear) * 255.f + 0.5f);
}

KOKKOS_INLINE_FUNCTION float srgb_decode_8bit(std::uint8_t code) {
  return srgb_decode(static_cast<float>(code) / 255.f);
}

}  // namespace rtmini
