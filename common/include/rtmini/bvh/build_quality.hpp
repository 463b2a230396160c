#pragma once
// Which BVH build an app asks for: the fast Morton-code LBVH, PLOC (SAH quality, built on the
// execution space: build_ploc.hpp) or the binned-SAH build on the host.
// Kokkos-free, so host-only settings code can name it.
#include <cmath>
#include <cstddef>
#include <cstdlib>
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

// --bvh auto: the build whose build time plus trace time is least for the rays a run will trace,
// from measured costs per triangle built and per ray traced (dragon, AO any hit; sources and
// the resulting crossovers: results/bvh/README.md, "--bvh auto"). The costs per ray stand for
// the mesh at hand only through their ratios; the crossover is a number of rays per triangle.
struct BuildCost {
  BuildQuality quality;
  double build_ns_per_triangle;
  double trace_ns_per_ray;
};

// One H200: LBVH build 0.90 ms and AO 1.61 Grays/s on the dragon (100K triangles); SAH build on
// the device machine's host 84 ms, AO 1.89 Grays/s; PLOC with treelet restructuring build
// 14.55 ms, AO 1.755 Grays/s (H200, mid trial c629598; results/gpu/README.md,
// results/bvh/README.md). PLOC beats the LBVH from ~2,700 rays per triangle, the SAH build beats
// PLOC from ~17,000.
inline constexpr BuildCost kDeviceBuildCosts[] = {{BuildQuality::kLbvh, 9.0, 0.621},
                                                  {BuildQuality::kPloc, 145.5, 0.570},
                                                  {BuildQuality::kSah, 840.0, 0.529}};
// This workplace's 2-core host, 2 threads (OpenMP): LBVH build 390 ms, SAH 556 ms, PLOC 4.7-9.8 s
// for the dragon (medians, shared machine); SAH AO 5.32 Mrays/s, the LBVH's rays doing 1.11x
// the SAH tree's node visits plus triangle tests. PLOC never pays here: slower to build than
// the SAH build and worse.
inline constexpr BuildCost kHostBuildCosts[] = {{BuildQuality::kLbvh, 3900.0, 210.0},
                                                {BuildQuality::kSah, 5560.0, 188.0}};

template <std::size_t N>
BuildQuality cheapest_build(const BuildCost (&costs)[N], double triangles, double rays) {
  BuildQuality best = costs[0].quality;
  double best_ns = 1e300;
  for (const BuildCost& c : costs) {
    const double ns = c.build_ns_per_triangle * triangles + c.trace_ns_per_ray * rays;
    if (ns < best_ns) {
      best_ns = ns;
      best = c.quality;
    }
  }
  return best;
}

inline BuildQuality choose_build_quality(double triangles, double rays, bool on_device) {
  return on_device ? cheapest_build(kDeviceBuildCosts, triangles, rays)
                   : cheapest_build(kHostBuildCosts, triangles, rays);
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

// Extra references the SAH build may make for slivers (pre-split parts or spatial splits), as a
// fraction of the triangle count: a number >= 0, or auto (kAutoSplitBudget, any negative
// value), which grows the budget while the surface-area heuristic says it pays (presplit.hpp).
inline constexpr double kAutoSplitBudget = -1;

inline bool is_auto_split_budget(double budget) { return budget < 0; }

inline std::string split_budget_to_string(double budget) {
  if (is_auto_split_budget(budget)) return "auto";
  std::string s = std::to_string(budget);  // fixed, six decimals: drop the trailing zeros
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

// False (and `out` untouched) unless `text` is auto or a finite number >= 0.
inline bool parse_split_budget(const std::string& text, double& out) {
  if (text == "auto") {
    out = kAutoSplitBudget;
    return true;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < 0) return false;
  out = v;
  return true;
}

}  // namespace rtmini::bvh
