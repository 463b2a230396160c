#pragma once
// The Kitchen (all ranks): reads and prepares the scene, splits the vertices into batches of
// any size over the ranks, runs each iteration's batches through this rank's Chef, shares the
// colours with an all-gather, checkpoints, and writes the baked map collectively.
#include <cstdint>
#include <vector>

#include "bake_config.hpp"
#include "bake_scene.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini::bake {

struct Batch {
  std::int64_t begin = 0, end = 0;  // vertices
  int rank = 0;
};

// Contiguous vertex batches assigned round-robin to ranks. kStatic: batch_size vertices each
// (default vertices / ranks, rounded up); kCost: the same number of batches, cut so each holds
// about the same cost: vertex_cost[v] when given (mirror_hit_cost), else its colour count (N per
// reflective vertex, 1 per other vertex). color_cap > 0 (kCost): no batch holds more than
// color_cap x the mean colours per batch (but for one vertex where a vertex alone is more), the
// cost balanced as well as that allows; with one batch per rank, the colours a rank owns, which
// its memory grows with (BakeConfig::color_cap), and a rank may then own several ranges, the
// cost balanced to 2 % (kitchen.cpp, capped_ownership). Batches come in vertex order.
std::vector<Batch> make_batches(const BakeSceneHost& scene, int ranks, Balance balance,
                                std::int64_t batch_size,
                                const std::vector<double>& vertex_cost = {}, double color_cap = 0);

// The cost of each vertex's colours in a mirror iteration: 1 per colour plus per_hit per mirror
// hit that needs a viewpoint lookup (hits[v], counted or estimated). Such a hit costs a
// viewpoint query and three scattered colour reads; a hit on view-independent vertices, or a miss, costs
// little more than its cache read. kLookupHitCost: the 16-core host's per-rank iteration times
// of bunny_room (N = 300, 16 x 1, commit e7c336d) against the ranks' counted work (the same cut
// recounted here, `results/bake/balance.md`) fit 59 ns per colour + 1.46 us per lookup hit
// (r^2 = 0.57 on one run's noisy per-rank times; 16 x 1 and 8 x 2 together: 34 ns + 1.66 us,
// r^2 = 0.93); remote reads add nothing measurable. kPilotLookupHitCost: the older fit (297 ns
// + 1.40 us) that --balance pilot keeps, so it reproduces the ranges measured before. Both
// were fitted with the KD-tree lookup; with the grid (the default since) the same fits give a
// weight of 2.3-4.6 (results/bake/distributed.md, twenty-third round), but re-weighting would
// move bunny_room's 16 x 1 counted max / mean by under 3 %, inside the cores' own 8-10 %: kept.
constexpr double kLookupHitCost = 25.0;
constexpr double kPilotLookupHitCost = 4.7;
std::vector<double> lookup_hit_cost(const BakeSceneHost& scene, const std::vector<float>& hits,
                                    double per_hit = kLookupHitCost);

// The cost of each vertex's mirror trace: the BVH nodes its rays visit (nodes[v], estimated)
// plus one per colour (every colour entry is a work item, traced or not).
std::vector<double> mirror_trace_cost(const BakeSceneHost& scene, const std::vector<float>& nodes);

// Spatial ownership: blocks of block_size consecutive vertices (default vertices / (16 ranks),
// at least 64), ordered by the Morton code of their centroid and cut into `ranks` runs of about
// equal cost (colours), so a rank owns a compact region of the scene and its rays read more of
// its own colours. Batches are returned in vertex order, neighbouring blocks of one rank merged.
std::vector<Batch> make_spatial_batches(const BakeSceneHost& scene,
                                        const std::vector<Vec3d>& positions, int ranks,
                                        std::int64_t block_size);

// Runs the whole bake; returns the process exit code.
int run_bake(Communicator& comm, const BakeConfig& config);

}  // namespace rtmini::bake
