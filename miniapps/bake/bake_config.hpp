#pragma once
// Everything a bake run is told on the command line, as plain data (filled by main.cpp).
#include <cstdint>
#include <string>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/geometry/vec.hpp"

namespace rtmini::bake {

// The viewpoint lookup (rtmini/sampling): all three give the same neighbours and weights, hence
// the same map; they differ in speed only (rtmini-bake-lookup-bench).
enum class Lookup { kGrid, kKdTree, kSphericalFibonacci };
// kCost: cut by the traced cost (kitchen.cpp, BakeRun::rebalance_by_traced_cost); kPilot: by the
// pilot's estimate alone (the cut before that, kept to compare); kMeasured: kCost, then recut
// once more after the first mirror iteration by each rank's measured time of it
// (BakeRun::recut_by_measured_time).
enum class Balance { kStatic, kCost, kSpatial, kPilot, kMeasured };
// Which viewpoints a view-dependent vertex stores: the N shared Fibonacci directions, or the N/2
// of them on its front side, in its own frame (one-sided mirrors only; map_reader.hpp).
enum class Directions { kSphere, kHemisphere };

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
  Lookup lookup = Lookup::kGrid;
  Balance balance = Balance::kCost;
  std::int64_t batch_size = 0;  // 0 = vertices / ranks, rounded up
  // --max-colors: the most colours a batch (a rank, at the default batch size) may own, over the
  // mean; the cost cuts balance time within that (make_batches). A rank's memory grows with its
  // own colours: a cut by time alone gave bunny_room's largest rank 1.69x the mean colours at 16
  // ranks, beyond the 1.2 / P memory bound (results/bake/distributed.md). 0: no cap.
  double color_cap = 1.1;
  std::int64_t max_memory = 0;  // --max-memory (report/memory_check.hpp): 0 = the machine's
  double time_limit_minutes = 0;
  Vec3f background{0.f, 0.f, 0.f};
  bvh::BuildQuality bvh = bvh::BuildQuality::kLbvh;
  bool cache_hits = true;
  // --exchange: after the first halo exchange send only the colours that changed (map_exchange.hpp)
  bool changed_exchanges = true;
  bool two_sided = false;  // mirrors reflect on both sides (README: why one-sided is the default)
  bool progress = false;
  // --node-sharing (node_share.hpp): the ranks of a node read one copy of the scene (scene, on)
  // and take each other's unfinished pieces (work, on)
  bool share_scene = false, share_work = false;
  // --node-map: with work shared by every rank of one node, the node keeps one map in its
  // shared memory that every rank reads directly (node_share.hpp, NodeMap), instead of each rank
  // its part and a halo refreshed by exchanges
  bool node_map = true;
  double share_test_delay = 0;    // hidden test hook: the node's first rank starts each shared
                                  // iteration this many seconds late
  int stop_after_iteration = -1;  // hidden test hook: checkpoint, then exit 4
  // Hidden test hook of --balance measured: rank r's measured time is taken as its counted cost
  // x (1 + recut_test_skew x r), so the recut moves work deterministically (0: measured).
  double recut_test_skew = 0;
  bool all_view_dependent = false;  // hidden, measurement: N colours for every vertex
  Directions directions = Directions::kSphere;

  bool hemisphere() const { return directions == Directions::kHemisphere; }
  // Colours of a view-dependent vertex: N, or N/2 on the front hemisphere.
  int stored_viewpoints() const { return hemisphere() ? viewpoints / 2 : viewpoints; }
};

inline const char* to_string(Lookup l) {
  return l == Lookup::kGrid ? "grid" : l == Lookup::kKdTree ? "kdtree" : "sf";
}
// The lookup a --lookup value names; false for any other name.
inline bool parse_lookup(const std::string& name, Lookup& out) {
  for (Lookup l : {Lookup::kGrid, Lookup::kKdTree, Lookup::kSphericalFibonacci})
    if (name == to_string(l)) {
      out = l;
      return true;
    }
  return false;
}
inline const char* to_string(Directions d) {
  return d == Directions::kSphere ? "sphere" : "hemisphere";
}
inline const char* to_string(Balance b) {
  return b == Balance::kStatic     ? "static"
         : b == Balance::kCost     ? "cost"
         : b == Balance::kPilot    ? "pilot"
         : b == Balance::kMeasured ? "measured"
                                   : "spatial";
}

}  // namespace rtmini::bake
