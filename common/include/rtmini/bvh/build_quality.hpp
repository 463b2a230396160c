#pragma once
// Which BVH build an app asks for: the fast Morton-code LBVH, PLOC (SAH quality, built on the
// execution space: build_ploc.hpp) or the binned-SAH build on the host.
// Kokkos-free, so host-only settings code can name it.
#include <string>

namespace rtmini::bvh {

enum class BuildQuality { kLbvh, kSah, kPloc };

inline const char* to_string(BuildQuality q) {
  return q == BuildQuality::kLbvh ? "lbvh" : q == BuildQuality::kSah ? "sah" : "ploc";
}

// False (and `out` untouched) unless `name` is lbvh, sah or ploc.
inline bool parse_build_quality(const std::string& name, BuildQuality& out) {
  for (const BuildQuality q : {BuildQuality::kLbvh, BuildQuality::kSah, BuildQuality::kPloc})
    if (name == to_string(q)) {
      out = q;
      return true;
    }
  return false;
}

// Spatial splits in the SAH build (build_sah.cpp): never, wherever the best object split's
// children overlap enough to try them, or auto (the builder's measured choice:
// uses_spatial_splits).
enum class SpatialSplits { kOff, kOn, kAuto };

inline const char* to_string(SpatialSplits s) {
  return s == SpatialSplits::kOff ? "off" : s == SpatialSplits::kOn ? "on" : "auto";
}

// False (and `out` untouched) unless `name` is off, on or auto.
inline bool parse_spatial_splits(const std::string& name, SpatialSplits& out) {
  for (const SpatialSplits s : {SpatialSplits::kOff, SpatialSplits::kOn, SpatialSplits::kAuto})
    if (name == to_string(s)) {
      out = s;
      return true;
    }
  return false;
}

}  // namespace rtmini::bvh
