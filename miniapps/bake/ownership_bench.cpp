// rtmini-bake-ownership-bench: the time of bake's ownership plan (make_batches, --balance cost
// under the colour cap) at many ranks, on synthetic per-vertex costs, without MPI ranks.
//
//   rtmini-bake-ownership-bench [RANKS [VERTICES_PER_RANK [VIEWPOINTS]]]   (default 1000 1000 300)
//
// The scene: bands of vertices of random length (0.5 to 10.5 ranks' share), each band
// view-dependent (VIEWPOINTS colours a vertex; 3 in 4) or not (one colour), with 0.01-0.9 lookup
// hits per colour in a view-dependent band (as between bunny_room's ranks; fixed seed), so one
// contiguous range per rank under the cap leaves some ranks cheap and the pieces are swapped
// (kitchen.cpp, capped_ownership). Prints the plan's seconds (best of 3), the ranges and the
// largest rank's cost and colours over the mean.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "kitchen.hpp"

namespace {

using rtmini::bake::BakeSceneHost;
using rtmini::bake::Batch;

struct Synthetic {
  BakeSceneHost scene;
  std::vector<double> cost;
};

Synthetic synthetic_scene(std::int64_t vertices, std::int64_t per_rank, int viewpoints) {
  Synthetic s;
  s.scene.normal.assign(static_cast<std::size_t>(vertices), rtmini::Vec3(0, 0, 1));
  s.scene.color_offset.assign(static_cast<std::size_t>(vertices) + 1, 0);
  std::vector<float> hits(static_cast<std::size_t>(vertices), 0.f);
  std::mt19937_64 rng(19);
  std::int64_t v = 0;
  while (v < vertices) {
    const std::int64_t band = per_rank / 2 + std::int64_t(rng() % std::uint64_t(10 * per_rank));
    const std::int64_t end = std::min(vertices, v + band);
    const bool view_dependent = rng() % 4 != 0;
    const float per_color = 0.1f + 0.005f * static_cast<float>(rng() % 41);
    for (; v < end; ++v) {
      const std::int64_t n = view_dependent ? viewpoints : 1;
      s.scene.color_offset[v + 1] = s.scene.color_offset[v] + n;
      hits[v] = view_dependent ? per_color * float(n) : 0.f;
    }
  }
  s.cost = rtmini::bake::lookup_hit_cost(s.scene, hits);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int ranks = argc > 1 ? std::atoi(argv[1]) : 1000;
  const std::int64_t per_rank = argc > 2 ? std::atoll(argv[2]) : 1000;
  const int viewpoints = argc > 3 ? std::atoi(argv[3]) : 300;
  if (ranks < 1 || per_rank < 1 || viewpoints < 1) {
    std::fprintf(stderr, "usage: %s [RANKS [VERTICES_PER_RANK [VIEWPOINTS]]]\n", argv[0]);
    return 2;
  }
  const Synthetic s = synthetic_scene(std::int64_t(ranks) * per_rank, per_rank, viewpoints);
  constexpr double kCap = 1.1;  // bake's default --max-colors
  double best = 1e30;
  std::vector<Batch> b;
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    b = rtmini::bake::make_batches(s.scene, ranks, rtmini::bake::Balance::kCost, 0, s.cost, kCap);
    best = std::min(best,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::vector<double> cost(static_cast<std::size_t>(ranks), 0.0), colors(cost);
  double total_cost = 0;
  for (const Batch& x : b)
    for (std::int64_t v = x.begin; v < x.end; ++v) {
      cost[x.rank] += s.cost[v];
      colors[x.rank] += double(s.scene.color_count(v));
      total_cost += s.cost[v];
    }
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a of the batches: the same plan, the same
  for (const Batch& x : b)                      // hash (to compare implementations)
    for (const std::int64_t w : {x.begin, x.end, std::int64_t(x.rank)})
      hash = (hash ^ static_cast<std::uint64_t>(w)) * 1099511628211ull;
  const double mean_cost = total_cost / ranks, mean_colors = double(s.scene.colors()) / ranks;
  std::printf(
      "ranks %d, vertices %lld, colours %lld: ownership plan %.4f s (best of 3), %zu ranges, "
      "cost max/mean %.4f, colours max/mean %.4f, plan hash %016llx\n",
      ranks, static_cast<long long>(s.scene.vertices()), static_cast<long long>(s.scene.colors()),
      best, b.size(), *std::max_element(cost.begin(), cost.end()) / mean_cost,
      *std::max_element(colors.begin(), colors.end()) / mean_colors,
      static_cast<unsigned long long>(hash));
  return 0;
}
