#include "kitchen.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "bakeshop_mpi_writer.hpp"
#include "checkpoint.hpp"
#include "chef.hpp"
#include "iteration_eta.hpp"
#include "map_errors.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/timings.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/stop_request.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini::bake {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

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

// Everything that changes the colours: the input's bytes and the physics parameters (not K,
// so a finished run can be extended; not the lookup or BVH kind, which give the same result).
std::string parameter_hash(const BakeConfig& c) {
  std::ifstream in(c.input, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ostringstream p;
  p << "bake-map-v1 N=" << c.viewpoints << " S=" << c.shadow_samples << " M=" << c.gather_rays
    << " seed=" << c.seed << " bg=" << c.background.x << "," << c.background.y << ","
    << c.background.z << " real=" << sizeof(Real) << (c.trace_reference ? " traced" : "");
  const std::string params = p.str();
  return hash_hex(fnv1a(params.data(), params.size(), fnv1a(bytes.data(), bytes.size())));
}

MemoryEstimate estimate_memory(const Mesh& mesh, const BakeSceneHost& s, std::int64_t my_items,
                               std::int64_t my_vertices, int iterations, const BakeConfig& c,
                               bool root) {
  MemoryEstimate m;
  const std::int64_t nv = s.vertices(), nt = static_cast<std::int64_t>(mesh.triangle_count());
  const std::int64_t vec = sizeof(Vec3), col = sizeof(Vec3f);
  // Mesh SoA + BVH (about 2 nodes per leaf triangle group, the triangles again in leaf order).
  m.scene = nv * (vec * 6 + 8) + nt * (3 * vec * 2 + 4 * 6) + nt * sizeof(bvh::BvhNode) +
            static_cast<std::int64_t>(c.viewpoints) * (vec * 2 + 8);
  m.maps = 2 * s.colors() * col;                                  // prev + next on the device
  m.host = 2 * s.colors() * col + my_items * col;                 // map, gathered, packed
  m.host += my_vertices * c.viewpoints * 60;                      // formatted output text
  if (root && !c.checkpoint.empty()) m.host += s.colors() * col;  // checkpoint copy
  if (!c.reference.empty()) m.host += nv * c.viewpoints * col;    // the reference's colours
  if (c.cache_hits && iterations > 1) m.hit_cache = Chef::hit_cache_bytes(my_items);
  return m;
}

KOKKOS_INLINE_FUNCTION std::int64_t quantise(float x) {
  return static_cast<std::int64_t>(math::floor(double(x) * 65536.0 + 0.5));
}

// Order-independent hash over (vertex, viewpoint, quantised colour) of this rank's vertices.
// Copies a device map into the host map (sizes match).
void download(Kokkos::View<const Vec3f*, MemSpace> from, std::vector<Vec3f>& to) {
  Kokkos::deep_copy(
      Kokkos::View<Vec3f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(to.data(),
                                                                                       to.size()),
      from);
}

std::uint64_t map_hash(const BakeSceneDevice& s, Kokkos::View<const Vec3f*, MemSpace> map,
                       const std::vector<Batch>& batches, int rank, int n) {
  std::uint64_t total = 0;
  auto off = s.color_offset;
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
  std::int64_t allgather_bytes = 0;
};

struct ChunkRecord {
  std::int64_t rank, iteration, work_units, rays;
  double start, end;
};

void write_timings_file(const Communicator& comm, const BakeConfig& c, const PhaseTimer& timer,
                        const std::vector<std::string>& phase_names,
                        const std::vector<IterationRecord>& iters,
                        const std::vector<ChunkRecord>& chunks, double completion, double idle,
                        std::int64_t rays, std::int64_t work, const std::string& params_json) {
  const int ranks = comm.size();
  std::vector<double> my_start, my_end;
  for (const auto& name : phase_names) {
    double s = -1, e = -1;
    for (const auto& p : timer.phases()) {
      if (p.first != name) continue;
      if (s < 0) s = p.second.first;
      e = p.second.second;
    }
    my_start.push_back(s);
    my_end.push_back(e);
  }
  std::vector<double> it_trace, it_gather, it_write;
  std::vector<std::int64_t> it_bytes;
  for (const auto& r : iters) {
    it_trace.push_back(r.trace);
    it_gather.push_back(r.allgather);
    it_write.push_back(r.write);
    it_bytes.push_back(r.allgather_bytes);
  }
  std::vector<double> chunk_times;
  std::vector<std::int64_t> chunk_ints;
  for (const auto& ch : chunks) {
    chunk_times.push_back(ch.start);
    chunk_times.push_back(ch.end);
    chunk_ints.insert(chunk_ints.end(), {ch.rank, ch.iteration, ch.work_units, ch.rays});
  }
  std::vector<double> rank_d{completion, idle};
  std::vector<std::int64_t> rank_i{comm.messages_sent(), comm.bytes_sent(), rays, work};
  const auto g_start = comm.gatherv(my_start), g_end = comm.gatherv(my_end);
  const auto g_trace = comm.gatherv(it_trace), g_gather = comm.gatherv(it_gather);
  const auto g_write = comm.gatherv(it_write);
  const auto g_bytes = comm.gatherv(it_bytes);
  const auto g_ct = comm.gatherv(chunk_times);
  const auto g_ci = comm.gatherv(chunk_ints);
  const auto g_rd = comm.gatherv(rank_d);
  const auto g_ri = comm.gatherv(rank_i);
  if (!comm.is_root()) return;
  TimingsData t;
  t.app = "bake";
  t.version = version_string();
  t.git_hash = git_hash();
  t.backend = compat::backend_name();
  t.strategy = to_string(c.balance);
  t.scene = c.input;
  t.parameters = params_json;
  t.ranks = ranks;
  t.threads = compat::concurrency();
  t.phase_names = phase_names;
  t.phase_start = g_start;
  t.phase_end = g_end;
  for (std::size_t i = 0; i + 1 < g_ct.size(); i += 2) {
    t.chunk_start.push_back(g_ct[i]);
    t.chunk_end.push_back(g_ct[i + 1]);
  }
  for (std::size_t i = 0; i + 3 < g_ci.size(); i += 4) {
    t.chunk_rank.push_back(g_ci[i]);
    t.chunk_iteration.push_back(g_ci[i + 1]);
    t.chunk_work_units.push_back(g_ci[i + 2]);
    t.chunk_rays.push_back(g_ci[i + 3]);
  }
  for (int r = 0; r < ranks; ++r) {
    t.rank_completion_time.push_back(g_rd[2 * r]);
    t.rank_idle_time.push_back(g_rd[2 * r + 1]);
    t.rank_messages_sent.push_back(g_ri[4 * r]);
    t.rank_bytes_sent.push_back(g_ri[4 * r + 1]);
    t.rank_rays.push_back(g_ri[4 * r + 2]);
    t.rank_work_units.push_back(g_ri[4 * r + 3]);
  }
  t.iterations = static_cast<int>(iters.size());
  t.iteration_trace_time = g_trace;
  t.iteration_allgather_time = g_gather;
  t.iteration_write_time = g_write;
  t.iteration_allgather_bytes = g_bytes;
  write_timings(c.timings, t);
}

}  // namespace

std::vector<Batch> make_batches(const BakeSceneHost& scene, int ranks, Balance balance,
                                std::int64_t batch_size) {
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
  // Cost balance: cut where the running cost passes the next multiple of total / count.
  const double total = static_cast<double>(scene.colors());
  std::int64_t begin = 0;
  for (std::int64_t b = 0; b < count && begin < nv; ++b) {
    std::int64_t end = nv;
    if (b + 1 < count) {
      const double target = total * static_cast<double>(b + 1) / static_cast<double>(count);
      end = begin + 1;
      while (end < nv && static_cast<double>(scene.color_offset[end]) < target) ++end;
    }
    out.push_back({begin, end, static_cast<int>(b % ranks)});
    begin = end;
  }
  return out;
}

int run_bake(Communicator& comm, const BakeConfig& c) {
  RunReport report;
  report.app = "bake";
  PhaseTimer& timer = report.timer;
  const bool root = comm.is_root();
  const bool progress = c.progress || ::isatty(2);
  install_stop_handlers();

  timer.start("read");
  const Mesh mesh = read_mesh(c.input);
  timer.stop();
  if (mesh.positions.empty() || mesh.faces.empty())
    throw InputError(c.input, 0, "the scene has no vertices or no faces");

  timer.start("setup");
  const BakeSceneHost host = prepare_bake_scene(mesh, c.viewpoints, c.all_view_dependent);
  const bool needs_iterations = host.reflective_vertices > 0 || c.gather_rays > 0;
  // The traced reference is one pass (it follows the K mirror bounces itself).
  const int iterations = needs_iterations && !c.trace_reference ? c.iterations : 0;
  const std::vector<Batch> batches = make_batches(host, comm.size(), c.balance, c.batch_size);
  std::vector<VertexRange> my_ranges;
  std::vector<std::int64_t> my_cache_offset;
  std::int64_t my_items = 0, my_vertices = 0;
  for (const Batch& b : batches) {
    if (b.rank != comm.rank()) continue;
    my_vertices += b.end - b.begin;
    my_ranges.push_back({b.begin, b.end});
    my_cache_offset.push_back(my_items);
    my_items += host.color_offset[b.end] - host.color_offset[b.begin];
  }
  const MemoryEstimate mem =
      estimate_memory(mesh, host, my_items, my_vertices, iterations, c, root);
  const double max_mem = comm.max(static_cast<double>(mem.total()));

  nlohmann::json params = {{"input", c.input},
                           {"output", c.output},
                           {"viewpoints", c.viewpoints},
                           {"iterations", c.iterations},
                           {"shadow_samples", c.shadow_samples},
                           {"gather_rays", c.gather_rays},
                           {"seed", c.seed},
                           {"lookup", to_string(c.lookup)},
                           {"balance", to_string(c.balance)},
                           {"batch_size", c.batch_size},
                           {"batches", batches.size()},
                           {"bvh", c.sah ? "sah" : "lbvh"},
                           {"background", {c.background.x, c.background.y, c.background.z}},
                           {"max_memory", c.max_memory},
                           {"time_limit_minutes", c.time_limit_minutes},
                           {"hit_cache", c.cache_hits},
                           {"all_view_dependent", c.all_view_dependent},
                           {"checkpoint", c.checkpoint},
                           {"restart", c.restart},
                           {"reference", c.reference},
                           {"trace_reference", c.trace_reference}};
  report.parameters = params;
  report.scene = {
      {"vertices", host.vertices()},          {"faces", mesh.faces.size()},
      {"triangles", mesh.triangle_count()},   {"reflective_vertices", host.reflective_vertices},
      {"emissive_faces", host.lights.size()}, {"colors", host.colors()}};
  if (root) {
    std::printf("%s\n", build_banner().c_str());
    std::printf("bake: view-dependent ray-trace map (Robinson & Jacoby-Cooper), %d rank(s)\n",
                comm.size());
    for (auto it = params.begin(); it != params.end(); ++it)
      std::printf("  %-20s %s\n", it.key().c_str(), it.value().dump().c_str());
    std::printf("  scene: %lld vertices (%lld reflective), %zu faces, %zu triangles, %zu lights\n",
                static_cast<long long>(host.vertices()),
                static_cast<long long>(host.reflective_vertices), mesh.faces.size(),
                mesh.triangle_count(), host.lights.size());
    std::printf("  colour map: %lld entries (view-independent vertices keep one colour)\n",
                static_cast<long long>(host.colors()));
    if (c.trace_reference)
      std::printf("  traced reference: %d mirror bounces traced per colour, no map lookups\n",
                  needs_iterations ? c.iterations : 0);
    if (!needs_iterations && c.iterations > 0)
      std::printf("  note: no reflective vertex and no gather rays: iterations 1..%d skipped\n",
                  c.iterations);
    if (host.lights.empty()) std::printf("  note: no emissive faces: no shadow rays\n");
    std::printf(
        "  memory estimate (max over ranks): %s (scene %s, maps %s, hit cache %s, host %s)\n",
        human_bytes(max_mem).c_str(), human_bytes(double(mem.scene)).c_str(),
        human_bytes(double(mem.maps)).c_str(), human_bytes(double(mem.hit_cache)).c_str(),
        human_bytes(double(mem.host)).c_str());
    std::fflush(stdout);
  }
  if (c.max_memory > 0 && max_mem > static_cast<double>(c.max_memory)) {
    if (root)
      std::cerr << "bake: estimated memory " << human_bytes(max_mem) << " exceeds --max-memory "
                << human_bytes(double(c.max_memory)) << "; use more ranks or fewer viewpoints\n";
    return kExitResource;
  }
  const std::string phash = parameter_hash(c);
  Checkpoint restart_cp;
  if (!c.restart.empty()) {
    restart_cp = read_checkpoint(c.restart, phash, host.colors());
    if (restart_cp.iteration > iterations)
      throw InputError(c.restart, 0,
                       "checkpoint is at iteration " + std::to_string(restart_cp.iteration) +
                           ", beyond --iterations " + std::to_string(iterations));
  }
  // Every rank reads and checks the reference (so all ranks agree on a bad one, exit 2)
  // before anything is baked or written.
  ReferenceMap reference;
  if (!c.reference.empty()) reference = read_reference_map(c.reference, mesh);
  const BakeSceneDevice scene = upload_bake_scene(
      mesh, host, c.viewpoints, c.sah ? bvh::BuildQuality::kSah : bvh::BuildQuality::kLbvh);
  Chef chef(scene, c, my_items);
  Kokkos::View<Vec3f*, MemSpace> prev("rtmini::bake::map_prev", host.colors());
  Kokkos::View<Vec3f*, MemSpace> next("rtmini::bake::map_next", host.colors());
  std::vector<Vec3f> map(static_cast<std::size_t>(host.colors()));
  timer.stop();

  // Base colours of this rank's vertices (needed by every iteration, also after a restart).
  timer.start("base");
  std::int64_t rays = 0, work = 0;
  if (c.trace_reference && comm.size() > 1) {
    // The traced recursion reads the base colour of any vertex a mirror ray reaches: each
    // rank computes all of them (the same counter-based samples, so the same colours).
    rays += chef.bake_base(0, host.vertices());
  } else {
    for (const VertexRange& r : my_ranges) rays += chef.bake_base(r.begin, r.end);
  }
  timer.stop();

  int first = 0;
  if (!c.restart.empty()) {
    map = std::move(restart_cp.colors);
    first = restart_cp.iteration + 1;
    Kokkos::deep_copy(
        prev,
        Kokkos::View<const Vec3f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
            map.data(), map.size()));
    if (root)
      std::printf("  restart: iteration %d of %s done, resuming at %d\n", restart_cp.iteration,
                  c.restart.c_str(), first);
  }

  std::vector<IterationRecord> iter_records;
  std::vector<ChunkRecord> chunks;
  const bool device_resident = comm.size() == 1;
  std::vector<Vec3f> pack(device_resident ? 0 : static_cast<std::size_t>(my_items));
  const bool contiguous_in_rank_order =
      std::is_sorted(batches.begin(), batches.end(),
                     [](const Batch& a, const Batch& b) { return a.rank < b.rank; });
  bool cache_filled = false;
  double idle = 0, completion = 0;
  int exit_code = kExitOk;
  timer.start("iterate");
  // Rank 0's own colour entries stand for the whole run (the batches are cut to equal cost).
  ProgressLine progress_line("bake", "colours", progress && root);
  IterationEta eta;
  const double iterate_start = timer.now();
  for (int it = first; it <= iterations; ++it) {
    IterationRecord rec;
    const double t0 = timer.now();
    const HitCacheMode mode = it == 0           ? HitCacheMode::kOff
                              : cache_filled    ? HitCacheMode::kUse
                              : it < iterations ? HitCacheMode::kFill
                                                : HitCacheMode::kOff;
    std::size_t packed = 0;
    std::int64_t entries_done = 0;
    for (std::size_t k = 0; k < my_ranges.size(); ++k) {
      const VertexRange r = my_ranges[k];
      const double cs = timer.now();
      const std::int64_t crays =
          c.trace_reference
              ? chef.trace_reference(r.begin, r.end, next)
              : chef.bake_iteration(it, r.begin, r.end, my_cache_offset[k], mode, prev, next);
      Kokkos::fence();
      const std::int64_t ib = host.color_offset[r.begin], ie = host.color_offset[r.end];
      chunks.push_back({comm.rank(), it, ie - ib, crays, cs, timer.now()});
      rays += crays;
      work += ie - ib;
      entries_done += ie - ib;
      if (progress_line.due()) {
        const double spent = timer.now() - iterate_start;
        const double left =
            eta.remaining(timer.now() - t0, entries_done, my_items,
                          modes_after(it, iterations, cache_filled || mode == HitCacheMode::kFill));
        progress_line.update(static_cast<double>((it - first) * my_items + entries_done),
                             static_cast<double>((iterations - first + 1) * my_items), spent,
                             spent + left);
      }
      if (device_resident) continue;
      Kokkos::deep_copy(
          Kokkos::View<Vec3f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
              pack.data() + packed, ie - ib),
          Kokkos::subview(next, std::make_pair(ib, ie)));
      packed += static_cast<std::size_t>(ie - ib);
    }
    if (mode == HitCacheMode::kFill) cache_filled = true;
    const double t1 = timer.now();
    eta.iteration_done(static_cast<int>(mode), t1 - t0);
    rec.trace = t1 - t0;
    completion = t1;
    // All-gather: every rank gets every batch's colours (the seed's MPI_Allgather step).
    // One rank already holds the whole map in `next`: it becomes `prev` without leaving the
    // device (on a GPU the two host copies and the gather would cost more than the iteration).
    const std::int64_t bytes_before = comm.bytes_sent();
    comm.barrier();
    const double t_wait = timer.now();
    idle += t_wait - t1;
    if (device_resident) {
      std::swap(prev, next);
      if (!c.checkpoint.empty() || it == iterations) download(prev, map);
    } else {
      std::vector<Vec3f> gathered = comm.allgatherv(pack);
      if (contiguous_in_rank_order) {
        map.swap(gathered);
      } else {
        std::vector<std::size_t> pos(static_cast<std::size_t>(comm.size()), 0);
        std::vector<std::size_t> rank_start(static_cast<std::size_t>(comm.size()) + 1, 0);
        for (const Batch& b : batches)
          rank_start[b.rank + 1] += host.color_offset[b.end] - host.color_offset[b.begin];
        for (int r = 0; r < comm.size(); ++r) rank_start[r + 1] += rank_start[r];
        for (const Batch& b : batches) {
          const std::int64_t ib = host.color_offset[b.begin], ie = host.color_offset[b.end];
          std::copy(gathered.begin() + rank_start[b.rank] + pos[b.rank],
                    gathered.begin() + rank_start[b.rank] + pos[b.rank] + (ie - ib),
                    map.begin() + ib);
          pos[b.rank] += static_cast<std::size_t>(ie - ib);
        }
      }
      Kokkos::deep_copy(
          prev,
          Kokkos::View<const Vec3f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
              map.data(), map.size()));
    }
    const double t2 = timer.now();
    rec.allgather = t2 - t_wait;
    rec.allgather_bytes = comm.bytes_sent() - bytes_before;
    if (!c.checkpoint.empty()) {
      if (root) {
        Checkpoint cp;
        cp.iteration = it;
        cp.parameter_hash = phash;
        cp.vertices = host.vertices();
        cp.viewpoints = c.viewpoints;
        cp.colors = map;
        write_checkpoint(c.checkpoint, cp);
      }
      comm.barrier();
    }
    rec.write = timer.now() - t2;
    iter_records.push_back(rec);
    if (progress && root)
      std::fprintf(stderr, "bake: iteration %d/%d done (%.3f s trace, %.3f s all-gather)\n", it,
                   iterations, rec.trace, rec.allgather);
    if (it == iterations) break;
    // Stop early with a valid checkpoint: test hook, signal, or a time limit the next
    // iteration (estimated from this one) would overrun. All ranks decide together.
    const double elapsed = timer.now(), last = elapsed - t0;
    const bool over_time = c.time_limit_minutes > 0 && elapsed + last > c.time_limit_minutes * 60.0;
    const bool stop =
        comm.max((c.stop_after_iteration == it || stop_requested() || over_time) ? 1.0 : 0.0) > 0.5;
    if (stop) {
      if (root)
        std::fprintf(stderr, "bake: stopping after iteration %d (%s); %s\n", it,
                     over_time ? "time limit" : "stop requested",
                     c.checkpoint.empty() ? "no --checkpoint given, progress is lost"
                                          : ("restart with --restart " + c.checkpoint).c_str());
      exit_code = kExitCheckpointed;
      break;
    }
  }
  timer.stop();
  progress_line.finish(static_cast<double>(work), static_cast<double>(work));
  if (exit_code != kExitOk) return exit_code;

  timer.start("write");
  std::vector<Vec3f> dirs(static_cast<std::size_t>(c.viewpoints));
  for (int i = 0; i < c.viewpoints; ++i) dirs[i] = Vec3f(fibonacci_point(i, c.viewpoints));
  const BakedMap baked{&mesh, &map, &host.color_offset, &dirs};
  const WriteStats ws = write_baked_map(comm, c.output, baked, my_ranges);
  timer.stop();
  if (!iter_records.empty()) iter_records.back().write += ws.seconds;

  timer.start("compare");
  if (!c.reference.empty() && root) {
    Kokkos::View<Vec3f*, MemSpace> ref("rtmini::bake::reference", reference.colors.size());
    Kokkos::deep_copy(
        ref, Kokkos::View<const Vec3f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
                 reference.colors.data(), reference.colors.size()));
    const MapErrors e = errors_from_sums(chef.lookup_errors(prev, ref, reference.viewpoints));
    report.errors = error_json(e);
    report.errors["reference"] = c.reference;
    report.errors["reference_viewpoints"] = reference.viewpoints;
    report.errors["lookup"] = to_string(c.lookup);
    print_errors("map read along the reference's directions", e);
    if (reference.viewpoints == c.viewpoints) {
      const MapErrors st = compare_stored(map, host.color_offset, reference);
      report.errors["stored"] = error_json(st);
      print_errors("stored colours, viewpoint by viewpoint", st);
    }
  }
  timer.stop();

  const std::uint64_t hash =
      comm.sum_wrap(map_hash(scene, prev, batches, comm.rank(), c.viewpoints));
  const double total_rays = static_cast<double>(comm.sum(rays));
  const double bake_time = comm.max(timer.total("base") + timer.total("iterate"));
  const double baked_colors = static_cast<double>(host.vertices()) * c.viewpoints *
                              static_cast<double>(iterations - first + 1);
  report.fom_name = "baked viewpoint colours";
  report.fom_unit = "M/s";
  report.fom_value = bake_time > 0 ? baked_colors / bake_time * 1e-6 : 0.0;
  report.verification_hash = hash;
  report.scene["rays_traced"] = total_rays;
  report.scene["rays_per_second"] = bake_time > 0 ? total_rays / bake_time : 0.0;
  report.scene["output_bytes"] = ws.file_bytes;
  if (!c.timings.empty())
    write_timings_file(comm, c, timer, {"read", "setup", "base", "iterate", "write"}, iter_records,
                       chunks, completion, idle, rays, work, params.dump());
  if (root) {
    std::printf(
        "  bake time %.4f s (base + iterations), %.4g rays (%.4g Mrays/s), write %.4f s, "
        "%s written\n",
        bake_time, total_rays, bake_time > 0 ? total_rays / bake_time * 1e-6 : 0.0, ws.seconds,
        human_bytes(double(ws.file_bytes)).c_str());
  }
  report.finish(comm, c.summary);
  return kExitOk;
}

}  // namespace rtmini::bake
