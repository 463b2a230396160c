#pragma once
// Everything a bake run is told on the command line, as plain data (filled by main.cpp).
#include <cstdint>
#include <string>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/geometry/vec.hpp"

namespace rtmini::bake {

enum class Lookup { kKdTree, kSphericalFibonacci };
enum class Balance { kStatic, kCost, kSpatial };

struct BakeConfig {
  std::string input;
  std::string output;
  int viewpoints = 100;
  int iterations = 1;
  int shadow_samples = 16;
  int gather_rays = 0;
  std::uint64_t seed = 1;
  std::string summary, timings, checkpoint, restart;
  std::string reference;         // compare the baked map with this map (errors in the summary)
  bool trace_reference = false;  // write the traced reference instead of a bake
  Lookup lookup = Lookup::kKdTree;
  Balance balance = Balance::kCost;
  std::int64_t batch_size = 0;  // 0 = vertices / ranks, rounded up
  std::int64_t max_memory = 0;  // --max-memory (report/memory_check.hpp): 0 = the machine's
  double time_limit_minutes = 0;
  Vec3f background{0.f, 0.f, 0.f};
  bvh::BuildQuality bvh = bvh::BuildQuality::kLbvh;
  bool cache_hits = true;
  bool two_sided = false;  // mirrors reflect on both sides (README: why one-sided is the default)
  bool progress = false;
  int stop_after_iteration = -1;    // hidden test hook: checkpoint, then exit 4
  bool all_view_dependent = false;  // hidden, measurement: N colours for every vertex
};

inline const char* to_string(Lookup l) { return l == Lookup::kKdTree ? "kdtree" : "sf"; }
inline const char* to_string(Balance b) {
  return b == Balance::kStatic ? "static" : b == Balance::kCost ? "cost" : "spatial";
}

}  // namespace rtmini::bake
