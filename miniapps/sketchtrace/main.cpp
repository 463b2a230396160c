// sketchtrace: the hand-drawn seed's ray tracer with the distribution seed's
// effects, as a Kokkos + MPI mini-app. A scheduler (--balance, schedule.hpp) hands
// each rank ranges of pixels; finished pixels flow to rank 0 in batches
// (result_sink.hpp), which checkpoints them and writes the image, AOVs and
// post-process. --time-limit, SIGTERM and SIGUSR1 stop the run cleanly: checkpoint,
// exit 4; --restart renders only the missing pixels.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <type_traits>

#include "checkpoint.hpp"
#include "cli_options.hpp"
#include "cost_map.hpp"
#include "frame_output.hpp"
#include "render_scene.hpp"
#include "renderer.hpp"
#include "result_sink.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/input_files.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/scene_file.hpp"
#include "rtmini/io/timings.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/image_metrics.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/stop_request.hpp"
#include "rtmini/report/version.hpp"
#include "schedule.hpp"

namespace rtmini::sketch {
namespace {

// Exit status of a run whose image misses its --reference by more than --max-rmse.
constexpr int kVerificationFailed = 1;

nlohmann::json vec_json(const Vec3d& v) { return {v.x, v.y, v.z}; }
nlohmann::json vec_json(const Vec3f& v) { return {v.x, v.y, v.z}; }

// Every parameter that changes pixels (also the checkpoint signature).
nlohmann::json parameters_json(const RenderSettings& s) {
  nlohmann::json p;
  p["width"] = s.width;
  p["height"] = s.height;
  p["spp"] = s.spp;
  p["soft_shadows"] = s.soft_shadows;
  p["shadow_samples"] = s.shadow_samples;
  p["bounces"] = s.bounces;
  p["glossy_samples"] = s.glossy_samples;
  p["indirect"] = s.indirect;
  p["edge_thickness"] = s.edge_thickness;
  p["crease_angle"] = s.crease_angle_deg;
  p["depth_threshold"] = s.depth_threshold;
  p["stencil_samples"] = s.stencil_samples;
  p["sphere_subdivisions"] = s.sphere_subdivisions;
  p["smooth"] = s.smooth;
  p["displacement"] = s.displacement;
  p["displacement_level"] = s.displacement_level;
  p["texture_filter"] = s.texture_filter;
  p["background"] = vec_json(s.background);
  p["ambient"] = vec_json(s.ambient);
  p["camera"] = {{"position", vec_json(s.camera.position)},
                 {"look_at", vec_json(s.camera.look_at)},
                 {"up", vec_json(s.camera.up)},
                 {"fov_deg", s.camera.fov_deg},
                 {"aperture", s.camera.aperture},
                 {"focus_distance", s.camera.focus_distance},
                 {"shutter", {s.camera.shutter_open, s.camera.shutter_close}},
                 {"velocity", vec_json(s.camera.velocity)}};
  p["seed"] = s.seed;
  p["bvh"] = bvh::to_string(s.bvh);
  p["aov"] = s.aov;
  p["style"] = s.style;
  p["general_kernel"] = s.general_kernel;
  return p;
}

// Pixels per dispatch: about 1/64 of a rank's share on a CPU backend (256..65536),
// 1/8 on a GPU, whose launches need many pixels to fill the device (65536..2^20).
std::int64_t dispatch_pixels(const RenderSettings& s, std::int64_t pixels, int ranks) {
  if (s.chunk_pixels > 0) return s.chunk_pixels;
  constexpr bool host =
      std::is_same<Kokkos::DefaultExecutionSpace, Kokkos::DefaultHostExecutionSpace>::value;
  const std::int64_t share = pixels / ((host ? 64 : 8) * static_cast<std::int64_t>(ranks));
  return std::clamp<std::int64_t>(share / (kTile * kTile) * (kTile * kTile), host ? 256 : 65536,
                                  host ? 65536 : std::int64_t(1) << 20);
}

// The progress line's cost of the pixels rank 0 has merged: the probe cost map's estimate per
// pixel, so that cheap early pixels (sky, background) do not make the ETA optimistic.
double merged_cost(const CostMap& cost, const std::vector<std::uint8_t>& done) {
  double sum = 0;
  for (std::size_t p = 0; p < done.size(); ++p)
    if (done[p]) sum += cost.at(static_cast<std::int64_t>(p));
  return sum;
}

struct BandRecord {
  double start, end;
  std::int64_t pixels, rays;
  std::int64_t iteration;
};

void write_timings_file(const std::string& path, const Communicator& comm, const RunReport& report,
                        const std::vector<BandRecord>& bands, double completion, double idle,
                        std::int64_t rays, std::int64_t pixels, const std::string& scene_name,
                        const std::string& strategy) {
  RankTimings mine;
  for (const BandRecord& b : bands)
    mine.chunks.push_back({b.iteration, b.pixels, b.rays, b.start, b.end});
  mine.completion = completion;
  mine.idle = idle;
  mine.rays = rays;
  mine.work_units = pixels;
  write_rank_timings(path, comm, report.timer, mine,
                     {"sketchtrace", strategy, scene_name, report.parameters.dump(), {}});
}

// One run's state, handed from phase to phase (read, plan, trace, gather, write, report).
struct RunState {
  explicit RunState(Communicator& c) : comm(c) {}
  Communicator& comm;
  RunOptions opt;
  RunReport report;
  RenderSettings s;
  Balance balance = Balance::kStatic;
  std::unique_ptr<HostScene> scene;
  std::unique_ptr<Renderer> renderer;
  std::vector<std::uint8_t> done;         // rank 0: per-pixel done mask
  std::vector<PixelResult> frame_pixels;  // rank 0: the whole image
  std::string signature;                  // what a checkpoint must match
  std::vector<InputFileHash> inputs;      // content of every file the scene was read from
  double peak_bytes = 0;                  // expected peak resident bytes, max over ranks
  std::unique_ptr<PixelOrder> order;
  std::int64_t batch = 0;  // pixels per dispatch
  CostMap cost;
  bool root() const { return comm.is_root(); }
  std::size_t pixels_total() const { return static_cast<std::size_t>(s.width) * s.height; }
};

// What the render loop leaves for the phases after it.
struct TraceResult {
  std::vector<BandRecord> records;
  std::int64_t rays = 0, tests = 0, rendered = 0, missing = 0;
  double render_start = 0, loop_end = 0, render_end = 0, completion = 0, idle = 0;
  bool stopping = false;
  std::string stop_reason;
};

// Read: settings from the scene file and the command line, then the scene itself.
void read_inputs(RunState& r, const CliOverrides& cli) {
  RunOptions& opt = r.opt;
  r.report.timer.start("load");
  std::unique_ptr<SceneDescription> desc;
  if (lower_extension(opt.input) == ".toml") {
    desc = std::make_unique<SceneDescription>(read_scene_file(opt.input));
    apply_scene_settings(*desc, r.s);
  } else if (!std::ifstream(opt.input)) {
    throw InputError(opt.input + ": cannot open the input");
  }
  cli.apply(r.s);
  validate_settings(r.s, "command line");
  if (!opt.output.empty()) check_output_path(opt.output, r.s);
  if (!opt.reference.empty()) require_readable_image(opt.reference);
  // Every place the run will write, before anything is read or computed (IoError: exit 3).
  const double pixels = static_cast<double>(r.s.width) * r.s.height;
  check_output_places({{opt.output, pixels * 3},
                       {opt.checkpoint, pixels * (sizeof(PixelResult) + 1)},
                       {opt.summary, 0},
                       {opt.timings, 0}});
#ifndef RTMINI_SKETCH_HAVE_NPR
  if (r.s.style != "none")
    throw InputError("--style " + r.s.style + ": this build has no hand-drawn passes");
#endif
  r.balance = parse_balance(opt.balance);
  if (!(opt.time_limit_minutes >= 0))
    throw InputError("--time-limit must be >= 0 minutes (got " +
                     std::to_string(opt.time_limit_minutes) + ")");
  if (!(opt.checkpoint_interval > 0)) throw InputError("--checkpoint-interval must be > 0 seconds");
  r.scene = std::make_unique<HostScene>(build_scene(opt.input, desc.get(), r.s));
  // Hashed as read, for the checkpoint to remember and the restart to compare.
  if (!opt.checkpoint.empty() || !opt.restart.empty()) {
    std::vector<std::string> files =
        desc ? std::vector<std::string>{opt.input} : mesh_files(opt.input);
    if (desc)
      for (const MeshDesc& m : desc->meshes)
        for (std::string& f : mesh_files(m.file)) files.push_back(std::move(f));
    r.inputs = hash_input_files(files);
  }
  cli.apply_camera(r.s);
  validate_settings(r.s, "command line");
  r.report.timer.stop();
  r.report.parameters = parameters_json(r.s);
}

// Upload: the device scene, and what the summary says about it.
void upload_scene(RunState& r) {
  r.report.timer.start("upload");
  r.renderer = std::make_unique<Renderer>(*r.scene, r.s);
  r.report.timer.stop();
  const DeviceScene& ds = r.renderer->scene();
  r.report.scene = {{"input", r.opt.input},
                    {"triangles", ds.triangles},
                    {"vertices", r.scene->mesh.positions.size()},
                    {"objects", r.scene->mesh.objects.size()},
                    {"materials", r.scene->mesh.materials.size()},
                    {"quad_lights", ds.num_quads},
                    {"mesh_lights", ds.num_mesh_lights},
                    {"point_lights", ds.num_points},
                    {"memory_estimate_bytes", r.peak_bytes}};
  if (ds.maps.any) {
    r.report.scene["textures"] = r.scene->map_images.size();
    r.report.scene["texture_bytes"] = ds.texture_bytes;
  }
}

// What the run will allocate from here on (report/memory_check.hpp), from the host scene and
// the frame size, before anything is uploaded. Rank 0 holds the whole frame (pixel results,
// output planes, done flags); every rank the device scene and one dispatch's buffers.
MemoryNeed memory_need(const RunState& r) {
  const double nt = static_cast<double>(r.scene->mesh.triangle_count());
  const double nv = static_cast<double>(r.scene->mesh.positions.size());
  const double pixels = static_cast<double>(r.pixels_total());
  const double dispatch = static_cast<double>(
      dispatch_pixels(r.s, static_cast<std::int64_t>(r.pixels_total()), r.comm.size()));
  MemoryNeed need;
  need.views = device_mesh_bytes(r.scene->mesh.triangle_count(), r.scene->mesh.positions.size()) +
               nv * sizeof(Vec3) + dispatch * (sizeof(std::int64_t) + sizeof(PixelResult)) +
               texture_bytes(*r.scene);
  // Upload's host side (triangle list, normals in double) and one dispatch's results.
  need.host = nt * 4 * sizeof(int) + nv * (sizeof(Vec3d) + sizeof(Vec3)) +
              dispatch * (sizeof(std::int64_t) + sizeof(PixelResult));
  if (r.root()) need.host += pixels * (sizeof(PixelResult) + 11 * sizeof(float) + 1);
  return need;
}

// Refuses, on every rank alike (IoError: exit 3), a run that would not fit; keeps the peak
// expected for the banner.
void check_memory(RunState& r) {
  const MemoryNeed need = memory_need(r);
  const MemoryPeak peak = expected_peak(need);
  r.peak_bytes = r.comm.max(peak.host + peak.device);
  require_memory(r.comm, need, r.opt.max_memory);
}

// The banner, with the memory estimate.
void print_banner(const RunState& r) {
  if (!r.root()) return;
  std::printf("%s\n", build_banner().c_str());
  std::printf("sketchtrace: input %s, output %s\n", r.opt.input.c_str(),
              r.opt.output.empty() ? "(none)" : r.opt.output.c_str());
  std::printf("  parameters: %s\n", r.report.parameters.dump().c_str());
  std::printf("  scene: %s\n", r.report.scene.dump().c_str());
  std::printf("  kernel features: %s%s, ranks %d, threads per rank %d\n",
              feature_names(r.renderer->features()).c_str(),
              r.s.general_kernel ? " (forced general kernel)" : "", r.comm.size(),
              compat::concurrency());
  std::printf("  memory estimate (max over ranks): %.1f MiB peak resident\n",
              r.peak_bytes / 1048576.0);
  if (r.renderer->scene().maps.any)
    std::printf("  textures: %zu images, %.2f MiB on the device (mip chains and texture records)\n",
                r.scene->map_images.size(), r.renderer->scene().texture_bytes / 1048576.0);
  std::fflush(stdout);
}

// Restart: rank 0 reads the finished pixels, every rank learns which to skip.
void read_restart(RunState& r) {
  if (r.root()) {
    r.frame_pixels.assign(r.pixels_total(), PixelResult{});
    r.done.assign(r.pixels_total(), 0);
  }
  r.signature = r.report.parameters.dump() + "|" + r.opt.input;
  if (r.opt.restart.empty()) return;
  if (r.root()) {
    Checkpoint c = read_checkpoint(r.opt.restart);
    verify_input_hashes(r.opt.restart, c.inputs, r.inputs);
    if (c.width != r.s.width || c.height != r.s.height || c.signature != r.signature)
      throw InputError(r.opt.restart +
                       ": checkpoint was written with different parameters or scene");
    r.done = std::move(c.done);
    r.frame_pixels = std::move(c.pixels);
  }
  r.comm.broadcast(r.done);
}

// Plan: the pixels left, the dispatch size and, where needed, the probed cost map.
void plan(RunState& r) {
  read_restart(r);
  r.order = std::make_unique<PixelOrder>(r.s.width, r.s.height, r.done);
  if (!r.root()) r.done.clear();
  r.batch = dispatch_pixels(r.s, r.order->size(), r.comm.size());
  // The progress ETA weighs pixels by the probed cost too, so a run that shows progress on any
  // rank probes even when its balance does not need the map (collective: all ranks probe).
  const bool eta_probe = r.comm.max(r.opt.progress ? 1.0 : 0.0) > 0.5;
  if (needs_cost_map(r.balance) || eta_probe) {
    r.report.timer.start("probe");
    bool reused = false;
    r.cost = make_cost_map(*r.renderer, r.comm, r.s.width, r.s.height, r.opt.cost_map, r.signature,
                           reused);
    r.report.timer.stop();
    if (r.root())
      std::printf("  cost map: %s (%d x %d probes)\n",
                  reused ? ("reused " + r.opt.cost_map).c_str() : "probed", r.cost.grid_w,
                  r.cost.grid_h);
  }
  r.report.parameters["balance"] = to_string(r.balance);
  if (r.root()) {
    std::printf("  balance: %s, %lld pixels to render, %lld per dispatch\n", to_string(r.balance),
                static_cast<long long>(r.order->size()), static_cast<long long>(r.batch));
    std::fflush(stdout);
  }
}

// Rank 0's progress line: pixels merged so far, weighted by the fitted per-pixel cost.
class RenderProgress {
 public:
  explicit RenderProgress(const RunState& r)
      : r_(r), line_("sketchtrace", "px", r.opt.progress && r.root()) {
    if (!line_.enabled()) return;
    restart_cost_ = merged_cost(r.cost, r.done);
    for (std::int64_t pos = 0; pos < r.order->size(); ++pos)
      total_probe_cost_ += r.cost.at(r.order->pixel(pos));
  }
  void dispatched(const std::vector<std::int64_t>& pixels, double seconds, std::int64_t merged) {
    if (!line_.enabled()) return;
    double probe = 0;
    for (const std::int64_t p : pixels) probe += r_.cost.at(p);
    fit_.add(seconds, static_cast<double>(pixels.size()), probe);
    if (!line_.due()) return;
    const double m = static_cast<double>(merged), total = static_cast<double>(r_.order->size());
    line_.update(m, total, fit_.cost(m, merged_cost(r_.cost, r_.done) - restart_cost_),
                 fit_.cost(total, total_probe_cost_));
  }
  void finish(double done, double total) { line_.finish(done, total); }

 private:
  const RunState& r_;
  ProgressLine line_;
  CostFit fit_;  // seconds per pixel as a + b x probe cost
  double restart_cost_ = 0, total_probe_cost_ = 0;
};

// --comm-thread: peers' steal requests and loads are answered while this rank renders,
// instead of between dispatches. MPI calls take turns under mpi_mutex(): the main thread
// holds it except while a dispatch renders.
class CommThread {
 public:
  CommThread(bool on, Scheduler& scheduler) : on_(on), lock_(mpi_mutex(), std::defer_lock) {
    if (!on_) return;
    lock_.lock();
    worker_ = std::thread([this, &scheduler]() {
      while (!quit_.load()) {
        {
          const std::lock_guard<std::mutex> g(mpi_mutex());
          scheduler.progress();
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    });
  }
  void rendering() {
    if (on_) lock_.unlock();
  }
  void rendered() {
    if (on_) lock_.lock();
  }
  void stop() {
    if (!on_) return;
    quit_ = true;
    lock_.unlock();
    worker_.join();
    on_ = false;
  }
  ~CommThread() { stop(); }

 private:
  bool on_;
  std::unique_lock<std::mutex> lock_;
  std::atomic<bool> quit_{false};
  std::thread worker_;
};

bool use_comm_thread(RunState& r, const Scheduler& scheduler) {
  const bool on = r.opt.comm_thread && scheduler.has_progress() && mpi_serialized_threads();
  r.report.parameters["comm_thread"] = on;
  if (scheduler.has_progress() && r.root()) {
    std::printf("  communication thread: %s\n",
                on                  ? "on"
                : r.opt.comm_thread ? "off (MPI did not grant MPI_THREAD_SERIALIZED)"
                                    : "off (--comm-thread off)");
    std::fflush(stdout);
  }
  return on;
}

// Gather: the schedule's and the sink's last messages, and the run-wide stop reason.
void gather(RunState& r, Scheduler& scheduler, ResultSink& sink, TraceResult& t) {
  r.report.timer.start("gather");
  scheduler.finish(t.stopping);
  sink.finish();
  r.report.timer.stop();
  t.render_end = r.comm.max(t.loop_end);
  // Report the reason any rank stopped for (rank 0 may only have heard that a peer stopped):
  // the gravest that some rank saw (signal, then time limit, then --stop-after-chunks).
  static const char* const kReasons[] = {"", "--stop-after-chunks", "time limit", "stop signal"};
  int code = 0;
  for (int k = 1; k < 4; ++k)
    if (t.stop_reason == kReasons[k]) code = k;
  code = static_cast<int>(r.comm.max(static_cast<double>(code)));
  if (code > 0) t.stop_reason = kReasons[code];
  // A rank's completion is the end of its last dispatch (the paper's per-rank
  // completion plots); idle is the rest of the render span: waiting for work, for
  // messages, for the termination round and for the slowest rank.
  t.completion = t.records.empty() ? t.render_start : t.records.back().end;
  double busy = 0;
  for (const BandRecord& b : t.records) busy += b.end - b.start;
  t.idle = std::max(0.0, (t.render_end - t.render_start) - busy);
  t.missing = r.comm.sum(r.root() ? r.order->size() - sink.merged() : std::int64_t(0));
}

void save_checkpoint(RunState& r) {
  r.report.timer.start("checkpoint");
  write_checkpoint(r.opt.checkpoint, {r.s.width, r.s.height, r.signature,
                                      format_input_hashes(r.inputs), r.done, r.frame_pixels});
  r.report.timer.stop();
}

// Trace: dispatches until the schedule runs dry or a stop is asked for, then gather.
TraceResult trace(RunState& r) {
  install_stop_handlers();
  const RunOptions& opt = r.opt;
  const bool checkpointing = !opt.checkpoint.empty();
  RenderProgress progress(r);
  const double limit_s = opt.time_limit_minutes * 60.0;
  const double reserve = std::min(60.0, 0.05 * limit_s);  // for the final gather and checkpoint
  ResultSink sink(r.comm, *r.order, r.frame_pixels, r.done,
                  checkpointing ? opt.checkpoint_interval : (opt.progress ? 1.0 : 0.0));
  const std::unique_ptr<Scheduler> scheduler = make_scheduler(
      r.balance, r.comm, *r.order, needs_cost_map(r.balance) ? &r.cost : nullptr, r.batch);
  TraceResult t;
  std::vector<PosRange> ranges;
  std::vector<std::int64_t> list;
  std::vector<PixelResult> out;
  double last_checkpoint = r.report.timer.now(), last_dispatch = 0.0;
  t.render_start = r.report.timer.now();
  auto should_stop = [&]() {
    if (stop_requested())
      t.stop_reason = "stop signal";
    else if (limit_s > 0 && r.report.timer.now() + 2.0 * last_dispatch + reserve > limit_s)
      t.stop_reason = "time limit";
    else if (opt.stop_after_chunks >= 0 &&
             static_cast<int>(t.records.size()) >= opt.stop_after_chunks)
      t.stop_reason = "--stop-after-chunks";
    else
      return false;
    return true;
  };
  CommThread comm_thread(use_comm_thread(r, *scheduler), *scheduler);
  r.report.timer.start("render");
  for (;;) {
    if (should_stop()) {
      t.stopping = true;
      break;
    }
    if (!scheduler->next(ranges, should_stop)) {
      t.stopping = !t.stop_reason.empty();
      break;
    }
    list.clear();
    for (const PosRange& pr : ranges)
      for (std::int64_t pos = pr.begin; pos < pr.end; ++pos) list.push_back(r.order->pixel(pos));
    const double t0 = r.report.timer.now();
    comm_thread.rendering();
    r.renderer->render_pixels(list, out);
    comm_thread.rendered();
    const double t1 = r.report.timer.now();
    last_dispatch = t1 - t0;
    std::int64_t chunk_rays = 0;
    for (const PixelResult& p : out) {
      chunk_rays += p.rays;
      t.tests += static_cast<std::int64_t>(p.tests);
    }
    t.rays += chunk_rays;
    t.rendered += static_cast<std::int64_t>(out.size());
    t.records.push_back({t0, t1, static_cast<std::int64_t>(out.size()), chunk_rays,
                         static_cast<std::int64_t>(t.records.size())});
    sink.add(ranges, out, t1);
    sink.poll(t1);
    if (r.root() && checkpointing && t1 - last_checkpoint >= opt.checkpoint_interval) {
      save_checkpoint(r);
      last_checkpoint = r.report.timer.now();
    }
    if (r.root()) progress.dispatched(list, t1 - t0, sink.merged());
  }
  t.loop_end = r.report.timer.now();
  r.report.timer.stop();
  comm_thread.stop();
  gather(r, *scheduler, sink, t);
  const double size = static_cast<double>(r.order->size());
  progress.finish(size - static_cast<double>(t.missing), size);
  if (t.missing > 0 && r.root() && checkpointing) save_checkpoint(r);
  return t;
}

// The figure of merit (rays per second over the render span) and the optional --stats line.
void report_rates(RunState& r, const TraceResult& t) {
  const std::int64_t total_rays = r.comm.sum(t.rays);
  const std::int64_t total_tests = r.comm.sum(t.tests);
  const double render_time = t.render_end - t.render_start;
  r.report.fom_name = "ray_rate";
  r.report.fom_unit = "Mrays/s";
  r.report.fom_value = render_time > 0 ? static_cast<double>(total_rays) / render_time * 1e-6 : 0.0;
  const std::size_t triangles = r.renderer->scene().triangles;
  if (r.root()) {
    std::printf("  render: %.3f s (max over ranks), %lld rays, %.3f Mrays/s\n", render_time,
                static_cast<long long>(total_rays), r.report.fom_value);
    if (r.s.stats && total_rays > 0) {
      const double per_ray = static_cast<double>(total_tests) / static_cast<double>(total_rays);
      std::printf(
          "  stats: %.2f ray-triangle tests per ray; brute force %zu (%.5f of brute force, "
          "1/%.0f)\n",
          per_ray, triangles, per_ray / static_cast<double>(triangles),
          static_cast<double>(triangles) / std::max(per_ray, 1e-9));
    }
  }
  r.report.scene["rays"] = total_rays;
  if (r.s.stats)
    r.report.scene["tests_per_ray"] =
        total_rays > 0 ? double(total_tests) / double(total_rays) : 0.0;
}

// Image statistics for the stability checks (issue 7): a non-finite pixel is a bug.
void report_image_statistics(RunState& r) {
  double sum[3] = {0, 0, 0}, peak = 0;
  std::int64_t nonfinite = 0;
  for (const PixelResult& p : r.frame_pixels) {
    const double c[3] = {p.r, p.g, p.b};
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) {
      ++nonfinite;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      sum[k] += c[k];
      peak = std::max(peak, c[k]);
    }
  }
  const double inv = 1.0 / std::max<double>(1.0, double(r.frame_pixels.size() - nonfinite));
  r.report.scene["image"] = {{"mean_rgb", {sum[0] * inv, sum[1] * inv, sum[2] * inv}},
                             {"max", peak},
                             {"nonfinite_pixels", nonfinite}};
  std::printf("  image: mean %.6g %.6g %.6g, max %.6g, %lld non-finite pixels\n", sum[0] * inv,
              sum[1] * inv, sum[2] * inv, peak, static_cast<long long>(nonfinite));
}

// --reference: the colour image against it; kVerificationFailed past --max-rmse.
int compare_with_reference(RunState& r, const Frame& frame) {
  const RunOptions& opt = r.opt;
  const ImageErrors e = compare_images(frame.color, read_image(opt.reference), opt.reference);
  r.report.errors = {{"reference", opt.reference},
                     {"rmse", e.rmse},
                     {"rel_mse", e.rel_mse},
                     {"psnr", e.psnr},
                     {"ssim", e.ssim},
                     {"max_rmse", opt.max_rmse}};
  const bool ok = opt.max_rmse < 0 || e.rmse <= opt.max_rmse;
  std::printf(
      "  reference %s: RMSE %.6g, relative MSE %.6g, PSNR %.2f dB, SSIM %.5f (RMSE limit %g) "
      "%s\n",
      opt.reference.c_str(), e.rmse, e.rel_mse, e.psnr, e.ssim, opt.max_rmse, ok ? "PASS" : "FAIL");
  return ok ? kExitOk : kVerificationFailed;
}

// Write (rank 0): the verification hash, the image statistics, the image and the comparison.
int write_outputs(RunState& r) {
  int exit_code = kExitOk;
  r.report.timer.start("write");
  if (r.root()) {
    r.report.verification_hash = hash_pixels(r.frame_pixels, 0, r.s.needs_aov_pass());
    report_image_statistics(r);
    if (!r.opt.output.empty() || !r.opt.reference.empty()) {
      const Frame frame = assemble_frame(r.frame_pixels, r.s.width, r.s.height);
      if (!r.opt.output.empty())
        for (const std::string& f : write_frame(r.opt.output, frame, r.s))
          std::printf("  wrote %s\n", f.c_str());
      if (!r.opt.reference.empty()) exit_code = compare_with_reference(r, frame);
    }
  }
  r.report.timer.stop();
  return exit_code;
}

// Stopped early: the missing pixels are the figure, exit 4 (checkpointed or not).
void report_stop(RunState& r, const TraceResult& t) {
  if (r.root())
    std::fprintf(stderr, "sketchtrace: stopped (%s) with %lld of %zu pixels missing; %s\n",
                 t.stop_reason.empty() ? "peer stopped" : t.stop_reason.c_str(),
                 static_cast<long long>(t.missing), r.pixels_total(),
                 !r.opt.checkpoint.empty() ? ("restart with --restart " + r.opt.checkpoint).c_str()
                                           : "no --checkpoint given, the work is lost");
  r.report.fom_name = "pixels_missing";
  r.report.fom_unit = "pixels";
  r.report.fom_value = static_cast<double>(t.missing);
}

// Report: per-rank timings (when asked for) and the summary; collective.
void finish_report(RunState& r, const TraceResult& t) {
  if (!r.opt.timings.empty())
    write_timings_file(r.opt.timings, r.comm, r.report, t.records, t.completion, t.idle, t.rays,
                       t.rendered, r.opt.input, to_string(r.balance));
  r.report.finish(r.comm, r.opt.summary);
}

int run(Communicator& comm, int argc, char** argv) {
  CLI::App app{"sketchtrace: distribution ray tracer with a hand-drawn post-process",
               "sketchtrace"};
  CommonOptions common;
  add_common_options(app, common);
  RunOptions opt;
  CliOverrides cli;
  cli.add_to(app, opt);
  if (const auto done = parse_command_line(app, argc, argv, common, comm.is_root())) return *done;
  opt.summary = common.summary;
  opt.timings = common.timings;
  opt.progress = progress_wanted(common);
  opt.max_memory = common.memory_limit();

  RunState r(comm);  // its report's clock starts here, after Kokkos, as before the split
  r.opt = opt;
  r.report.app = "sketchtrace";

  read_inputs(r, cli);
  check_memory(r);
  upload_scene(r);
  print_banner(r);
  plan(r);
  const TraceResult t = trace(r);
  report_rates(r, t);
  if (t.missing > 0) {
    report_stop(r, t);
    finish_report(r, t);
    return kExitCheckpointed;
  }
  const int exit_code = write_outputs(r);
  finish_report(r, t);
  return static_cast<int>(comm.max(static_cast<double>(exit_code)));
}
}  // namespace
}  // namespace rtmini::sketch

int main(int argc, char** argv) {
  return rtmini::app_main("sketchtrace", argc, argv, rtmini::sketch::run);
}
