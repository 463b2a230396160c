#include "kitchen.hpp"

#include <sys/resource.h>
#include <unistd.h>  // isatty
#if defined(__GLIBC__)
#include <malloc.h>  // mallopt
#endif

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>
#include <thread>

#include "bakeshop_mpi_writer.hpp"
#include "checkpoint.hpp"
#include "chef.hpp"
#include "iteration_eta.hpp"
#include "map_errors.hpp"
#include "map_exchange.hpp"
#include "node_share.hpp"
#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/input_files.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/timings.hpp"
#include "rtmini/parallel/spread_order.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/stop_request.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini::bake {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

// This process's peak resident set (Linux reports KiB).
double peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;
}

// This process's resident set now, by kind (Linux: /proc/self/status; zeros where it is
// missing): the peak says how high a step went, this what it left resident. The kinds place what
// no bake buffer accounts for: anonymous pages are heap (the bake's, the runtimes'), file pages
// the program and its libraries, shared-memory pages what the MPI library maps to reach the
// ranks on its node (the bake itself maps none).
// `huge` is the part of the heap on transparent huge pages (AnonHugePages): where the kernel
// backs a large array with them only when a 2 MiB page happens to be free, ranks of one job can
// get different shares, and a rank on 4 KiB pages pays page walks on every random read.
// `pss` is the proportional set size: each page divided by the processes that map it. With
// node sharing (--node-sharing on) a rank maps the pages of the other ranks' segments that its
// stolen pieces read, which its RSS counts in full and every rank's RSS again: the node's memory
// is the sum of the ranks' PSS, not of their RSS.
struct ResidentNow {
  double total = 0, anon = 0, file = 0, shmem = 0, huge = 0, pss = 0;
};

// The kernel's transparent-huge-page policy (the bracketed word of
// /sys/kernel/mm/transparent_hugepage/enabled: always, madvise or never; "" where unknown), which
// decides whether the heap's share on huge pages (ResidentNow::huge) depends on luck.
std::string transparent_huge_page_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string word;
  while (in >> word)
    if (word.size() > 2 && word.front() == '[' && word.back() == ']')
      return word.substr(1, word.size() - 2);
  return "";
}

ResidentNow resident_now() {
  constexpr double kKiB = 1024.0;  // /proc gives kB
  ResidentNow r;
  r.total = read_field("/proc/self/status", "VmRSS:") * kKiB;
  r.anon = read_field("/proc/self/status", "RssAnon:") * kKiB;
  r.file = read_field("/proc/self/status", "RssFile:") * kKiB;
  r.shmem = read_field("/proc/self/status", "RssShmem:") * kKiB;
  r.huge = read_field("/proc/self/smaps_rollup", "AnonHugePages:") * kKiB;
  r.pss = read_field("/proc/self/smaps_rollup", "Pss:") * kKiB;
  return r;
}

// Every rank's `mine` (the same length on every rank) in one collective, by field: [k][r] is
// field k of rank r. The per-rank reports gather all their figures at once with it.
std::vector<std::vector<double>> gather_fields(const Communicator& comm,
                                               const std::vector<double>& mine) {
  const std::size_t n = mine.size();
  const std::vector<double> all = comm.allgatherv(mine);
  const std::size_t ranks = n == 0 ? 0 : all.size() / n;
  std::vector<std::vector<double>> fields(n, std::vector<double>(ranks));
  for (std::size_t r = 0; r < ranks; ++r)
    for (std::size_t k = 0; k < n; ++k) fields[k][r] = all[r * n + k];
  return fields;
}

std::string human_bytes(double b) {
  const char* unit[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (b >= 1024.0 && u < 4) {
    b /= 1024.0;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %s", b, unit[u]);
  return buf;
}

// Every parameter that changes the colours (not K, so a finished run can be extended; not the
// lookup or BVH kind, which give the same result). The inputs' content is compared file by
// file (io/input_files.hpp), so that a refusal can name the file that changed.
std::string parameter_hash(const BakeConfig& c) {
  std::ostringstream p;
  p << "bake-map-v2 N=" << c.viewpoints << " S=" << c.shadow_samples << " M=" << c.gather_rays
    << " seed=" << c.seed << " bg=" << c.background.x << "," << c.background.y << ","
    << c.background.z << " real=" << sizeof(Real) << (c.trace_reference ? " traced" : "")
    << (c.hemisphere() ? " hemisphere" : "");
  const std::string params = p.str();
  return hash_hex(fnv1a(params.data(), params.size()));
}

// local_colors: the colours this rank's map holds (owned + halo; the halo is known only after
// the mirror rays are traced, so the caller passes its best bound).
MemoryEstimate estimate_memory(const Mesh& mesh, const BakeSceneHost& s, std::int64_t my_items,
                               std::int64_t my_vertices, std::int64_t local_colors, int iterations,
                               const BakeConfig& c, bool root) {
  MemoryEstimate m;
  const std::int64_t nv = s.vertices(), nt = static_cast<std::int64_t>(mesh.triangle_count());
  const std::int64_t vec = sizeof(Vec3), col = sizeof(Vec3f);
  // Mesh SoA + BVH (about 2 nodes per leaf triangle group, the triangles again in leaf order).
  m.scene = nv * (vec * 6 + 8) + nt * (3 * vec * 2 + 4 * 6) + nt * sizeof(bvh::BvhNode) +
            static_cast<std::int64_t>(c.viewpoints) * (vec * 2 + 8);
  m.maps = 2 * local_colors * col;  // prev + next on the device
  // Local map; exchange buffers (and with changed-only exchanges a message each way besides).
  m.host = local_colors * col + (c.changed_exchanges ? 4 : 2) * my_items * col;
  // Formatted output text (~60 bytes a colour), at its peak held twice over in part: the
  // per-task pieces, grown by appending, and the joined copy (bakeshop_mpi_writer.cpp).
  m.host += my_vertices * c.stored_viewpoints() * 90;
  // The root holds the whole map once for a checkpoint or a comparison.
  if (root && (!c.checkpoint.empty() || !c.reference.empty())) m.host += s.colors() * col;
  if (!c.reference.empty()) m.host += nv * c.viewpoints * col;  // the reference's colours
  if (c.cache_hits && iterations > 1) m.hit_cache = Chef::hit_cache_bytes(my_items);
  return m;
}

bool same_batches(const std::vector<Batch>& a, const std::vector<Batch>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const Batch& x, const Batch& y) {
    return x.begin == y.begin && x.end == y.end && x.rank == y.rank;
  });
}

KOKKOS_INLINE_FUNCTION std::int64_t quantise(float x) {
  return static_cast<std::int64_t>(math::floor(double(x) * 65536.0 + 0.5));
}

// Order-independent hash over (vertex, viewpoint, quantised colour) of this rank's vertices;
// `off`: where each vertex's colours sit in `map`.
std::uint64_t map_hash(Kokkos::View<const std::int64_t*, MemSpace> off,
                       Kokkos::View<const Vec3f*, MemSpace> map, const std::vector<Batch>& batches,
                       int rank, int n) {
  std::uint64_t total = 0;
  for (const Batch& b : batches) {
    if (b.rank != rank) continue;
    std::uint64_t h = 0;
    Kokkos::parallel_reduce(
        "rtmini::bake::verification_hash",
        Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(b.begin, b.end),
        KOKKOS_LAMBDA(std::int64_t v, std::uint64_t & acc) {
          const std::int64_t first = off(v);
          const bool single = off(v + 1) - first == 1;
          for (int i = 0; i < n; ++i) {
            const Vec3f c = map(single ? first : first + i);
            const std::uint64_t value =
                hash_term(hash_term(static_cast<std::uint64_t>(quantise(c.x)),
                                    static_cast<std::uint64_t>(quantise(c.y))),
                          static_cast<std::uint64_t>(quantise(c.z)));
            acc +=
                hash_term(static_cast<std::uint64_t>(v) * static_cast<std::uint64_t>(n) + i, value);
          }
        },
        h);
    total += h;
  }
  return total;
}

// The read flags `from_flags` (one per colour of the vertices present in layout offsets `from`)
// moved to layout offsets `to` (`colors` entries): a vertex present in both keeps its flags, the
// others start unflagged. (Free functions: CUDA's device lambdas may not sit in private members.)
Kokkos::View<char*, MemSpace> moved_read_flags(Kokkos::View<const std::int64_t*, MemSpace> from,
                                               Kokkos::View<const char*, MemSpace> from_flags,
                                               Kokkos::View<const std::int64_t*, MemSpace> to,
                                               std::int64_t colors) {
  Kokkos::View<char*, MemSpace> flags("rtmini::bake::read_items", static_cast<std::size_t>(colors));
  Kokkos::parallel_for(
      "rtmini::bake::moved_read_flags",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(
          0, static_cast<std::int64_t>(to.extent(0)) - 1),
      KOKKOS_LAMBDA(std::int64_t v) {
        if (from(v + 1) == from(v)) return;
        for (std::int64_t j = 0; j < to(v + 1) - to(v); ++j)
          flags(to(v) + j) = from_flags(from(v) + j);
      });
  return flags;
}

// Per vertex, 0 for one owned before (owned_before) and not now (owned), else 1: the vertices
// given away, as the `owned` argument of Chef::mark_read_items (which flags only the others).
Kokkos::View<char*, MemSpace> not_given_away(Kokkos::View<const char*, MemSpace> owned_before,
                                             Kokkos::View<const char*, MemSpace> owned) {
  Kokkos::View<char*, MemSpace> out("rtmini::bake::not_given", owned.extent(0));
  Kokkos::parallel_for(
      "rtmini::bake::not_given_away",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(0, owned.extent(0)),
      KOKKOS_LAMBDA(std::int64_t v) { out(v) = owned_before(v) && !owned(v) ? 0 : 1; });
  return out;
}

nlohmann::json error_json(const MapErrors& e) {
  return {{"entries", e.entries},
          {"mean_abs", e.mean_abs},
          {"rmse", e.rmse},
          {"rel_mse", e.rel_mse},
          {"max_abs", e.max_abs},
          {"mean_reference", e.mean_reference},
          {"view_dependent_entries", e.view_dependent},
          {"view_dependent_rmse", e.view_dependent_rmse},
          {"view_independent_rmse", e.view_independent_rmse}};
}

void print_errors(const char* what, const MapErrors& e) {
  std::printf(
      "  reference, %s: mean |map - ref| %.6g, RMSE %.6g, relative MSE %.6g, max %.6g "
      "(mean reference %.6g; RMSE %.6g over the %lld view-dependent of %lld colours, %.6g over "
      "the others)\n",
      what, e.mean_abs, e.rmse, e.rel_mse, e.max_abs, e.mean_reference, e.view_dependent_rmse,
      static_cast<long long>(e.view_dependent), static_cast<long long>(e.entries),
      e.view_independent_rmse);
}

struct IterationRecord {
  double trace = 0, allgather = 0, write = 0;
  std::int64_t allgather_bytes = 0;  // the map exchange's bytes sent by this rank
};

struct ChunkRecord {
  std::int64_t rank, iteration, work_units, rays;
  double start, end;
};

// The per-rank totals of a run: completion and idle time, rays and work.
struct RankTotals {
  double completion = 0, idle = 0;
  std::int64_t rays = 0, work = 0;
};

void write_timings_file(const Communicator& comm, const BakeConfig& c, const PhaseTimer& timer,
                        const std::vector<std::string>& phase_names,
                        const std::vector<IterationRecord>& iters,
                        const std::vector<ChunkRecord>& chunks, const RankTotals& totals,
                        const std::string& params_json) {
  RankTimings mine;
  for (const auto& ch : chunks)
    mine.chunks.push_back({ch.iteration, ch.work_units, ch.rays, ch.start, ch.end});
  for (const auto& r : iters)
    mine.iterations.push_back({r.trace, r.allgather, r.write, r.allgather_bytes});
  mine.completion = totals.completion;
  mine.idle = totals.idle;
  mine.rays = totals.rays;
  mine.work_units = totals.work;
  write_rank_timings(c.timings, comm, timer, mine,
                     {"bake", to_string(c.balance), c.input, params_json, phase_names});
}

}  // namespace

std::vector<double> lookup_hit_cost(const BakeSceneHost& scene, const std::vector<float>& hits,
                                    double per_hit) {
  std::vector<double> cost(static_cast<std::size_t>(scene.vertices()));
  for (std::int64_t v = 0; v < scene.vertices(); ++v)
    cost[v] = static_cast<double>(scene.color_count(v)) + per_hit * double(hits[v]);
  return cost;
}

std::vector<double> mirror_trace_cost(const BakeSceneHost& scene, const std::vector<float>& nodes) {
  std::vector<double> cost(static_cast<std::size_t>(scene.vertices()));
  for (std::int64_t v = 0; v < scene.vertices(); ++v)
    cost[v] = static_cast<double>(scene.color_count(v)) + double(nodes[v]);
  return cost;
}

namespace {

// The end of the batch that starts at `begin`, `left` batches before the last vertex included:
// where the running cost passes `target`, but no further than `cap` colours from `begin` (0: no
// cap) and no nearer than leaves the later batches at most `cap` colours each. A batch holds at
// least one vertex, so a cap below one vertex's colours is exceeded by that vertex.
std::int64_t batch_end(const std::vector<double>& before, const std::vector<std::int64_t>& colors,
                       std::int64_t begin, std::int64_t left, double target, double cap) {
  const std::int64_t nv = static_cast<std::int64_t>(before.size()) - 1;
  std::int64_t end = begin + 1;
  while (end < nv && before[end] < target) ++end;
  if (cap <= 0) return end;
  const auto colors_in = [&](std::int64_t e) { return double(colors[e] - colors[begin]); };
  while (end > begin + 1 && colors_in(end) > cap) --end;
  // The rest must fit: at most `left` more batches of `cap` colours.
  const auto colors_after = [&](std::int64_t e) { return double(colors[nv] - colors[e]); };
  while (end < nv && colors_after(end) > cap * double(left)) ++end;
  return end;
}

// The running cost before each vertex (vertices + 1 entries): vertex_cost, or the colours.
std::vector<double> cost_before(const BakeSceneHost& scene,
                                const std::vector<double>& vertex_cost) {
  const std::int64_t nv = scene.vertices();
  std::vector<double> before(static_cast<std::size_t>(nv) + 1, 0.0);
  for (std::int64_t v = 0; v < nv; ++v)
    before[v + 1] =
        before[v] + (vertex_cost.empty() ? double(scene.color_count(v)) : vertex_cost[v]);
  return before;
}

// `count` contiguous batches, dealt round-robin to the ranks, cut where the running cost passes
// the next multiple of total / count. Under a colour cap (colours per batch, 0: none) a batch
// may close early; then the cost left is shared equally by the batches left (each target is the
// cost so far plus that share).
std::vector<Batch> contiguous_cut(const BakeSceneHost& scene, const std::vector<double>& before,
                                  std::int64_t count, int ranks, double cap) {
  const std::int64_t nv = scene.vertices();
  const double total = before[nv];
  std::vector<Batch> out;
  std::int64_t begin = 0;
  for (std::int64_t b = 0; b < count && begin < nv; ++b) {
    std::int64_t end = nv;
    if (b + 1 < count) {
      const double target =
          cap > 0 ? before[begin] + (total - before[begin]) / static_cast<double>(count - b)
                  : total * static_cast<double>(b + 1) / static_cast<double>(count);
      end = batch_end(before, scene.color_offset, begin, count - b - 1, target, cap);
    }
    out.push_back({begin, end, static_cast<int>(b % ranks)});
    begin = end;
  }
  return out;
}

// The largest rank's cost under `batches` over the mean per rank.
double max_cost_over_mean(const std::vector<double>& before, const std::vector<Batch>& batches,
                          int ranks) {
  std::vector<double> cost(static_cast<std::size_t>(ranks), 0.0);
  for (const Batch& b : batches) cost[b.rank] += before[b.end] - before[b.begin];
  const double total = before.back();
  return total > 0 ? *std::max_element(cost.begin(), cost.end()) * double(ranks) / total : 1.0;
}

// Swaps of one piece for another between the rank with the most colours and any other rank
// until no rank holds more than `cap` colours; false where no swap lowers the largest rank's
// colours before that. Each time the swap that leaves the larger of the two ranks' colours
// smallest: it moves the fewest pieces for the colours shed (ties: the top rank's first piece,
// then the other's first, in vertex order). The pieces cost the same, so the cost stays balanced.
//
// A swap of d colours between ranks of H and h colours leaves max(H - d, h + d), at least
// (H + h) / 2 and at least H - (the top's largest piece - the other's smallest): the pieces of a
// rank are compared only where that bound reaches the best swap found, the rank of the lowest
// bound first. Trying every pair of pieces (16 x 16 P per swap, thousands of swaps) took 0.9 s at
// P = 1000 (rtmini-bake-ownership-bench; results/bake/distributed.md, fifteenth round).
bool swap_under_cap(std::vector<Batch>& pieces, const std::vector<std::int64_t>& colors, int ranks,
                    double cap) {
  std::vector<std::int64_t> held(static_cast<std::size_t>(ranks), 0);
  std::vector<std::vector<std::size_t>> of_rank(static_cast<std::size_t>(ranks));
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    held[pieces[i].rank] += colors[i];
    of_rank[pieces[i].rank].push_back(i);
  }
  const auto extreme = [&](int r, bool largest) {
    std::int64_t x = colors[of_rank[r].front()];
    for (const std::size_t i : of_rank[r])
      x = largest ? std::max(x, colors[i]) : std::min(x, colors[i]);
    return x;
  };
  std::vector<std::int64_t> smallest(static_cast<std::size_t>(ranks), 0);  // piece, per rank
  for (int r = 0; r < ranks; ++r)
    if (!of_rank[r].empty()) smallest[r] = extreme(r, false);
  std::vector<std::int64_t> least(static_cast<std::size_t>(ranks));  // the bound, per rank
  for (;;) {
    const int top = static_cast<int>(std::max_element(held.begin(), held.end()) - held.begin());
    const std::int64_t big = held[top];
    if (double(big) <= cap) return true;
    const std::int64_t largest = extreme(top, true);
    int first = -1;  // the rank of the lowest bound, compared first
    for (int q = 0; q < ranks; ++q) {
      least[q] = q == top || of_rank[q].empty()
                     ? big + 1
                     : std::max((big + held[q] + 1) / 2, big - (largest - smallest[q]));
      if (first < 0 || least[q] < least[first]) first = q;
    }
    std::int64_t best = big;
    std::size_t give = 0, take = 0;
    const auto compare = [&](int q) {
      for (const std::size_t i : of_rank[top])
        for (const std::size_t j : of_rank[q]) {
          const std::int64_t d = colors[i] - colors[j];
          if (d <= 0) continue;
          const std::int64_t larger = std::max(big - d, held[q] + d);
          const bool tie =
              larger == best && best < big && std::make_pair(i, j) < std::make_pair(give, take);
          if (larger < best || tie) {
            best = larger;
            give = i;
            take = j;
          }
        }
    };
    if (first >= 0 && least[first] <= best) compare(first);
    for (int q = 0; q < ranks; ++q)
      if (q != first && least[q] <= best) compare(q);
    if (best == big) return false;
    const int q = pieces[take].rank;
    const std::int64_t d = colors[give] - colors[take];
    held[top] -= d;
    held[q] += d;
    std::replace(of_rank[top].begin(), of_rank[top].end(), give, take);
    std::replace(of_rank[q].begin(), of_rank[q].end(), take, give);
    std::swap(pieces[give].rank, pieces[take].rank);
    smallest[top] = extreme(top, false);
    smallest[q] = extreme(q, false);
  }
}

// kPiecesPerRank x ranks contiguous pieces of equal cost, the rank's share of them in a row
// (the cost cut without a cap, to a piece), then pieces swapped between ranks until every rank
// fits the colour cap (swap_under_cap): each rank keeps most of its contiguous range and holds
// the same cost, to a vertex per piece. Returned in vertex order, a rank's neighbouring pieces
// merged; empty when there are fewer vertices than pieces or the swaps cannot fit the cap.
constexpr int kPiecesPerRank = 16;

std::vector<Batch> swapped_pieces(const BakeSceneHost& scene, const std::vector<double>& before,
                                  int ranks, double cap) {
  const std::int64_t count = std::int64_t(ranks) * kPiecesPerRank;
  std::vector<Batch> pieces = contiguous_cut(scene, before, count, ranks, 0.0);
  if (static_cast<std::int64_t>(pieces.size()) < count) return {};
  std::vector<std::int64_t> colors(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    pieces[i].rank = static_cast<int>(i / kPiecesPerRank);
    colors[i] = scene.color_offset[pieces[i].end] - scene.color_offset[pieces[i].begin];
  }
  if (!swap_under_cap(pieces, colors, ranks, cap)) return {};
  std::vector<Batch> merged;
  for (const Batch& x : pieces) {
    if (!merged.empty() && merged.back().rank == x.rank)
      merged.back().end = x.end;
    else
      merged.push_back(x);
  }
  return merged;
}

// The ownership of --balance cost under a colour cap (colours per rank): one contiguous range
// per rank (capped, contiguous_cut) while that leaves the largest cost within kCostTolerance of
// the mean, else swapped_pieces. On bunny_room (N = 300) the capped contiguous cut left
// 1.09-1.16x the mean cost at 2-16 ranks: a range of cheap vertices (many colours, few lookup
// hits) fills its colour quota before its cost share, and the ranges of expensive ones carry
// the rest; swapped pieces give a cheap range's rank some expensive pieces for some of its own.
// Dealing all the pieces afresh balanced both as well but cut a rank's region into unrelated
// parts: at 16 ranks its halo grew 26 % and the exchange 34 % (results/bake/distributed.md,
// thirteenth round). Where the pieces cannot fit the cap, the contiguous cut stays.
constexpr double kCostTolerance = 1.02;

std::vector<Batch> capped_ownership(const BakeSceneHost& scene, const std::vector<double>& before,
                                    int ranks, double cap) {
  std::vector<Batch> contiguous = contiguous_cut(scene, before, ranks, ranks, cap);
  if (max_cost_over_mean(before, contiguous, ranks) <= kCostTolerance) return contiguous;
  std::vector<Batch> swapped = swapped_pieces(scene, before, ranks, cap);
  return swapped.empty() ? contiguous : swapped;
}

}  // namespace

std::vector<Batch> make_batches(const BakeSceneHost& scene, int ranks, Balance balance,
                                std::int64_t batch_size, const std::vector<double>& vertex_cost,
                                double color_cap) {
  const std::int64_t nv = scene.vertices();
  std::vector<Batch> out;
  if (nv == 0) return out;
  const std::int64_t size = batch_size > 0 ? batch_size : (nv + ranks - 1) / ranks;
  const std::int64_t count = (nv + size - 1) / size;
  if (balance == Balance::kStatic) {
    for (std::int64_t b = 0; b < count; ++b)
      out.push_back({b * size, std::min(nv, (b + 1) * size), static_cast<int>(b % ranks)});
    return out;
  }
  const std::vector<double> before = cost_before(scene, vertex_cost);
  const double cap =
      color_cap > 0 ? color_cap * double(scene.colors()) / static_cast<double>(count) : 0.0;
  // One batch per rank (no --batch-size): a rank may take several ranges to fit both.
  if (cap > 0 && count == ranks && ranks > 1) return capped_ownership(scene, before, ranks, cap);
  return contiguous_cut(scene, before, count, ranks, cap);
}

std::vector<Batch> make_spatial_batches(const BakeSceneHost& scene,
                                        const std::vector<Vec3d>& positions, int ranks,
                                        std::int64_t block_size) {
  const std::int64_t nv = scene.vertices();
  if (nv == 0) return {};
  const std::int64_t b =
      block_size > 0 ? block_size : std::max<std::int64_t>(64, nv / (16 * ranks));
  const std::int64_t count = (nv + b - 1) / b;
  std::vector<Vec3> centre(static_cast<std::size_t>(count), Vec3(Real(0)));
  Vec3 lo(Real(1e30)), hi(Real(-1e30));
  for (std::int64_t k = 0; k < count; ++k) {
    const std::int64_t end = std::min(nv, (k + 1) * b);
    for (std::int64_t v = k * b; v < end; ++v)
      centre[k] += Vec3(Real(positions[v].x), Real(positions[v].y), Real(positions[v].z));
    centre[k] = centre[k] * (Real(1) / Real(end - k * b));
    lo = vmin(lo, centre[k]);
    hi = vmax(hi, centre[k]);
  }
  // One scale for all three axes (the Morton grid's cells are cubes): scaled per axis, a thin
  // axis would weigh as much as the longest, and two facing sheets (make_sheets_scene.py) were
  // ordered sheet by sheet: the diffuse ceiling fell to one or two ranks, read remotely by all.
  const Vec3 ext = hi - lo;
  const Real longest = std::max(ext.x, std::max(ext.y, ext.z));
  const Real inv = longest > 0 ? 1 / longest : 0;
  std::vector<std::uint64_t> key(static_cast<std::size_t>(count));
  for (std::int64_t k = 0; k < count; ++k)
    key[k] = bvh::detail::morton_key((centre[k] - lo) * inv, static_cast<std::uint32_t>(k));
  std::sort(key.begin(), key.end());
  // A block goes to the rank whose share of the total cost holds the block's middle.
  const double total = static_cast<double>(scene.colors());
  std::vector<Batch> out;
  double before = 0;
  for (std::uint64_t kk : key) {
    const std::int64_t k = static_cast<std::int64_t>(kk & 0xffffffffULL);
    const std::int64_t begin = k * b, end = std::min(nv, (k + 1) * b);
    const double cost = static_cast<double>(scene.color_offset[end] - scene.color_offset[begin]);
    const int rank = std::min(ranks - 1, static_cast<int>((before + cost / 2) * ranks / total));
    out.push_back({begin, end, rank});
    before += cost;
  }
  std::sort(out.begin(), out.end(),
            [](const Batch& x, const Batch& y) { return x.begin < y.begin; });
  std::vector<Batch> merged;
  for (const Batch& x : out) {
    if (!merged.empty() && merged.back().rank == x.rank && merged.back().end == x.begin)
      merged.back().end = x.end;
    else
      merged.push_back(x);
  }
  return merged;
}

namespace {

// How this rank's map is laid out and refreshed: which vertices it holds besides its own.
enum class Halo {
  kAll,     // one rank, or diffuse gather rays (they may read any vertex): the whole map
  kOwned,   // nothing is read across ranks (no iterations, or the traced reference)
  kTraced,  // the vertices the traced mirror hits read
};

// One bake from reading the scene to the report: the state each phase hands the next.
class BakeRun {
 public:
  BakeRun(Communicator& comm, const BakeConfig& c) : comm_(comm), c_(c), root_(comm.is_root()) {}
  int run();

 private:
  void read();
  void plan();
  nlohmann::json parameters() const;
  void print_banner(const MemoryEstimate& mem, double max_mem) const;
  void check_outputs() const;
  void check_memory();
  void setup();
  void trace_map();
  void plan_map();
  void count_reads();
  void assign_batches(std::vector<Batch> batches);
  void balance_by_pilot();
  bool counts_traced_cost() const;
  bool recuts_after_trace() const;
  void rebalance_by_traced_cost();
  std::int64_t move_traced_hits(const std::vector<Batch>& from);
  std::vector<TracePiece> pieces_owned_before(const std::vector<Batch>& from, bool mine) const;
  bool recuts_by_measured_time() const;
  void recut_by_measured_time(double my_time);
  void replan_first_reads(const std::vector<Batch>& from);
  void report_recut();
  void report_work();
  std::vector<char> read_items(const MapLayout& remote) const;
  bool fuses_halo_plan() const;
  std::vector<char> owned_vertices() const;
  MapLayout remote_layout(const std::vector<char>& own) const;
  void plan_exchange();
  void start_fused_plan(const std::vector<char>& own);
  void finish_fused_plan(int it);
  void report_map_plan();
  void bake_base();
  void restart();
  void restart_local_map();
  int iterate();
  HitCacheMode hit_mode(int it) const;
  std::vector<TracePiece> trace_pieces(bool progress) const;
  std::int64_t trace(int it, Kokkos::View<Vec3f*, MemSpace> out);
  bool shares_iteration(int it);
  void start_node_sharing(int it);
  void make_node_share();
  SegmentSizes node_share_room() const;
  std::int64_t trace_shared(int it);
  bool shares_trace() const;
  bool uses_node_map() const;
  bool node_holds_all() const;
  std::vector<char> map_vertices() const;
  void trace_node_shared();
  void report_node_sharing();
  void report_progress(int it, std::int64_t entries_done);
  void report_stopped(int it);
  void exchange(int it, IterationRecord& rec);
  void checkpoint(int it);
  bool stop_after(int it, double t0);
  std::vector<Vec3f> global_map();
  void release_iteration_buffers();
  void report_exchange();
  void write();
  void compare();
  void report_results();

  Communicator& comm_;
  const BakeConfig& c_;
  const bool root_;
  RunReport report_;
  PhaseTimer& timer_ = report_.timer;

  Mesh mesh_;
  BakeSceneHost host_;
  int iterations_ = 0;
  bool needs_iterations_ = false;
  Halo halo_ = Halo::kAll;
  std::vector<Batch> batches_;
  std::vector<int> owner_;  // rank of each vertex
  std::vector<VertexRange> my_ranges_;
  std::vector<std::int64_t> my_cache_offset_;
  std::vector<TracePiece> pieces_;  // the dispatches of every iteration (trace_pieces)
  std::int64_t my_items_ = 0, my_vertices_ = 0;
  nlohmann::json params_;
  std::string phash_;
  std::vector<InputFileHash> inputs_;  // content of the scene's files, when checkpointing
  Checkpoint restart_cp_;
  ReferenceMap reference_;

  std::unique_ptr<BakeSceneDevice> scene_;
  double scene_rss_bytes_ = 0;  // peak RSS once the scene and its BVH are up, before any map
  // This rank's peak and current RSS after each step of the run (mark_rss), in order: which
  // step sets the peak, which is what the memory bound per rank has to chase, and what the step
  // left resident (the difference is the step's transient).
  struct RssMark {
    std::string step;
    double peak = 0;
    ResidentNow now;
  };
  std::vector<RssMark> rss_marks_;
  // The large buffers this rank held after the step that raised its peak last (resident_buffers):
  // what the peak is made of, besides the scene and that step's transient.
  std::size_t peak_mark_ = 0;
  std::vector<std::pair<const char*, double>> buffers_at_peak_;
  void mark_rss(const std::string& step);
  std::vector<std::pair<const char*, double>> resident_buffers() const;
  void report_resident_buffers();
  std::unique_ptr<Chef> chef_;
  MapLayout layout_;
  std::unique_ptr<MapExchange> exchange_;
  // --node-sharing: the node's ranks take each other's pieces in the mirror iterations.
  std::unique_ptr<NodeShare> share_;
  std::unique_ptr<NodeHits> node_hits_;    // the node's hit records, from a shared trace on
  std::unique_ptr<NodeScene> node_scene_;  // the node's one copy of the scene (--node-sharing)
  std::unique_ptr<NodeMap> node_map_;      // the node's one map (uses_node_map)
  int share_from_ = -1;                    // the first shared iteration
  HitCacheMode shared_mode_ = HitCacheMode::kOff;      // the hit records published
  bool share_stale_ = false;                           // the part changed since it was published
  std::int64_t stolen_items_ = 0, stolen_pieces_ = 0;  // computed here for other ranks
  std::int64_t trace_stolen_items_ = 0;                // traced here for other ranks
  // The fused halo plan between plan_map and the end of iteration 1 (fuses_halo_plan).
  struct PendingHalo {
    bool active = false;
    std::vector<char> own;  // the vertices in the map (map_vertices)
    MapLayout remote;  // the remote vertices read, each with all its viewpoints: the flags' layout
    Kokkos::View<char*, MemSpace> flags;
  } pending_;
  Kokkos::View<char*, MemSpace> owned_;  // per vertex, with the traced halo
  // Per vertex: in this rank's map (owned_, or with the node's one map its node's vertices); the
  // others are read from the halo.
  Kokkos::View<char*, MemSpace> held_;
  std::vector<char> read_;               // per vertex: read by this rank's traced hits
  ReadCount traced_;                     // the mirror trace's rays and nodes (trace ownership)
  ReadCount reads_;                      // the reads of each iteration (final ownership)
  std::int64_t moved_hits_ = 0;          // traced hits this rank received at the rebalance
  std::vector<double> iteration_cost_;   // per vertex: colours + kLookupHitCost x lookup hits
  // --balance measured: the recut after the first mirror iteration, per rank
  // (recut_by_measured_time).
  struct MeasuredRecut {
    std::vector<double> measured;      // each rank's time of that iteration (s)
    std::vector<double> cost_before;   // counted iteration cost of each rank's vertices
    std::vector<double> cost_after;    // the same on the new ownership
    std::vector<double> scaled_after;  // the new ownership's cost scaled by measured / counted
    std::int64_t moved_colors = 0;     // colour entries this rank received
    std::int64_t bytes = 0;            // bytes this rank received (colours + traced hits)
    double seconds = 0;                // the recut and the re-planned first reads, this rank
  } recut_;
  Kokkos::View<Vec3f*, MemSpace> prev_, next_;

  int first_ = 0;
  std::vector<IterationRecord> iter_records_;
  std::vector<ChunkRecord> chunks_;
  RankTotals totals_;
  WriteStats written_;
  // Rank 0's own colour entries stand for the whole run (the batches are cut to equal cost).
  std::unique_ptr<ProgressLine> progress_line_;
  IterationEta eta_;
  double iterate_start_ = 0;
};

void BakeRun::read() {
  timer_.start("read");
  mesh_ = read_mesh(c_.input);
  // Hashed as read, for the checkpoint to remember and the restart to compare.
  if (!c_.checkpoint.empty() || !c_.restart.empty())
    inputs_ = hash_input_files(mesh_files(c_.input));
  timer_.stop();
  if (mesh_.positions.empty() || mesh_.faces.empty())
    throw InputError(c_.input, 0, "the scene has no vertices or no faces");
  check_representable(bounds_of(mesh_.positions), bounds_of(mesh_.positions).centre(), c_.input);
}

// The colour layout, the iteration count, the vertex batches and who owns which vertex.
void BakeRun::plan() {
  host_ = prepare_bake_scene(mesh_, c_.stored_viewpoints(), c_.all_view_dependent);
  needs_iterations_ = host_.reflective_vertices > 0 || c_.gather_rays > 0;
  // The traced reference is one pass (it follows the K mirror bounces itself).
  iterations_ = needs_iterations_ && !c_.trace_reference ? c_.iterations : 0;
  assign_batches(
      c_.balance == Balance::kSpatial
          ? make_spatial_batches(host_, mesh_.positions, comm_.size(), c_.batch_size)
          : make_batches(host_, comm_.size(), c_.balance, c_.batch_size, {}, c_.color_cap));
  if (comm_.size() == 1 || (c_.gather_rays > 0 && iterations_ > 0))
    halo_ = Halo::kAll;
  else if (iterations_ == 0)
    halo_ = Halo::kOwned;
  else
    halo_ = Halo::kTraced;
  params_ = parameters();
  report_.parameters = params_;
  report_.scene = {
      {"vertices", host_.vertices()},          {"faces", mesh_.faces.size()},
      {"triangles", mesh_.triangle_count()},   {"reflective_vertices", host_.reflective_vertices},
      {"emissive_faces", host_.lights.size()}, {"colors", host_.colors()}};
}

// Who owns which vertex, and this rank's ranges and hit-cache slots.
void BakeRun::assign_batches(std::vector<Batch> batches) {
  batches_ = std::move(batches);
  owner_.assign(static_cast<std::size_t>(host_.vertices()), 0);
  my_ranges_.clear();
  my_cache_offset_.clear();
  my_vertices_ = my_items_ = 0;
  for (const Batch& b : batches_) {
    std::fill(owner_.begin() + b.begin, owner_.begin() + b.end, b.rank);
    if (b.rank != comm_.rank()) continue;
    my_vertices_ += b.end - b.begin;
    my_ranges_.push_back({b.begin, b.end});
    my_cache_offset_.push_back(my_items_);
    my_items_ += host_.color_offset[b.end] - host_.color_offset[b.begin];
  }
}

// With ranks reading each other's colours along mirror rays, a colour whose ray hits a
// view-dependent vertex costs about kLookupHitCost others (kitchen.hpp), and where the rays hit
// varies across the mesh (bunny_room: 0.01 to 0.9 lookup hits per colour between the 16 ranks'
// colour-balanced ranges). A pilot of kPilotRays mirror rays per vertex, traced by every rank for
// its share of the vertices, estimates those hits and the BVH nodes the rays visit. --balance
// pilot cuts the final ranges by colours plus estimated hits; --balance cost cuts ranges of
// equal estimated trace work (nodes) for the mirror trace and recuts them after it by the hits
// it counted (rebalance_by_traced_cost).
void BakeRun::balance_by_pilot() {
  constexpr int kPilotRays = 8;
  const std::int64_t nv = host_.vertices(), p = comm_.size(), r = comm_.rank();
  const MirrorCostEstimate mine =
      estimate_mirror_costs(*scene_, c_, nv * r / p, nv * (r + 1) / p, kPilotRays, totals_.rays);
  std::vector<double> cost;
  if (c_.balance == Balance::kPilot) {
    cost = lookup_hit_cost(host_, comm_.allgatherv(mine.lookup_hits), kPilotLookupHitCost);
  } else {
    cost = mirror_trace_cost(host_, comm_.allgatherv(mine.nodes));
  }
  assign_batches(
      make_batches(host_, comm_.size(), Balance::kCost, c_.batch_size, cost, c_.color_cap));
}

// The mirror trace and the iterations weigh vertices differently (BVH nodes against viewpoint
// lookups; bunny_room's pilot-balanced ranks traced 0.17-0.44 s and iterated at up to 1.2x the
// mean), so the trace runs on ranges of equal trace work, and the ranges are recut afterwards by
// the lookup hits it counted, exactly: colours + kLookupHitCost x hits. The traced hits move to
// their new owners (the same bits: output identical to any other cut).
void BakeRun::rebalance_by_traced_cost() {
  std::vector<float> mine;
  for (std::size_t k = 0; k < my_ranges_.size(); ++k) {
    const std::vector<float> h =
        chef_->lookup_hits(my_ranges_[k].begin, my_ranges_[k].end, my_cache_offset_[k]);
    mine.insert(mine.end(), h.begin(), h.end());
  }
  // allgatherv concatenates by rank; each rank's ranges are in vertex order.
  const std::vector<float> all = comm_.allgatherv(mine);
  std::vector<float> hits(static_cast<std::size_t>(host_.vertices()));
  std::size_t at = 0;
  for (int r = 0; r < comm_.size(); ++r)
    for (const Batch& b : batches_)
      if (b.rank == r)
        for (std::int64_t v = b.begin; v < b.end; ++v) hits[v] = all[at++];
  const std::vector<Batch> from = batches_;
  iteration_cost_ = lookup_hit_cost(host_, hits);
  assign_batches(make_batches(host_, comm_.size(), Balance::kCost, c_.batch_size, iteration_cost_,
                              c_.color_cap));
  moved_hits_ = move_traced_hits(from);
}

// --balance cost and measured cut the iterations' ranges by the cost counted at the traced hits.
bool BakeRun::counts_traced_cost() const {
  return c_.balance == Balance::kCost || c_.balance == Balance::kMeasured;
}

// Whether the ranges are recut after the trace (counts_traced_cost). Not where node work sharing
// spans every rank (one node): there each iteration evens itself out as the ranks take each
// other's pieces, and the recut would only move traced hits between the ranks before iteration 1
// (on bunny_room at 16 x 1, 72 % of them; results/bake/distributed.md, twenty-first round).
// Across nodes the recut stays: sharing balances within a node, not between nodes.
bool BakeRun::recuts_after_trace() const {
  const bool one_sharing_node =
      c_.share_work && comm_.size() > 1 && comm_.node_size() == comm_.size();
  return counts_traced_cost() && !one_sharing_node;
}

// The traced hits of ownership `from` to this rank's batches (the current ownership); returns
// the hits received from other ranks.
std::int64_t BakeRun::move_traced_hits(const std::vector<Batch>& from) {
  if (same_batches(from, batches_)) return 0;
  // Two statements, so the old hits are freed before the Chef refills its float cache.
  const auto hits = move_entries(comm_, host_, from, batches_, chef_->take_traced_hits());
  chef_->adopt_traced_hits(hits);
  std::int64_t received = 0;
  for (const TracePiece& p : pieces_owned_before(from, false))
    received += host_.color_offset[p.end] - host_.color_offset[p.begin];
  return received;
}

// The parts of this rank's ranges that ownership `from` gave this rank (mine) or another rank
// (!mine), each with its hit-cache slot.
std::vector<TracePiece> BakeRun::pieces_owned_before(const std::vector<Batch>& from,
                                                     bool mine) const {
  std::vector<TracePiece> out;
  for (std::size_t k = 0; k < my_ranges_.size(); ++k) {
    const VertexRange r = my_ranges_[k];
    for (const Batch& f : from) {
      if ((f.rank == comm_.rank()) != mine || f.end <= r.begin || f.begin >= r.end) continue;
      const std::int64_t begin = std::max(r.begin, f.begin), end = std::min(r.end, f.end);
      out.push_back(
          {begin, end,
           my_cache_offset_[k] + host_.color_offset[begin] - host_.color_offset[r.begin]});
    }
  }
  return out;
}

nlohmann::json BakeRun::parameters() const {
  return {{"input", c_.input},
          {"output", c_.output},
          {"viewpoints", c_.viewpoints},
          {"directions", to_string(c_.directions)},
          {"stored_viewpoints", c_.stored_viewpoints()},
          {"iterations", c_.iterations},
          {"shadow_samples", c_.shadow_samples},
          {"gather_rays", c_.gather_rays},
          {"seed", c_.seed},
          {"lookup", to_string(c_.lookup)},
          {"balance", to_string(c_.balance)},
          {"batch_size", c_.batch_size},
          {"max_colors", c_.color_cap},
          {"batches", batches_.size()},
          {"bvh", bvh::to_string(c_.bvh)},
          {"background", {c_.background.x, c_.background.y, c_.background.z}},
          {"max_memory", c_.max_memory},
          {"time_limit_minutes", c_.time_limit_minutes},
          {"hit_cache", c_.cache_hits},
          {"two_sided", c_.two_sided},
          {"all_view_dependent", c_.all_view_dependent},
          {"checkpoint", c_.checkpoint},
          {"restart", c_.restart},
          {"reference", c_.reference},
          {"trace_reference", c_.trace_reference},
          {"node_sharing", node_sharing_name(c_)},
          {"node_map", c_.node_map}};
}

void BakeRun::print_banner(const MemoryEstimate& mem, double max_mem) const {
  std::printf("%s\n", build_banner().c_str());
  std::printf("bake: view-dependent ray-trace map (Robinson & Jacoby-Cooper), %d rank(s)\n",
              comm_.size());
  for (auto it = params_.begin(); it != params_.end(); ++it)
    std::printf("  %-20s %s\n", it.key().c_str(), it.value().dump().c_str());
  std::printf("  scene: %lld vertices (%lld reflective), %zu faces, %zu triangles, %zu lights\n",
              static_cast<long long>(host_.vertices()),
              static_cast<long long>(host_.reflective_vertices), mesh_.faces.size(),
              mesh_.triangle_count(), host_.lights.size());
  std::printf("  colour map: %lld entries (view-independent vertices keep one colour)\n",
              static_cast<long long>(host_.colors()));
  if (c_.trace_reference)
    std::printf("  traced reference: %d mirror bounces traced per colour, no map lookups\n",
                needs_iterations_ ? c_.iterations : 0);
  if (!needs_iterations_ && c_.iterations > 0)
    std::printf("  note: no reflective vertex and no gather rays: iterations 1..%d skipped\n",
                c_.iterations);
  if (host_.lights.empty()) std::printf("  note: no emissive faces: no shadow rays\n");
  // (Rank 0's node stands for the others: a job places ranks alike.)
  if (!c_.share_work && node_sharing_possible() && comm_.node_size() >= 4 && needs_iterations_)
    std::printf(
        "  note: %d ranks share this node; --node-sharing on lets them take each other's "
        "unfinished work (README: ranks and threads on a node)\n",
        comm_.node_size());
  std::printf(
      "  memory estimate (max over ranks): %s peak resident (scene %s, maps %s, hit cache %s, "
      "host %s)%s\n",
      human_bytes(max_mem).c_str(), human_bytes(double(mem.scene)).c_str(),
      human_bytes(double(mem.maps)).c_str(), human_bytes(double(mem.hit_cache)).c_str(),
      human_bytes(double(mem.host)).c_str(),
      halo_ == Halo::kTraced ? " + the halo (known after the mirror trace)" : "");
  std::fflush(stdout);
}

// Every place this run will write, before anything is computed (IoError: exit 3); sizes: the
// text map (~60 bytes a colour; the binary form is smaller) and the checkpoint's colours.
void BakeRun::check_outputs() const {
  const double colors = static_cast<double>(host_.colors());
  check_output_places({{c_.output, colors * 60},
                       {c_.checkpoint, colors * sizeof(Vec3f)},
                       {c_.summary, 0},
                       {c_.timings, 0}});
}

// Prints the banner and refuses (IoError on every rank: exit 3) a run that would not fit.
void BakeRun::check_memory() {
  const std::int64_t local = halo_ == Halo::kAll ? host_.colors() : my_items_;
  const MemoryEstimate mem =
      estimate_memory(mesh_, host_, my_items_, my_vertices_, local, iterations_, c_, root_);
  const MemoryNeed need{static_cast<double>(mem.host),
                        static_cast<double>(mem.scene + mem.maps + mem.hit_cache)};
  const MemoryPeak peak = expected_peak(need);
  const double max_peak = comm_.max(peak.host + peak.device);
  report_.scene["memory_estimate_bytes"] = max_peak;
  if (root_) print_banner(mem, max_peak);
  require_memory(comm_, need, c_.max_memory);
}

// Validates the restart and the reference (every rank, so all agree on a bad one: exit 2)
// before anything is baked, then uploads the scene.
void BakeRun::setup() {
  phash_ = parameter_hash(c_);
  if (!c_.restart.empty()) {
    restart_cp_ = read_checkpoint(c_.restart, phash_, inputs_, host_.colors());
    if (restart_cp_.iteration > iterations_)
      throw InputError(c_.restart, 0,
                       "checkpoint is at iteration " + std::to_string(restart_cp_.iteration) +
                           ", beyond --iterations " + std::to_string(iterations_));
  }
  if (!c_.reference.empty()) reference_ = read_reference_map(c_.reference, mesh_);
  scene_ =
      std::make_unique<BakeSceneDevice>(upload_bake_scene(mesh_, host_, c_.viewpoints, c_.bvh));
  if (c_.share_scene && comm_.size() > 1) node_scene_ = std::make_unique<NodeScene>(comm_, *scene_);
  scene_rss_bytes_ = peak_rss_bytes();
  if (halo_ == Halo::kTraced && (counts_traced_cost() || c_.balance == Balance::kPilot))
    balance_by_pilot();
  chef_ = std::make_unique<Chef>(*scene_, c_, my_items_);
}

// Phase "map" (bake time): traces this rank's mirror rays once, recuts the ownership by what
// they cost (--balance cost), and finds the vertices the hits read.
void BakeRun::trace_map() {
  timer_.start("map");
  if (halo_ == Halo::kTraced) {
    if (shares_trace()) {
      trace_node_shared();
    } else {
      for (std::size_t k = 0; k < my_ranges_.size(); ++k) {
        const ReadCount n =
            chef_->trace_mirror_hits(my_ranges_[k].begin, my_ranges_[k].end, my_cache_offset_[k]);
        traced_.rays += n.rays;
        traced_.nodes += n.nodes;
      }
    }
    totals_.rays += traced_.rays;
    if (recuts_after_trace()) rebalance_by_traced_cost();
    count_reads();
  }
  timer_.stop();
}

// Whether the mirror trace is shared between the node's ranks (NodeHits): with --node-sharing
// on (work), on one node, where no recut moves the traced hits after it.
bool BakeRun::shares_trace() const {
  return c_.share_work && comm_.size() > 1 && comm_.node_size() == comm_.size() &&
         !recuts_after_trace();
}

// The mirror trace with the node's ranks taking each other's pieces, as the iterations do
// (trace_shared): each rank's hit records live in the node's window from the start, a rank that
// has traced its own pieces traces the unclaimed pieces of the others into their owners'
// records, and the records are complete on every rank after the closing barrier. The rays and
// BVH nodes are counted for the owner of the vertices (the work counters stay the cut's, the
// same on any machine), the colour entries traced for others for the tracer.
void BakeRun::trace_node_shared() {
  node_hits_ = std::make_unique<NodeHits>(comm_, my_items_, trace_pieces(true));
  const int me = node_hits_->node_rank(), ranks = node_hits_->node_size();
  std::vector<double> counted(2 * static_cast<std::size_t>(ranks), 0.0);  // rays, nodes by owner
  chef_->adopt_traced_hits(node_hits_->traced(me));
  // Test hook: the node's first rank starts late, so that the others take its pieces for certain.
  if (me == 0 && c_.share_test_delay > 0)
    std::this_thread::sleep_for(std::chrono::duration<double>(c_.share_test_delay));
  for (int k = 0; k < ranks; ++k) {
    const int owner = (me + k) % ranks;
    const Kokkos::View<TracedHit*, MemSpace> records = node_hits_->traced(owner);
    std::int64_t first = 0, end = 0;
    while (node_hits_->claim(owner, first, end)) {
      while (first < end) {
        std::int64_t pieces = 0;
        const TracePiece r = node_hits_->next_run(owner, first, end, pieces);
        const ReadCount n = chef_->trace_mirror_hits_into(records, r.begin, r.end, r.cache_offset);
        counted[2 * owner] += static_cast<double>(n.rays);
        counted[2 * owner + 1] += static_cast<double>(n.nodes);
        if (k > 0) trace_stolen_items_ += host_.color_offset[r.end] - host_.color_offset[r.begin];
      }
    }
  }
  Kokkos::fence();
  node_hits_->barrier(comm_);
  // One node: node rank = rank (the node's communicator keeps the order of comm_'s).
  const std::vector<double> all = comm_.allgatherv(counted);
  for (int r = 0; r < ranks; ++r) {
    traced_.rays += static_cast<std::int64_t>(all[2 * (r * ranks + me)]);
    traced_.nodes += static_cast<std::int64_t>(all[2 * (r * ranks + me) + 1]);
  }
}

// Which vertices this rank's traced hits read (read_), and its reads per iteration (reads_).
void BakeRun::count_reads() {
  const std::size_t nv = static_cast<std::size_t>(host_.vertices());
  std::vector<char> own(nv, 0);
  for (const VertexRange& r : my_ranges_) std::fill(own.begin() + r.begin, own.begin() + r.end, 1);
  owned_ = Kokkos::View<char*, MemSpace>("rtmini::bake::owned", nv);
  Kokkos::View<char*, MemSpace> read("rtmini::bake::read", nv);
  Kokkos::deep_copy(owned_, compat::host_view(own.data(), nv));
  reads_ = ReadCount{};
  for (std::size_t k = 0; k < my_ranges_.size(); ++k) {
    const ReadCount n = chef_->count_mirror_reads(my_ranges_[k].begin, my_ranges_[k].end,
                                                  my_cache_offset_[k], owned_, read);
    reads_.lookups += n.lookups;
    reads_.reads += n.reads;
    reads_.view_reads += n.view_reads;
    reads_.remote_reads += n.remote_reads;
  }
  compat::download(read, read_);
}

// This rank's own vertices, one flag per vertex.
std::vector<char> BakeRun::owned_vertices() const {
  std::vector<char> own(static_cast<std::size_t>(host_.vertices()), 0);
  for (const VertexRange& r : my_ranges_) std::fill(own.begin() + r.begin, own.begin() + r.end, 1);
  return own;
}

// The layout of the remote vertices this rank reads, each with all its colours (where read flags
// sit until the halo keeps only the colours read): those the traced hits read, or with
// diffuse gather rays every other rank's vertex.
MapLayout BakeRun::remote_layout(const std::vector<char>& own) const {
  std::vector<char> remote(own.size());
  for (std::size_t v = 0; v < own.size(); ++v)
    remote[v] = !own[v] && (halo_ == Halo::kAll || (halo_ == Halo::kTraced && read_[v]));
  return make_map_layout(host_, remote);
}

// Phase "halo" (bake time): the vertices this rank holds, their layout and the exchange that
// keeps the remote ones fresh.
void BakeRun::plan_map() {
  timer_.start("halo");
  const std::vector<char> own = map_vertices();
  held_ = uses_node_map() ? compat::upload<MemSpace>("rtmini::bake::held", own) : owned_;
  if (node_holds_all()) {
    layout_ = make_map_layout(host_, own);  // nothing is remote: no halo, no exchange
  } else if (fuses_halo_plan()) {
    start_fused_plan(own);
  } else if (comm_.size() == 1 || halo_ == Halo::kOwned) {
    layout_ = make_map_layout(host_, halo_ == Halo::kAll ? std::vector<char>(own.size(), 1) : own);
  } else {
    // Several ranks: diffuse gather rays read any vertex, all its colours; a restart's traced
    // lookups, the colours they read (read_items).
    const MapLayout remote = remote_layout(own);
    const std::vector<char> read =
        halo_ == Halo::kTraced ? read_items(remote) : std::vector<char>();
    layout_ = make_halo_layout(host_, remote, read.empty() ? nullptr : read.data(), owner_, own);
  }
  if (!pending_.active) {
    make_node_share();
    if (node_holds_all()) {
      chef_->set_map_offset(layout_.device);
      report_map_plan();
    } else {
      plan_exchange();
    }
  }
  prev_ = share_ ? share_->map_buffer(0)
                 : Kokkos::View<Vec3f*, MemSpace>("rtmini::bake::map_prev", layout_.colors());
  next_ = share_ ? share_->map_buffer(1)
                 : Kokkos::View<Vec3f*, MemSpace>("rtmini::bake::map_next", layout_.colors());
  timer_.stop();
}

// Whether the ranks of a node keep one map (NodeMap, --node-map on): with work shared between
// them (node sharing's window holds each rank's part). Not for the traced reference or a run
// without mirror iterations (no map is read across ranks).
bool BakeRun::uses_node_map() const {
  return c_.node_map && c_.share_work && comm_.size() > 1 && !c_.trace_reference &&
         iterations_ >= 1 && halo_ != Halo::kOwned;
}

// The node's one map on the only node: every vertex in it, nothing read from a halo.
bool BakeRun::node_holds_all() const {
  return uses_node_map() && comm_.node_size() == comm_.size();
}

// The vertices this rank's map holds: its own, or with the node's one map every vertex its
// node's ranks own.
std::vector<char> BakeRun::map_vertices() const {
  if (!uses_node_map()) return owned_vertices();
  std::vector<char> on_node(static_cast<std::size_t>(comm_.size()), 0);
  for (const int r : comm_.node_ranks()) on_node[static_cast<std::size_t>(r)] = 1;
  std::vector<char> own(static_cast<std::size_t>(host_.vertices()));
  for (std::size_t v = 0; v < own.size(); ++v) own[v] = on_node[static_cast<std::size_t>(owner_[v])];
  return own;
}

// The room this rank's segment of the node's window needs (node_share.hpp): the maps and the
// exchange's halo are made there; the hits, base colours and tables are copied in when sharing
// starts. Before a fused first iteration the halo is not planned yet: its room is every colour
// of the remote vertices read, of which it keeps a part.
SegmentSizes BakeRun::node_share_room() const {
  SegmentSizes room;
  room.vertices = host_.vertices();
  room.map_colors = layout_.colors();
  room.hits = my_items_;
  room.sparse = 1;
  room.pieces = static_cast<std::int64_t>(trace_pieces(true).size());
  room.iterations = iterations_ + 1;
  if (!pending_.active) {
    room.halo_colors = layout_.halo_colors;
    room.mask_words = static_cast<std::int64_t>(layout_.mask.size());
  } else {
    room.halo_colors = pending_.remote.colors();
    room.read_flags = pending_.remote.colors();
    for (std::int64_t v = 0; v < host_.vertices(); ++v)
      if (pending_.remote.in_map(v) && host_.color_count(v) > 1)
        room.mask_words += (host_.color_count(v) + 63) / 64;  // make_halo_layout's words
  }
  room.kept_words = room.mask_words;
  return room;
}

// The exchange of layout_'s halo, whose receive buffer the Chef's reads of the halo then see.
void BakeRun::plan_exchange() {
  exchange_ = std::make_unique<MapExchange>(
      comm_, host_, layout_, c_.changed_exchanges,
      share_ ? share_->halo(layout_.halo_colors) : Kokkos::View<Vec3f*, MemSpace>(),
      node_map_ != nullptr);
  if (!layout_.sparse.empty()) layout_.sparse.halo = exchange_->halo();
  chef_->set_map_offset(layout_.device, layout_.sparse);
  report_map_plan();
}

// Which colours of remote vertices a rank reads is known only once its lookups have run at the
// traced hits. A fresh run's first mirror iteration runs exactly those lookups on the base map,
// whose colours are constant per vertex: it reads remote vertices from their fetched base
// colours and flags what it reads (FirstReads), and the sparse layout and exchange are planned
// right after it. A restart's first iteration reads a map that varies per viewpoint, so it needs
// the read set up front: a separate pass over the lookups (read_items).
bool BakeRun::fuses_halo_plan() const {
  return halo_ == Halo::kTraced && c_.restart.empty() && iterations_ >= 1 && !node_holds_all();
}

// Until iteration 1 has run, this rank's map holds its own vertices only; the remote vertices'
// base colours come from their owners (one colour per vertex).
void BakeRun::start_fused_plan(const std::vector<char>& own) {
  layout_ = make_map_layout(host_, own);
  mark_dense(host_, layout_);  // the readers take colour counts from the scene, not the layout
  chef_->set_map_offset(layout_.device, layout_.sparse);
  pending_.remote = remote_layout(own);
  pending_.own = own;
  pending_.active = true;
  make_node_share();
  pending_.flags =
      share_ ? share_->read_flags()
             : Kokkos::View<char*, MemSpace>("rtmini::bake::read_items",
                                             static_cast<std::size_t>(pending_.remote.colors()));
  std::vector<std::int64_t> remote;
  for (std::int64_t v = 0; v < host_.vertices(); ++v)
    if (pending_.remote.in_map(v)) remote.push_back(v);
  std::vector<Vec3> base;
  compat::download(chef_->base(), base);
  // Vec3f(base): the bits iteration 0 stores for every viewpoint of the vertex.
  std::vector<Vec3f> mine(base.size());
  for (std::size_t v = 0; v < base.size(); ++v)
    if (own[v]) mine[v] = Vec3f(base[v]);
  const std::vector<Vec3f> fetched = fetch_vertex_colors(comm_, owner_, remote, mine);
  std::vector<Vec3f> remote_base(base.size());
  for (std::size_t k = 0; k < remote.size(); ++k) remote_base[remote[k]] = fetched[k];
  FirstReads first;
  first.owned = held_;
  first.base = compat::upload<MemSpace>("rtmini::bake::remote_base", remote_base);
  first.at = pending_.remote.device;
  first.flags = pending_.flags;
  chef_->set_first_reads(first);
}

// After the fused first iteration: the halo from what it read and the exchange plan. The map
// keeps its layout (this rank's vertices, dense), so iteration 1's colours stay where they are.
void BakeRun::finish_fused_plan(int it) {
  chef_->set_first_reads(FirstReads{});
  {
    // The flags (one byte per colour of every remote vertex read, the flags' view itself on a
    // host backend) go before the exchange is planned: held through the plan, they were 7 MiB
    // of the largest 16 x 1 rank's 98 MiB peak on bunny_room (results/bake/distributed.md,
    // fifteenth round).
    const auto read = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pending_.flags);
    layout_ = make_halo_layout(host_, pending_.remote, read.data(), owner_, pending_.own);
  }
  pending_ = PendingHalo{};
  if (share_) {
    share_->release_read_flags();
    share_stale_ = true;  // the halo's tables are new: published again before the next iteration
  }
  mark_rss("iteration " + std::to_string(it) + " halo layout");
  // A measured recut changed this rank's share (next_ moved with it); prev_ follows.
  if (static_cast<std::int64_t>(prev_.extent(0)) != layout_.colors())
    prev_ = Kokkos::View<Vec3f*, MemSpace>("rtmini::bake::map_prev", layout_.colors());
  plan_exchange();
  mark_rss("iteration " + std::to_string(it) + " exchange plan");
}

void BakeRun::mark_rss(const std::string& step) {
  const RssMark m{step, peak_rss_bytes(), resident_now()};
  if (rss_marks_.empty() || m.peak > rss_marks_[peak_mark_].peak) {
    peak_mark_ = rss_marks_.size();
    buffers_at_peak_ = resident_buffers();
  }
  rss_marks_.push_back(m);
}

// The buffers of the bake proper that this rank holds now, in bytes (host and device copies;
// one where they share memory). The scene, its BVH and the runtimes are the scene's RSS.
std::vector<std::pair<const char*, double>> BakeRun::resident_buffers() const {
  const auto bytes = [](const auto& v) {
    return static_cast<double>(v.span() * sizeof(typename std::decay_t<decltype(v)>::value_type));
  };
  const double nv = static_cast<double>(host_.vertices());
  // Per vertex: the owner (4 bytes), the read and owned flags, the iteration cost, the base.
  double per_vertex = static_cast<double>(owner_.capacity() * sizeof(int) + read_.capacity() +
                                          iteration_cost_.capacity() * sizeof(double)) +
                      bytes(owned_);
  if (chef_) per_vertex += bytes(chef_->base());
  double first = 0;  // the fused first iteration's read flags, their layout, the remote bases
  if (pending_.active)
    first = bytes(pending_.flags) + double(pending_.remote.table_bytes()) + nv * sizeof(Vec3f);
  // The node's one map: this rank's share of it, its own vertices (the rest is the others').
  const double map = node_map_ ? 2.0 * static_cast<double>(my_items_ * sizeof(Vec3f))
                               : bytes(prev_) + bytes(next_);
  return {{"map", map},
          {"hits", chef_ ? double(chef_->hit_bytes()) : 0.0},
          {"halo", exchange_ ? bytes(exchange_->halo()) : 0.0},
          {"send_list", exchange_ ? double(exchange_->send_list_bytes()) : 0.0},
          {"exchange_scratch", exchange_ ? double(exchange_->scratch_bytes()) : 0.0},
          {"layout_tables", double(layout_.table_bytes())},
          {"first_iteration_reads", first},
          {"per_vertex", per_vertex}};
}

// The summary's scene.resident_at_peak: per rank, the step after which its peak was highest, the
// RSS that step left, and the buffers held then (resident_buffers); one collective. Stdout
// gives the largest rank's.
void BakeRun::report_resident_buffers() {
  const RssMark& at = rss_marks_[peak_mark_];
  std::vector<double> mine{static_cast<double>(peak_mark_),
                           at.peak,
                           at.now.total,
                           at.now.anon,
                           at.now.file,
                           at.now.shmem,
                           at.now.huge};
  constexpr std::size_t kBuffers = 7;  // the buffers' fields follow these
  for (const auto& b : buffers_at_peak_) mine.push_back(b.second);
  const std::vector<std::vector<double>> field = gather_fields(comm_, mine);
  const std::size_t ranks = field[0].size();
  nlohmann::json out;
  std::vector<std::string> steps(ranks);
  for (std::size_t r = 0; r < ranks; ++r)
    steps[r] = rss_marks_[static_cast<std::size_t>(field[0][r])].step;
  out["step_per_rank"] = steps;
  out["peak_bytes_per_rank"] = field[1];
  out["rss_after_step_bytes_per_rank"] = field[2];
  out["rss_anon_after_step_bytes_per_rank"] = field[3];
  out["rss_file_after_step_bytes_per_rank"] = field[4];
  out["rss_shmem_after_step_bytes_per_rank"] = field[5];
  out["rss_huge_after_step_bytes_per_rank"] = field[6];
  for (std::size_t k = 0; k < buffers_at_peak_.size(); ++k)
    out[buffers_at_peak_[k].first] = field[kBuffers + k];
  report_.scene["resident_at_peak"] = out;
  if (!root_) return;
  const std::vector<double>& peaks = field[1];
  const std::size_t top = std::max_element(peaks.begin(), peaks.end()) - peaks.begin();
  std::string line;
  for (std::size_t k = 0; k < buffers_at_peak_.size(); ++k)
    line += std::string(k ? ", " : "") + buffers_at_peak_[k].first + " " +
            human_bytes(field[kBuffers + k][top]);
  std::printf(
      "  rank %zu's peak %s (after '%s', %s resident then: heap %s, files %s, shared "
      "memory %s): %s\n",
      top, human_bytes(peaks[top]).c_str(), steps[top].c_str(), human_bytes(field[2][top]).c_str(),
      human_bytes(field[3][top]).c_str(), human_bytes(field[4][top]).c_str(),
      human_bytes(field[5][top]).c_str(), line.c_str());
}

// The measured recut's threshold: the slowest rank's first mirror iteration over the mean.
constexpr double kRecutMinImbalance = 1.03;

// The largest of `x` over their mean (1 for none).
double max_over_mean(const std::vector<double>& x) {
  double sum = 0;
  for (double e : x) sum += e;
  return sum > 0 ? *std::max_element(x.begin(), x.end()) * double(x.size()) / sum : 1.0;
}

// --balance measured on a fresh run of several ranks and at least two mirror iterations: the
// ranges are recut between the first mirror iteration and the exchange after it.
bool BakeRun::recuts_by_measured_time() const {
  return c_.balance == Balance::kMeasured && fuses_halo_plan() && iterations_ >= 2;
}

// The counted cost (colours + kLookupHitCost x lookup hits) balances what the counters see. On
// the 16-core host at 16 x 1 the ranks' cached iterations still took 0.46-0.71 s with the
// counted cost balanced to 1.001, each rank keeping its place in every iteration, while their
// mirror traces, on the same cores, took the same time to 3 %: some vertices cost more than
// counted, and the first mirror iteration shows which ranks hold them (its time per counted
// cost, rank by rank, correlates 0.84 with the cached iterations'; results/bake/distributed.md).
// So every vertex's counted cost is scaled by its rank's measured / counted of that iteration,
// and the ranges are cut once more by that. Every colour is still computed from the same inputs:
// the output is identical; only the ownership follows the measured times, which vary run to run.
// Below kRecutMinImbalance (slowest rank over the mean) the cut stays: the recut (the moves and
// the incremental re-plan) took about 10 % of an iteration at 2 ranks
// (results/bake/distributed.md), about what 3 % saved in each of the three cached iterations of K =
// 4 would gain.
void BakeRun::recut_by_measured_time(double my_time) {
  const double t0 = timer_.now();
  const int p = comm_.size(), rank = comm_.rank();
  const std::int64_t nv = host_.vertices();
  std::vector<double> counted(static_cast<std::size_t>(p), 0.0);
  for (std::int64_t v = 0; v < nv; ++v) counted[owner_[v]] += iteration_cost_[v];
  if (c_.recut_test_skew > 0) my_time = counted[rank] * (1 + c_.recut_test_skew * rank) * 1e-9;
  recut_.measured = comm_.allgatherv(std::vector<double>{my_time});
  // Seconds per counted unit, rank by rank (the mean rate where a rank measured nothing).
  double all_time = 0, all_cost = 0;
  for (int r = 0; r < p; ++r) {
    all_time += recut_.measured[r];
    all_cost += counted[r];
  }
  std::vector<double> rate(static_cast<std::size_t>(p), all_cost > 0 ? all_time / all_cost : 1.0);
  for (int r = 0; r < p; ++r)
    if (counted[r] > 0 && recut_.measured[r] > 0) rate[r] = recut_.measured[r] / counted[r];
  std::vector<double> scaled(static_cast<std::size_t>(nv));
  for (std::int64_t v = 0; v < nv; ++v) scaled[v] = iteration_cost_[v] * rate[owner_[v]];
  const std::vector<Batch> from = batches_;
  recut_.cost_before = counted;
  if (max_over_mean(recut_.measured) >= kRecutMinImbalance)
    assign_batches(make_batches(host_, p, Balance::kCost, c_.batch_size, scaled, c_.color_cap));
  if (same_batches(batches_, from)) {  // nothing to move
    if (chef_->caches_hits()) chef_->release_traced_hits();
    recut_.cost_after = counted;
    recut_.scaled_after = recut_.measured;
    recut_.seconds = timer_.now() - t0;
    report_recut();
    return;
  }
  recut_.cost_after.assign(static_cast<std::size_t>(p), 0.0);
  recut_.scaled_after.assign(static_cast<std::size_t>(p), 0.0);
  for (std::int64_t v = 0; v < nv; ++v) {
    recut_.cost_after[owner_[v]] += iteration_cost_[v];
    recut_.scaled_after[owner_[v]] += scaled[v];
  }
  // Iteration 1's colours of the old ranges go to their new owners: until the halo is planned
  // the local map holds this rank's vertices only, in the order of its ranges, as move_entries
  // takes them.
  next_ = move_entries(comm_, host_, from, batches_, next_);
  recut_.moved_colors = move_traced_hits(from);
  recut_.bytes = recut_.moved_colors * static_cast<std::int64_t>(sizeof(Vec3f) + sizeof(TracedHit));
  // The base colours of the vertices received (the counter-based samples of their old owner).
  for (const TracePiece& piece : pieces_owned_before(from, false))
    totals_.rays += chef_->bake_base(piece.begin, piece.end);
  replan_first_reads(from);
  // The traced hits served their iteration (trace() kept them for this move).
  if (chef_->caches_hits()) chef_->release_traced_hits();
  pieces_ = trace_pieces(progress_line_->enabled());
  recut_.seconds = timer_.now() - t0;
  report_work();
  report_recut();
}

// The fused plan's read flags for the ownership after the measured recut. What iteration 1
// flagged stays true for the vertices this rank kept (the colours of other ranks' vertices
// their lookups read); what is new is looked up: the colours of the vertices it gave away that
// the kept ones read, and every remote colour the received vertices read. Flags that only the
// given-away vertices set stay where the vertex is still read (a few halo colours more, and no
// lookups repeated for the vertices kept).
void BakeRun::replan_first_reads(const std::vector<Batch>& from) {
  const Kokkos::View<const char*, MemSpace> owned_before = owned_;
  count_reads();  // owned_, read_ and reads_ of the new ownership
  const std::vector<char> own = owned_vertices();
  MapLayout remote = remote_layout(own);
  const Kokkos::View<char*, MemSpace> flags =
      moved_read_flags(pending_.remote.device, pending_.flags, remote.device, remote.colors());
  const Kokkos::View<char*, MemSpace> not_given = not_given_away(owned_before, owned_);
  chef_->set_map_offset(remote.device);
  for (const TracePiece& piece : pieces_owned_before(from, true))
    chef_->mark_read_items(piece.begin, piece.end, piece.cache_offset, not_given, flags);
  for (const TracePiece& piece : pieces_owned_before(from, false))
    chef_->mark_read_items(piece.begin, piece.end, piece.cache_offset, owned_, flags);
  pending_.remote = std::move(remote);
  pending_.flags = flags;
  pending_.own = own;
  held_ = owned_;  // (a measured recut never runs with the node's one map: no work sharing)
  layout_ = make_map_layout(host_, own);
  mark_dense(host_, layout_);
  chef_->set_map_offset(layout_.device, layout_.sparse);
}

// The measured recut into the summary's scene.recut and the timings file's parameters: every
// rank's measured time, counted cost before and after, and the cost after scaled as the cut
// saw it; the colours and bytes moved and the recut's time (max over ranks).
void BakeRun::report_recut() {
  const double colors = static_cast<double>(comm_.sum(recut_.moved_colors));
  const double bytes = static_cast<double>(comm_.sum(recut_.bytes));
  const double seconds = comm_.max(recut_.seconds);
  const double before = max_over_mean(recut_.measured);
  const double after = max_over_mean(recut_.scaled_after);
  report_.scene["recut"] = {{"after_iteration", 1},
                            {"min_imbalance", kRecutMinImbalance},
                            {"measured_time_per_rank", recut_.measured},
                            {"counted_cost_before_per_rank", recut_.cost_before},
                            {"counted_cost_after_per_rank", recut_.cost_after},
                            {"scaled_cost_after_per_rank", recut_.scaled_after},
                            {"measured_max_over_mean", before},
                            {"predicted_max_over_mean", after},
                            {"moved_colors", colors},
                            {"moved_fraction", colors / std::max(1.0, double(host_.colors()))},
                            {"bytes", bytes},
                            {"seconds", seconds},
                            {"test_skew", c_.recut_test_skew}};
  params_["recut"] = report_.scene["recut"];
  if (root_)
    std::printf(
        "  measured recut after iteration 1: time max / mean %.3f, predicted %.3f after; %.1f %% "
        "of the colours moved (%s), %.3f s\n",
        before, after, 100.0 * colors / std::max(1.0, double(host_.colors())),
        human_bytes(bytes).c_str(), seconds);
}

// Every rank's work, counted (the same on any machine, so the balance of a 16-rank run shows on
// 2 cores): per_rank, max and mean of each counter into the summary's scene.work and the
// timings file's parameters, max / mean on stdout. The mirror trace's rays and BVH nodes are
// those of the ownership it ran on; the rest are per iteration, on the final ownership: colour
// entries, hits needing a viewpoint lookup, colour reads (all, of view-dependent vertices, of
// remote ones) and the modelled iteration cost, entries + kLookupHitCost x lookups.
void BakeRun::report_work() {
  const std::vector<std::pair<const char*, double>> mine = {
      {"items", double(my_items_)},
      {"trace_rays", double(traced_.rays)},
      {"trace_nodes", double(traced_.nodes)},
      {"lookups", double(reads_.lookups)},
      {"reads", double(reads_.reads)},
      {"view_dependent_reads", double(reads_.view_reads)},
      {"remote_reads", double(reads_.remote_reads)},
      {"moved_hits", double(moved_hits_)},
      {"iteration_cost", double(my_items_) + kLookupHitCost * double(reads_.lookups)}};
  std::vector<double> values;
  for (const auto& m : mine) values.push_back(m.second);
  const std::vector<std::vector<double>> field = gather_fields(comm_, values);
  const std::size_t ranks = static_cast<std::size_t>(comm_.size());
  nlohmann::json work;
  std::string line;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const std::vector<double>& per_rank = field[k];
    const double max = *std::max_element(per_rank.begin(), per_rank.end());
    double mean = 0;
    for (double x : per_rank) mean += x / double(ranks);
    const double ratio = mean > 0 ? max / mean : 1.0;
    work[mine[k].first] = {
        {"per_rank", per_rank}, {"max", max}, {"mean", mean}, {"max_over_mean", ratio}};
    char buf[80];
    if (std::string(mine[k].first) == "moved_hits")  // a fraction of all entries, not a balance
      std::snprintf(buf, sizeof buf, ", traced hits moved %.1f %%",
                    100.0 * mean / std::max(1.0, work["items"]["mean"].get<double>()));
    else
      std::snprintf(buf, sizeof buf, "%s%s %.3f", k ? ", " : "", mine[k].first, ratio);
    line += buf;
  }
  report_.scene["work"] = work;
  params_["work"] = work;
  if (root_) std::printf("  work per rank, max / mean: %s\n", line.c_str());
}

// The map's size and traffic per rank, into the summary and on stdout: every rank's figures in
// one collective (integers below 2^53, so the sums are exact in any order).
void BakeRun::report_map_plan() {
  // Per rank: the colours it holds (its map, double-buffered, and its halo, held once), its halo
  // (received) and the entries it sends (both 12 bytes a colour in the first exchange), the
  // vertex ranges it owns (several where the colour cap and the cost need them), its mirror
  // reads and the remote ones among them.
  enum Field { kLocal, kHalo, kSent, kRanges, kReads, kRemote, kFields };
  std::vector<double> mine(kFields);
  // With the node's one map a rank holds its own vertices' part of it (and reads the rest there).
  mine[kLocal] = static_cast<double>((node_map_ ? my_items_ : layout_.colors()) +
                                     layout_.halo_colors);
  mine[kHalo] = static_cast<double>(layout_.halo_colors);
  mine[kSent] = static_cast<double>(exchange_ ? exchange_->send_colors() : 0);
  mine[kRanges] = static_cast<double>(my_ranges_.size());
  mine[kReads] = static_cast<double>(reads_.reads);
  mine[kRemote] = static_cast<double>(reads_.remote_reads);
  const std::vector<std::vector<double>> per_rank = gather_fields(comm_, mine);
  const auto sum = [](const std::vector<double>& x) {
    double t = 0;
    for (const double e : x) t += e;
    return t;
  };
  const auto max = [](const std::vector<double>& x) {
    return *std::max_element(x.begin(), x.end());
  };
  const double max_local = max(per_rank[kLocal]), sum_local = sum(per_rank[kLocal]);
  const double max_halo = max(per_rank[kHalo]);
  const double reads = sum(per_rank[kReads]), remote = sum(per_rank[kRemote]);
  const double bytes = sum(per_rank[kSent]) * sizeof(Vec3f);
  const std::vector<double>& halo_per_rank = per_rank[kHalo];
  const std::vector<double>& send_per_rank = per_rank[kSent];
  const std::vector<double>& ranges_per_rank = per_rank[kRanges];
  report_.scene["map"] = {{"halo", node_holds_all()        ? "node"
                                   : halo_ == Halo::kAll   ? "all"
                                   : halo_ == Halo::kOwned ? "owned"
                                                           : "traced"},
                          {"node_map", node_map_ != nullptr},
                          {"local_colors_max", max_local},
                          {"local_colors_mean", sum_local / comm_.size()},
                          {"halo_colors_max", max_halo},
                          {"halo_colors_per_rank", halo_per_rank},
                          {"send_colors_per_rank", send_per_rank},
                          {"ranges_per_rank", ranges_per_rank},
                          {"mirror_reads", reads},
                          {"remote_read_fraction", reads > 0 ? remote / reads : 0.0},
                          {"exchange_bytes_per_iteration", bytes},
                          {"exchange_buffers", comm_.size() == 1 || !exchange_ ? "none"
                                               : exchange_->direct() ? "direct"
                                                                     : "host-staged"}};
  params_["map"] = report_.scene["map"];
  if (root_)
    std::printf(
        "  map per rank: %.0f colours max (%.1f %% of the whole map; halo %.0f max), %.3g %% of "
        "mirror reads remote, %s exchanged per iteration%s\n",
        max_local, 100.0 * max_local / std::max<double>(1.0, double(host_.colors())), max_halo,
        reads > 0 ? 100.0 * remote / reads : 0.0, human_bytes(bytes).c_str(),
        !node_map_         ? ""
        : node_holds_all() ? " (one map per node, read in place)"
                           : " (one map per node; other nodes' colours through the halo)");
}

// One flag per entry of `remote` (remote_layout): the remote colours this rank's traced lookups
// read.
std::vector<char> BakeRun::read_items(const MapLayout& remote) const {
  Kokkos::View<char*, MemSpace> items("rtmini::bake::read_items", remote.colors());
  chef_->set_map_offset(remote.device);
  for (std::size_t k = 0; k < my_ranges_.size(); ++k)
    chef_->mark_read_items(my_ranges_[k].begin, my_ranges_[k].end, my_cache_offset_[k], held_,
                           items);
  std::vector<char> read;
  compat::download(items, read);
  return read;
}

// Base colours of this rank's vertices (needed by every iteration, also after a restart).
void BakeRun::bake_base() {
  timer_.start("base");
  if (c_.trace_reference && comm_.size() > 1) {
    // The traced recursion reads the base colour of any vertex a mirror ray reaches: each
    // rank computes all of them (the same counter-based samples, so the same colours).
    totals_.rays += chef_->bake_base(0, host_.vertices());
  } else {
    for (const VertexRange& r : my_ranges_) totals_.rays += chef_->bake_base(r.begin, r.end);
  }
  timer_.stop();
}

// Resumes from the checkpoint: its global map, cut to this rank's layout.
void BakeRun::restart() {
  if (c_.restart.empty()) return;
  to_storage_order(chef_->view_order(), host_.color_offset, restart_cp_.colors);
  first_ = restart_cp_.iteration + 1;
  restart_local_map();
  if (root_)
    std::printf("  restart: iteration %d of %s done, resuming at %d\n", restart_cp_.iteration,
                c_.restart.c_str(), first_);
}

// The checkpoint's map cut to this rank's layout: its map and its halo. In the node's one map a
// rank fills its own vertices' entries, its node's other ranks theirs.
void BakeRun::restart_local_map() {
  std::vector<Vec3f> local = localise_map(host_, layout_, restart_cp_.colors);
  std::vector<Vec3f>().swap(restart_cp_.colors);
  const std::size_t map = static_cast<std::size_t>(layout_.colors());
  if (node_map_) {
    for (const VertexRange& r : my_ranges_) {
      const std::int64_t a = layout_.offset[r.begin], b = layout_.offset[r.end];
      Kokkos::deep_copy(Kokkos::subview(prev_, std::make_pair(a, b)),
                        compat::host_view(local.data() + a, static_cast<std::size_t>(b - a)));
    }
  } else {
    Kokkos::deep_copy(prev_, compat::host_view(local.data(), map));
  }
  if (exchange_ && layout_.halo_colors > 0)
    Kokkos::deep_copy(exchange_->halo(), compat::host_view(local.data() + map, local.size() - map));
  if (node_map_) node_map_->barrier(comm_);
}

// Where iteration `it` finds its mirror hits. The first iteration after the start traces them
// (or reads the hits traced up front, the same bits); later ones read the float cache.
HitCacheMode BakeRun::hit_mode(int it) const {
  if (it == 0) return HitCacheMode::kOff;
  if (chef_->has_traced_hits())
    return it >= 2 && it > first_ && chef_->caches_hits() ? HitCacheMode::kUse
                                                          : HitCacheMode::kTraced;
  const bool cache_filled = it >= 2 && it > first_;
  return cache_filled       ? HitCacheMode::kUse
         : it < iterations_ ? HitCacheMode::kFill
                            : HitCacheMode::kOff;
}

// The dispatches of an iteration. With a progress line each of this rank's ranges is cut
// into pieces of at most about 1/kProgressPieces of its colour entries and of its vertices
// (whole vertices), so the line moves during an iteration (one range per rank, the default,
// would draw once per iteration, every 12 s on cornell_big_raw at N = 4000), and IterationEta,
// which compares iterations piece by piece, sees the same pieces every iteration. Both bounds,
// because the work is both per colour (mirror rays) and per vertex (gather rays): cut by
// colours alone, one piece held every diffuse vertex and 80 % of an iteration's time. Without
// a line: one dispatch per range. The cut changes no result: every colour entry is computed
// alone from the previous map, and a piece's hit-cache slots are its range's, offset by the
// entries before it.
std::vector<TracePiece> BakeRun::trace_pieces(bool progress) const {
  constexpr std::int64_t kProgressPieces = 64;
  const std::int64_t piece_items = std::max<std::int64_t>(1, my_items_ / kProgressPieces);
  const std::int64_t piece_vertices = std::max<std::int64_t>(1, my_vertices_ / kProgressPieces);
  std::vector<TracePiece> pieces;
  for (std::size_t k = 0; k < my_ranges_.size(); ++k) {
    const VertexRange r = my_ranges_[k];
    const std::int64_t first_item = host_.color_offset[r.begin];
    std::int64_t begin = r.begin;
    while (begin < r.end) {
      std::int64_t end = r.end;
      if (progress) {
        end = begin + 1;
        while (end < r.end && end - begin < piece_vertices &&
               host_.color_offset[end] - host_.color_offset[begin] < piece_items)
          ++end;
      }
      pieces.push_back({begin, end, my_cache_offset_[k] + host_.color_offset[begin] - first_item,
                        static_cast<std::int64_t>(k)});
      begin = end;
    }
  }
  return pieces;
}

// This rank's dispatches of iteration `it` into `out`; returns rays traced.
std::int64_t BakeRun::trace(int it, Kokkos::View<Vec3f*, MemSpace> out) {
  const HitCacheMode mode = hit_mode(it);
  std::int64_t rays = 0, entries_done = 0;
  // The pieces of a progress line run in a spread order (parallel/spread_order.hpp), the same
  // in every iteration: the pieces done so far are then a fair sample of the whole iteration,
  // the gather-heavy diffuse ones and the mirror-heavy ones alike, so an iteration of a mode not
  // measured yet is extrapolated linearly from them (in storage order its diffuse pieces came
  // first and that extrapolation was +100 % off). Any order gives the same bytes.
  const SpreadOrder spread(static_cast<std::int64_t>(pieces_.size()), 1);
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(pieces_.size()); ++i) {
    const TracePiece& r = pieces_[static_cast<std::size_t>(spread.item(i))];
    const double cs = timer_.now();
    const std::int64_t crays =
        c_.trace_reference
            ? chef_->trace_reference(r.begin, r.end, out)
            : chef_->bake_iteration(it, r.begin, r.end, r.cache_offset, mode, prev_, out);
    Kokkos::fence();
    const std::int64_t items = host_.color_offset[r.end] - host_.color_offset[r.begin];
    chunks_.push_back({comm_.rank(), it, items, crays, cs, timer_.now()});
    rays += crays;
    totals_.work += items;
    entries_done += items;
    eta_.batch_done(timer_.now() - cs);
    if (progress_line_->due()) report_progress(it, entries_done);
  }
  // The traced hits have served their one iteration once the float cache takes over.
  // (A measured recut moves them first: recut_by_measured_time releases them.)
  if (mode == HitCacheMode::kTraced && chef_->caches_hits() && it < iterations_ &&
      !recuts_by_measured_time())
    chef_->release_traced_hits();
  return rays;
}

// Whether iteration `it` shares its pieces between the ranks of a node (--node-sharing), and the
// publication of this rank's part where it starts or changes (the first iteration's part is
// published again once its halo is planned, and when the float cache replaces the traced hits).
// Every rank decides together (a rank that owns no vertex has no hits to tell its mode by, and
// then nobody shares).
bool BakeRun::shares_iteration(int it) {
  if (!share_ || it == 0) return false;
  const HitCacheMode mode = hit_mode(it);
  if (share_->published() && mode == shared_mode_ && !share_stale_) return true;
  // Mirror iterations whose hits are in place (traced, or the float cache): not one that fills
  // the cache as it goes (without traced hits), whose records appear only as it runs.
  const bool ready = (mode == HitCacheMode::kUse || mode == HitCacheMode::kTraced) && my_items_ > 0;
  if (comm_.min(ready ? 1.0 : 0.0) < 0.5) return false;
  start_node_sharing(it);
  return true;
}

// The node's window, where the maps, the halo and the first iteration's read flags are made
// (collective; once, when the layout of this rank's map is known). Not for the traced
// reference or a run without mirror iterations to share.
void BakeRun::make_node_share() {
  if (!c_.share_work || comm_.size() == 1 || c_.trace_reference || iterations_ < 1 ||
      halo_ == Halo::kOwned)
    return;
  // The node's one map: the map layout_ has just been made of the node's vertices.
  if (uses_node_map()) node_map_ = std::make_unique<NodeMap>(comm_, layout_.colors());
  share_ = std::make_unique<NodeShare>(comm_, node_share_room(), node_hits_.get(), node_map_.get());
}

// This rank's part is published in its segment of the node's window (the maps and the halo are
// there already; the hits and base colours move in, and the rank's own copies are freed; the
// small tables the readers need are copied), and the rank works on the shared part from now on.
void BakeRun::start_node_sharing(int it) {
  OwnerPart mine = chef_->own_part(hit_mode(it));
  mine.prev = prev_;
  mine.next = next_;
  if (exchange_) mine.sparse.halo = exchange_->halo();  // none before the fused plan
  const bool first = !share_->published();
  share_->publish(comm_, mine, pieces_, it, iterations_);
  shared_mode_ = hit_mode(it);
  share_stale_ = false;
  chef_->adopt_part(share_->part(share_->node_rank(), it));
  if (!first) return;
  share_from_ = it;
  if (root_)
    std::printf(
        "  node sharing from iteration %d: %d ranks on this node, %zu pieces each, "
        "%.1f MiB shared by this rank%s\n",
        it, share_->node_size(), pieces_.size(),
        static_cast<double>(share_->segment_bytes()) / (1 << 20),
        node_map_ ? (", the node's map " + human_bytes(2.0 * double(node_map_->colors()) *
                                                          sizeof(Vec3f)))
                        .c_str()
                  : "");
}

// Iteration `it` with the node's ranks sharing work: this rank claims its own pieces first, then
// the unclaimed pieces of the others, from the next rank on (so that the ranks that finish early
// spread over the late ones). A stolen piece reads its owner's previous map and halo and writes
// its owner's next map: the same colours, bit for bit, as the owner would have written.
std::int64_t BakeRun::trace_shared(int it) {
  const HitCacheMode mode = hit_mode(it);
  share_->open_iteration(comm_);
  std::int64_t rays = 0, entries_done = 0;
  const int me = share_->node_rank(), ranks = share_->node_size();
  // Test hook: the node's first rank starts late, so that the others take its pieces for certain.
  if (me == 0 && c_.share_test_delay > 0)
    std::this_thread::sleep_for(std::chrono::duration<double>(c_.share_test_delay));
  for (int k = 0; k < ranks; ++k) {
    const int owner = (me + k) % ranks;
    const OwnerPart part = k == 0 ? OwnerPart{} : share_->part(owner, it);
    std::int64_t first = 0, end = 0;
    while (share_->claim(owner, it, first, end)) {
      while (first < end) {
        std::int64_t pieces = 0;
        const TracePiece r = share_->next_run(owner, first, end, pieces);
        const double cs = timer_.now();
        const std::int64_t crays =
            k == 0 ? chef_->bake_iteration(it, r.begin, r.end, r.cache_offset, mode, prev_, next_)
                   : chef_->bake_iteration_of(part, it, r.begin, r.end, r.cache_offset, mode);
        Kokkos::fence();
        const double seconds = timer_.now() - cs;
        const std::int64_t items = host_.color_offset[r.end] - host_.color_offset[r.begin];
        chunks_.push_back({comm_.rank(), it, items, crays, cs, cs + seconds});
        rays += crays;
        totals_.work += items;
        if (k > 0) {
          stolen_items_ += items;
          stolen_pieces_ += pieces;
          continue;
        }
        entries_done += items;
        // The ETA compares iterations piece by piece: a merged run counts as its pieces.
        for (std::int64_t p = 0; p < pieces; ++p)
          eta_.batch_done(seconds / static_cast<double>(pieces));
        if (progress_line_->due()) report_progress(it, entries_done);
      }
    }
  }
  share_->close_iteration(comm_);
  // As in trace(): the traced hits have served their one iteration once the float cache takes
  // over (the same records when Real is float: the window's).
  if (mode == HitCacheMode::kTraced && chef_->caches_hits() && it < iterations_)
    chef_->release_traced_hits();
  return rays;
}

// What the node sharing moved: the scene's bytes, the colour entries each rank computed for
// other ranks.
void BakeRun::report_node_sharing() {
  if (!c_.share_work && !c_.share_scene) return;
  nlohmann::json s;
  s["ranks_per_node"] = comm_.node_size();
  s["scene_bytes_per_node"] = node_scene_ ? node_scene_->bytes() : 0;
  if (c_.share_work) {
    s["from_iteration"] = share_from_;
    s["pieces_per_rank"] =
        comm_.allgatherv(std::vector<double>{static_cast<double>(pieces_.size())});
    s["stolen_items_per_rank"] =
        comm_.allgatherv(std::vector<double>{static_cast<double>(stolen_items_)});
    s["stolen_pieces_per_rank"] =
        comm_.allgatherv(std::vector<double>{static_cast<double>(stolen_pieces_)});
    s["trace_shared"] = node_hits_ != nullptr;
    s["trace_stolen_items_per_rank"] =
        comm_.allgatherv(std::vector<double>{static_cast<double>(trace_stolen_items_)});
    s["segment_bytes_per_rank"] = comm_.allgatherv(
        std::vector<double>{share_ ? static_cast<double>(share_->segment_bytes()) : 0.0});
    // The rank's node's one map, both buffers (not in the segments); 0: per-rank maps.
    s["node_map_bytes_per_rank"] = comm_.allgatherv(std::vector<double>{
        node_map_ ? 2.0 * static_cast<double>(node_map_->colors()) * sizeof(Vec3f) : 0.0});
  }
  report_.scene["node_shared_work"] = s;
  params_["node_shared_work"] = s;
}

// The progress line during iteration `it`: entries done, ETA from the measured batch costs of
// the last iteration of each hit-cache mode (iteration_eta.hpp).
void BakeRun::report_progress(int it, std::int64_t entries_done) {
  std::vector<int> upcoming;
  for (int j = it + 1; j <= iterations_; ++j) upcoming.push_back(static_cast<int>(hit_mode(j)));
  const double left = eta_.remaining(static_cast<int>(hit_mode(it)), pieces_.size(), upcoming);
  const double spent = timer_.now() - iterate_start_;
  // No honest estimate yet (left < 0): the line shows the entries done and "ETA ?".
  progress_line_->update(static_cast<double>((it - first_) * my_items_ + entries_done),
                         static_cast<double>((iterations_ - first_ + 1) * my_items_),
                         left < 0 ? 0.0 : spent, spent + std::max(0.0, left));
}

// The new map becomes the previous one; its halo entries come from their owners. One rank
// holds everything: the map never leaves the device (on a GPU two host copies would cost more
// than the iteration). After the last iteration nothing reads another rank's colours (the
// output, the hash, checkpoints and the comparison take each rank's own), so nothing moves.
void BakeRun::exchange(int it, IterationRecord& rec) {
  const double t0 = timer_.now();
  if (pending_.active && it >= 1) {
    if (recuts_by_measured_time()) recut_by_measured_time(rec.trace);
    finish_fused_plan(it);
  }
  std::swap(prev_, next_);
  // The node's map: every rank's colours of this iteration are seen by all before the next.
  if (node_map_) node_map_->barrier(comm_);
  rec.allgather_bytes = exchange_ && it < iterations_ ? exchange_->run(comm_, prev_, next_) : 0;
  rec.allgather = timer_.now() - t0;
}

// The whole map on the root (every rank takes part): owned colours gathered in vertex order, in
// prev_'s order of each vertex's colours (storage order until release_iteration_buffers).
std::vector<Vec3f> BakeRun::global_map() {
  const auto local = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), prev_);
  return gather_global_map(comm_, host_, layout_, local.data(), owner_);
}

void BakeRun::checkpoint(int it) {
  if (c_.checkpoint.empty()) return;
  std::vector<Vec3f> colors = global_map();
  if (root_) {
    Checkpoint cp;
    cp.iteration = it;
    cp.parameter_hash = phash_;
    cp.inputs = format_input_hashes(inputs_);
    cp.vertices = host_.vertices();
    cp.viewpoints = c_.viewpoints;
    to_viewpoint_order(chef_->view_order(), host_.color_offset, colors);
    cp.colors = std::move(colors);
    write_checkpoint(c_.checkpoint, cp);
  }
  comm_.barrier();
}

// Stop early with a valid checkpoint: test hook, signal, or a time limit the next iteration
// (estimated from this one) would overrun. All ranks decide together.
bool BakeRun::stop_after(int it, double t0) {
  const double elapsed = timer_.now(), last = elapsed - t0;
  const bool over_time = c_.time_limit_minutes > 0 && elapsed + last > c_.time_limit_minutes * 60.0;
  const bool stop =
      comm_.max((c_.stop_after_iteration == it || stop_requested() || over_time) ? 1.0 : 0.0) > 0.5;
  if (stop && root_)
    std::fprintf(stderr, "bake: stopping after iteration %d (%s); %s\n", it,
                 over_time ? "time limit" : "stop requested",
                 c_.checkpoint.empty() ? "no --checkpoint given, progress is lost"
                                       : ("restart with --restart " + c_.checkpoint).c_str());
  return stop;
}

int BakeRun::iterate() {
  const bool progress = c_.progress || ::isatty(2);
  progress_line_ = std::make_unique<ProgressLine>("bake", "colours", progress && root_);
  // Shared work needs pieces to share: the progress line's cut.
  pieces_ = trace_pieces(progress_line_->enabled() || c_.share_work);
  timer_.start("iterate");
  iterate_start_ = timer_.now();
  for (int it = first_; it <= iterations_; ++it) {
    IterationRecord rec;
    const double t0 = timer_.now();
    totals_.rays += shares_iteration(it) ? trace_shared(it) : trace(it, next_);
    const double t1 = timer_.now();
    if (pending_.active && it >= 1) mark_rss("iteration " + std::to_string(it) + " trace");
    rec.trace = t1 - t0;
    eta_.iteration_done(static_cast<int>(hit_mode(it)));
    totals_.completion = t1;
    comm_.barrier();
    totals_.idle += timer_.now() - t1;
    exchange(it, rec);
    const double t2 = timer_.now();
    checkpoint(it);
    rec.write = timer_.now() - t2;
    mark_rss("iteration " + std::to_string(it));
    iter_records_.push_back(rec);
    if (progress && root_)
      std::fprintf(stderr, "bake: iteration %d/%d done (%.3f s trace, %.3f s exchange)\n", it,
                   iterations_, rec.trace, rec.allgather);
    if (it < iterations_ && stop_after(it, t0)) {
      timer_.stop();
      report_stopped(it);
      return kExitCheckpointed;
    }
  }
  timer_.stop();
  progress_line_->finish(static_cast<double>(totals_.work), static_cast<double>(totals_.work));
  return kExitOk;
}

// A stopped run's last stdout line is still the contract's figure-of-merit line: the
// iterations a --restart has left to do.
void BakeRun::report_stopped(int it) {
  report_.fom_name = "iterations_missing";
  report_.fom_unit = "iterations";
  report_.fom_value = static_cast<double>(iterations_ - it);
  report_.finish(comm_, c_.summary);
}

// After the last iteration only this rank's own colours (prev_) are read, in viewpoint order
// (view_order.hpp), which the other map buffer takes: then it goes, with the halo, the
// exchange's buffers and the hit records, before the output is written (at the output they
// were the run's peak, with the output's own buffers on top).
void BakeRun::release_iteration_buffers() {
  report_exchange();
  report_node_sharing();
  layout_.sparse = SparseColors{};
  chef_->set_map_offset(layout_.device);
  for (const VertexRange& r : my_ranges_) chef_->to_viewpoint_order(r.begin, r.end, prev_, next_);
  std::swap(prev_, next_);
  next_ = Kokkos::View<Vec3f*, MemSpace>();
  chef_->release_hits();
  if (exchange_) exchange_->release();
}

// Every rank writes its own vertices (collective MPI-IO), in either form.
void BakeRun::write() {
  timer_.start("write");
  // A hemisphere map stores the first N/2 points, in each vertex's frame (the file says so).
  std::vector<Vec3f> dirs(static_cast<std::size_t>(c_.stored_viewpoints()));
  for (int i = 0; i < c_.stored_viewpoints(); ++i)
    dirs[i] = Vec3f(fibonacci_point(i, c_.viewpoints));
  // On a host backend the map itself, else a host copy.
  const auto map = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), prev_);
  BakedMap baked{&mesh_, map.data(), &layout_.offset, &dirs};
  baked.hemisphere = c_.hemisphere();
  written_ = write_baked_map(comm_, c_.output, baked, my_ranges_);
  timer_.stop();
  if (!iter_records_.empty()) iter_records_.back().write += written_.seconds;
}

// The errors against --reference, on the root with the whole map.
void BakeRun::compare() {
  timer_.start("compare");
  if (!c_.reference.empty()) {
    const std::vector<Vec3f> global = global_map();
    if (root_) {
      const auto ref = compat::upload<MemSpace>("rtmini::bake::reference", reference_.colors);
      const auto map = compat::upload<MemSpace>("rtmini::bake::global_map", global);
      const MapErrors e = errors_from_sums(chef_->lookup_errors(map, ref, reference_.viewpoints));
      report_.errors = error_json(e);
      report_.errors["reference"] = c_.reference;
      report_.errors["reference_viewpoints"] = reference_.viewpoints;
      report_.errors["lookup"] = to_string(c_.lookup);
      print_errors("map read along the reference's directions", e);
      // A hemisphere map's viewpoints lie in each vertex's frame: none is a reference direction.
      if (reference_.viewpoints == c_.viewpoints && !c_.hemisphere()) {
        const MapErrors st = compare_stored(global, host_.color_offset, reference_);
        report_.errors["stored"] = error_json(st);
        print_errors("stored colours, viewpoint by viewpoint", st);
      }
    }
  }
  timer_.stop();
}

// After the first exchange only changed colours move: the fraction that did.
void BakeRun::report_exchange() {
  if (exchange_ && comm_.size() > 1) {
    const double offered = static_cast<double>(comm_.sum(exchange_->offered_colors()));
    report_.scene["map"]["exchange_changed_fraction"] =
        offered > 0 ? static_cast<double>(comm_.sum(exchange_->changed_colors())) / offered : 1.0;
    params_["map"] = report_.scene["map"];
  }
}

void BakeRun::report_results() {
  const std::uint64_t hash = comm_.sum_wrap(
      map_hash(layout_.device, prev_, batches_, comm_.rank(), c_.stored_viewpoints()));
  const double total_rays = static_cast<double>(comm_.sum(totals_.rays));
  const double bake_time = comm_.max(timer_.total("base") + timer_.total("map") +
                                     timer_.total("halo") + timer_.total("iterate"));
  const double baked_colors = static_cast<double>(host_.vertices()) * c_.stored_viewpoints() *
                              static_cast<double>(iterations_ - first_ + 1);
  report_.fom_name = "baked viewpoint colours";
  report_.fom_unit = "M/s";
  report_.fom_value = bake_time > 0 ? baked_colors / bake_time * 1e-6 : 0.0;
  report_.verification_hash = hash;
  report_.scene["rays_traced"] = total_rays;
  report_.scene["rays_per_second"] = bake_time > 0 ? total_rays / bake_time : 0.0;
  report_.scene["output_bytes"] = written_.file_bytes;
  report_.scene["peak_rss_bytes_per_rank"] =
      comm_.allgatherv(std::vector<double>{peak_rss_bytes()});
  // What a rank holds besides the map (the replicated scene, its BVH, the runtimes): the part
  // of the peak that does not fall with the ranks.
  report_.scene["scene_rss_bytes_per_rank"] =
      comm_.allgatherv(std::vector<double>{scene_rss_bytes_});
  // Every rank marks the same steps: their peaks and current RSS in one collective.
  std::vector<double> marks;
  for (const RssMark& m : rss_marks_) {
    marks.push_back(m.peak);
    marks.push_back(m.now.total);
    marks.push_back(m.now.shmem);
    marks.push_back(m.now.huge);
    marks.push_back(m.now.pss);
  }
  report_.scene["transparent_huge_pages"] = transparent_huge_page_mode();
  constexpr std::size_t kPerMark = 5;
  const std::vector<std::vector<double>> per_rank = gather_fields(comm_, marks);
  for (std::size_t i = 0; i < rss_marks_.size(); ++i) {
    const std::string& step = rss_marks_[i].step;
    report_.scene["peak_rss_after_bytes_per_rank"][step] = per_rank[kPerMark * i];
    report_.scene["rss_after_bytes_per_rank"][step] = per_rank[kPerMark * i + 1];
    report_.scene["rss_shmem_after_bytes_per_rank"][step] = per_rank[kPerMark * i + 2];
    report_.scene["rss_huge_after_bytes_per_rank"][step] = per_rank[kPerMark * i + 3];
    report_.scene["pss_after_bytes_per_rank"][step] = per_rank[kPerMark * i + 4];
  }
  // The largest PSS a rank had after any step: its share of the node's memory (ResidentNow).
  std::vector<double> max_pss(static_cast<std::size_t>(comm_.size()), 0.0);
  for (std::size_t i = 0; i < rss_marks_.size(); ++i)
    for (std::size_t r = 0; r < max_pss.size(); ++r)
      max_pss[r] = std::max(max_pss[r], per_rank[kPerMark * i + 4][r]);
  report_.scene["max_pss_after_step_bytes_per_rank"] = max_pss;
  report_resident_buffers();
  if (!c_.timings.empty())
    write_timings_file(comm_, c_, timer_,
                       {"read", "setup", "base", "map", "halo", "iterate", "write"}, iter_records_,
                       chunks_, totals_, params_.dump());
  if (root_)
    std::printf(
        "  bake time %.4f s (base + iterations), %.4g rays (%.4g Mrays/s), write %.4f s, "
        "%s written\n",
        bake_time, total_rays, bake_time > 0 ? total_rays / bake_time * 1e-6 : 0.0,
        written_.seconds, human_bytes(double(written_.file_bytes)).c_str());
  report_.finish(comm_, c_.summary);
}

// Large buffers go back to the operating system when freed. glibc raises its mmap threshold to
// the size of each mmap'd block freed (up to 32 MiB), after which blocks up to that size come
// from the heap, where freed memory stays resident: the exchange plan's request lists (8 bytes
// per halo and sent colour, freed before the halo is allocated) then stayed in the largest 16 x 1
// rank's peak RSS, 0.104 against 0.096 GiB with the threshold fixed (results/bake/distributed.md,
// thirteenth round). Fixed at glibc's default of 128 KiB (mallopt turns the adjustment off).
namespace {
void return_freed_buffers() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}
}  // namespace

int BakeRun::run() {
  report_.app = "bake";
  return_freed_buffers();
  install_stop_handlers();
  read();
  timer_.start("setup");
  plan();
  check_outputs();
  check_memory();
  setup();
  timer_.stop();
  mark_rss("setup");
  trace_map();
  mark_rss("map");
  report_work();
  bake_base();
  plan_map();
  restart();
  mark_rss("halo");
  if (const int code = iterate(); code != kExitOk) return code;
  release_iteration_buffers();
  write();
  mark_rss("write");
  compare();
  report_results();
  return kExitOk;
}

}  // namespace

int run_bake(Communicator& comm, const BakeConfig& c) { return BakeRun(comm, c).run(); }

}  // namespace rtmini::bake
