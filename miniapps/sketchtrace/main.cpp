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
#include "rtmini/io/error.hpp"
#include "rtmini/io/timings.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/image_metrics.hpp"
#include "rtmini/report/progress.hpp"
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

std::string extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
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

// Seconds per pixel as a + b * probe cost, fitted by least squares to rank 0's dispatches. The
// probe counts the rays of one camera sample; the constant part carries what it does not see
// (anti-aliasing samples, the stencil, the per-pixel work of cheap background pixels), without
// which the ETA over-weights the costly pixels still to come.
class PixelCostFit {
 public:
  void add(double seconds, double pixels, double probe_cost) {
    nn_ += pixels * pixels;
    nc_ += pixels * probe_cost;
    cc_ += probe_cost * probe_cost;
    tn_ += seconds * pixels;
    tc_ += seconds * probe_cost;
  }
  // Estimated seconds of `pixels` pixels whose probe costs sum to `probe_cost`.
  double cost(double pixels, double probe_cost) const {
    const double det = nn_ * cc_ - nc_ * nc_;
    double a = det > 1e-12 * nn_ * cc_ ? (tn_ * cc_ - tc_ * nc_) / det : -1.0;
    double b = det > 1e-12 * nn_ * cc_ ? (tc_ * nn_ - tn_ * nc_) / det : -1.0;
    if (a < 0 || b < 0) {  // one term explains the data: fall back to the probe cost alone
      a = 0;
      b = cc_ > 0 ? tc_ / cc_ : 0.0;
    }
    return a * pixels + b * probe_cost;
  }

 private:
  double nn_ = 0, nc_ = 0, cc_ = 0, tn_ = 0, tc_ = 0;
};

struct BandRecord {
  double start, end;
  std::int64_t pixels, rays;
  std::int64_t iteration;
};

void write_timings_file(const std::string& path, const Communicator& comm, const RunReport& report,
                        const std::vector<BandRecord>& bands, double completion, double idle,
                        std::int64_t rays, std::int64_t pixels, const std::string& scene_name,
                        const std::string& strategy) {
  std::vector<std::string> names;
  std::map<std::string, std::pair<double, double>> span;
  for (const auto& ph : report.timer.phases()) {
    if (!span.count(ph.first)) {
      names.push_back(ph.first);
      span[ph.first] = ph.second;
    }
    span[ph.first].second = ph.second.second;
  }
  std::vector<double> starts, ends;
  for (const auto& n : names) {
    starts.push_back(span[n].first);
    ends.push_back(span[n].second);
  }
  const auto all_starts = comm.gatherv(starts), all_ends = comm.gatherv(ends);
  const auto all_bands = comm.gatherv(bands);
  std::vector<std::int64_t> band_rank(bands.size(), comm.rank());
  const auto all_band_rank = comm.gatherv(band_rank);
  const std::vector<double> mine_d = {completion, idle};
  const std::vector<std::int64_t> mine_i = {comm.messages_sent(), comm.bytes_sent(), rays, pixels};
  const auto all_d = comm.gatherv(mine_d);
  const auto all_i = comm.gatherv(mine_i);
  if (!comm.is_root()) return;
  TimingsData t;
  t.app = "sketchtrace";
  t.version = version_string();
  t.git_hash = git_hash();
  t.backend = compat::backend_name();
  t.strategy = strategy;
  t.scene = scene_name;
  t.parameters = report.parameters.dump();
  t.ranks = comm.size();
  t.threads = compat::concurrency();
  t.phase_names = names;
  t.phase_start = all_starts;
  t.phase_end = all_ends;
  for (std::size_t i = 0; i < all_bands.size(); ++i) {
    t.chunk_rank.push_back(all_band_rank[i]);
    t.chunk_iteration.push_back(all_bands[i].iteration);
    t.chunk_work_units.push_back(all_bands[i].pixels);
    t.chunk_rays.push_back(all_bands[i].rays);
    t.chunk_start.push_back(all_bands[i].start);
    t.chunk_end.push_back(all_bands[i].end);
  }
  for (int r = 0; r < comm.size(); ++r) {
    t.rank_completion_time.push_back(all_d[2 * r]);
    t.rank_idle_time.push_back(all_d[2 * r + 1]);
    t.rank_messages_sent.push_back(all_i[4 * r]);
    t.rank_bytes_sent.push_back(all_i[4 * r + 1]);
    t.rank_rays.push_back(all_i[4 * r + 2]);
    t.rank_work_units.push_back(all_i[4 * r + 3]);
  }
  write_timings(path, t);
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

  RunReport report;
  report.app = "sketchtrace";
  report.timer.start("load");
  RenderSettings s;
  std::unique_ptr<SceneDescription> desc;
  if (extension(opt.input) == ".toml") {
    desc = std::make_unique<SceneDescription>(read_scene_file(opt.input));
    apply_scene_settings(*desc, s);
  } else if (!std::ifstream(opt.input)) {
    throw InputError(opt.input + ": cannot open the input");
  }
  cli.apply(s);
  opt.max_memory = cli.max_memory();
  validate_settings(s, "command line");
  if (!opt.output.empty()) check_output_path(opt.output);
#ifndef RTMINI_SKETCH_HAVE_NPR
  if (s.style != "none")
    throw InputError("--style " + s.style + ": this build has no hand-drawn passes");
#endif
  const Balance balance = parse_balance(opt.balance);
  if (!(opt.time_limit_minutes >= 0))
    throw InputError("--time-limit must be >= 0 minutes (got " +
                     std::to_string(opt.time_limit_minutes) + ")");
  if (!(opt.checkpoint_interval > 0)) throw InputError("--checkpoint-interval must be > 0 seconds");
  const HostScene scene = build_scene(opt.input, desc.get(), s);
  cli.apply_camera(s);
  validate_settings(s, "command line");
  report.timer.stop();

  report.parameters = parameters_json(s);
  const std::size_t pixels_total = static_cast<std::size_t>(s.width) * s.height;

  report.timer.start("upload");
  const Renderer renderer(scene, s);
  report.timer.stop();
  const DeviceScene& ds = renderer.scene();
  report.scene = {{"input", opt.input},
                  {"triangles", ds.triangles},
                  {"vertices", scene.mesh.positions.size()},
                  {"objects", scene.mesh.objects.size()},
                  {"materials", scene.mesh.materials.size()},
                  {"quad_lights", ds.num_quads},
                  {"mesh_lights", ds.num_mesh_lights},
                  {"point_lights", ds.num_points}};
  // Rank 0 holds the scene and the whole frame (pixel results, output planes, the
  // done flags); other ranks only the scene, so rank 0's total is the maximum.
  const double frame_bytes =
      static_cast<double>(pixels_total) * (sizeof(PixelResult) + 11 * sizeof(float) + 1);
  const double peak_bytes = static_cast<double>(ds.bytes) + frame_bytes;
  if (comm.is_root()) {
    std::printf("%s\n", build_banner().c_str());
    std::printf("sketchtrace: input %s, output %s\n", opt.input.c_str(),
                opt.output.empty() ? "(none)" : opt.output.c_str());
    std::printf("  parameters: %s\n", report.parameters.dump().c_str());
    std::printf("  scene: %s\n", report.scene.dump().c_str());
    std::printf("  kernel features: %s%s, ranks %d, threads per rank %d\n",
                feature_names(renderer.features()).c_str(),
                s.general_kernel ? " (forced general kernel)" : "", comm.size(),
                compat::concurrency());
    std::printf(
        "  memory estimate (max over ranks): %.1f MiB (scene %.1f MiB per rank, frame %.1f MiB on "
        "rank 0)\n",
        peak_bytes / 1048576.0, static_cast<double>(ds.bytes) / 1048576.0, frame_bytes / 1048576.0);
    std::fflush(stdout);
  }
  // Every rank computes the same estimate, so all refuse together (exit 3, as bake does).
  if (opt.max_memory > 0 && peak_bytes > static_cast<double>(opt.max_memory)) {
    if (comm.is_root())
      std::fprintf(stderr,
                   "sketchtrace: estimated memory %.1f MiB exceeds --max-memory %.1f MiB; lower "
                   "the resolution\n",
                   peak_bytes / 1048576.0, static_cast<double>(opt.max_memory) / 1048576.0);
    return kExitResource;
  }

  // Restart: rank 0 reads the finished pixels, every rank learns which to skip.
  std::vector<std::uint8_t> done;
  std::vector<PixelResult> frame_pixels;  // rank 0: the whole image
  if (comm.is_root()) {
    frame_pixels.assign(pixels_total, PixelResult{});
    done.assign(pixels_total, 0);
  }
  const std::string signature = report.parameters.dump() + "|" + opt.input;
  if (!opt.restart.empty()) {
    if (comm.is_root()) {
      Checkpoint c = read_checkpoint(opt.restart);
      if (c.width != s.width || c.height != s.height || c.signature != signature)
        throw InputError(opt.restart +
                         ": checkpoint was written with different parameters or scene");
      done = std::move(c.done);
      frame_pixels = std::move(c.pixels);
    }
    comm.broadcast(done);
  }
  const PixelOrder order(s.width, s.height, done);
  if (!comm.is_root()) done.clear();
  const std::int64_t batch = dispatch_pixels(s, order.size(), comm.size());

  CostMap cost;
  // The progress ETA weighs pixels by the probed cost too, so a run that shows progress on any
  // rank probes even when its balance does not need the map (collective: all ranks probe).
  const bool eta_probe = comm.max(opt.progress ? 1.0 : 0.0) > 0.5;
  if (needs_cost_map(balance) || eta_probe) {
    report.timer.start("probe");
    bool reused = false;
    cost = make_cost_map(renderer, comm, s.width, s.height, opt.cost_map, signature, reused);
    report.timer.stop();
    if (comm.is_root())
      std::printf("  cost map: %s (%d x %d probes)\n",
                  reused ? ("reused " + opt.cost_map).c_str() : "probed", cost.grid_w, cost.grid_h);
  }
  report.parameters["balance"] = to_string(balance);
  if (comm.is_root()) {
    std::printf("  balance: %s, %lld pixels to render, %lld per dispatch\n", to_string(balance),
                static_cast<long long>(order.size()), static_cast<long long>(batch));
    std::fflush(stdout);
  }

  install_stop_handlers();
  const bool checkpointing = !opt.checkpoint.empty();
  const bool progress = opt.progress;
  ProgressLine progress_line("sketchtrace", "px", progress && comm.is_root());
  const double restart_cost = progress_line.enabled() ? merged_cost(cost, done) : 0.0;
  double total_probe_cost = 0;
  if (progress_line.enabled())
    for (std::int64_t pos = 0; pos < order.size(); ++pos)
      total_probe_cost += cost.at(order.pixel(pos));
  PixelCostFit pixel_cost;
  const double limit_s = opt.time_limit_minutes * 60.0;
  const double reserve = std::min(60.0, 0.05 * limit_s);  // for the final gather and checkpoint
  ResultSink sink(comm, order, frame_pixels, done,
                  checkpointing ? opt.checkpoint_interval : (progress ? 1.0 : 0.0));
  const std::unique_ptr<Scheduler> scheduler =
      make_scheduler(balance, comm, order, needs_cost_map(balance) ? &cost : nullptr, batch);
  std::vector<BandRecord> records;
  std::vector<PosRange> ranges;
  std::vector<std::int64_t> list;
  std::vector<PixelResult> out;
  std::int64_t rays = 0, tests = 0, rendered = 0;
  double last_checkpoint = report.timer.now(), last_dispatch = 0.0;
  const double render_start = report.timer.now();
  bool stopping = false;
  std::string stop_reason;
  auto should_stop = [&]() {
    if (stop_requested())
      stop_reason = "stop signal";
    else if (limit_s > 0 && report.timer.now() + 2.0 * last_dispatch + reserve > limit_s)
      stop_reason = "time limit";
    else if (opt.stop_after_chunks >= 0 &&
             static_cast<int>(records.size()) >= opt.stop_after_chunks)
      stop_reason = "--stop-after-chunks";
    else
      return false;
    return true;
  };
  // --comm-thread: peers' steal requests and loads are answered while this rank renders,
  // instead of between dispatches. MPI calls take turns under mpi_mutex(): the main thread
  // holds it except while a dispatch renders.
  const bool comm_thread = opt.comm_thread && scheduler->has_progress() && mpi_serialized_threads();
  report.parameters["comm_thread"] = comm_thread;
  if (scheduler->has_progress() && comm.is_root()) {
    std::printf("  communication thread: %s\n",
                comm_thread       ? "on"
                : opt.comm_thread ? "off (MPI did not grant MPI_THREAD_SERIALIZED)"
                                  : "off (--comm-thread off)");
    std::fflush(stdout);
  }
  std::unique_lock<std::mutex> mpi_lock(mpi_mutex(), std::defer_lock);
  std::atomic<bool> comm_quit{false};
  std::thread comm_worker;
  if (comm_thread) {
    mpi_lock.lock();
    comm_worker = std::thread([&]() {
      while (!comm_quit.load()) {
        {
          const std::lock_guard<std::mutex> g(mpi_mutex());
          scheduler->progress();
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    });
  }
  report.timer.start("render");
  for (;;) {
    if (should_stop()) {
      stopping = true;
      break;
    }
    if (!scheduler->next(ranges, should_stop)) {
      stopping = !stop_reason.empty();
      break;
    }
    list.clear();
    for (const PosRange& r : ranges)
      for (std::int64_t pos = r.begin; pos < r.end; ++pos) list.push_back(order.pixel(pos));
    const double t0 = report.timer.now();
    if (comm_thread) mpi_lock.unlock();
    renderer.render_pixels(list, out);
    if (comm_thread) mpi_lock.lock();
    const double t1 = report.timer.now();
    last_dispatch = t1 - t0;
    std::int64_t chunk_rays = 0;
    for (const PixelResult& p : out) {
      chunk_rays += p.rays;
      tests += static_cast<std::int64_t>(p.tests);
    }
    rays += chunk_rays;
    rendered += static_cast<std::int64_t>(out.size());
    records.push_back({t0, t1, static_cast<std::int64_t>(out.size()), chunk_rays,
                       static_cast<std::int64_t>(records.size())});
    sink.add(ranges, out, t1);
    sink.poll(t1);
    if (comm.is_root()) {
      if (checkpointing && t1 - last_checkpoint >= opt.checkpoint_interval) {
        report.timer.start("checkpoint");
        write_checkpoint(opt.checkpoint, {s.width, s.height, signature, done, frame_pixels});
        report.timer.stop();
        last_checkpoint = report.timer.now();
      }
      if (progress_line.enabled()) {
        double probe = 0;
        for (const std::int64_t p : list) probe += cost.at(p);
        pixel_cost.add(t1 - t0, static_cast<double>(list.size()), probe);
      }
      if (progress_line.due()) {
        const double merged = static_cast<double>(sink.merged());
        const double total = static_cast<double>(order.size());
        progress_line.update(merged, total,
                             pixel_cost.cost(merged, merged_cost(cost, done) - restart_cost),
                             pixel_cost.cost(total, total_probe_cost));
      }
    }
  }
  const double loop_end = report.timer.now();
  report.timer.stop();
  if (comm_thread) {
    comm_quit = true;
    mpi_lock.unlock();
    comm_worker.join();
  }
  report.timer.start("gather");
  scheduler->finish(stopping);
  sink.finish();
  report.timer.stop();
  const double render_end = comm.max(loop_end);
  {
    // Report the reason any rank stopped for (rank 0 may only have heard that a peer stopped):
    // the gravest that some rank saw (signal, then time limit, then --stop-after-chunks).
    static const char* const kReasons[] = {"", "--stop-after-chunks", "time limit", "stop signal"};
    int code = 0;
    for (int k = 1; k < 4; ++k)
      if (stop_reason == kReasons[k]) code = k;
    code = static_cast<int>(comm.max(static_cast<double>(code)));
    if (code > 0) stop_reason = kReasons[code];
  }
  // A rank's completion is the end of its last dispatch (the paper's per-rank
  // completion plots); idle is the rest of the render span: waiting for work, for
  // messages, for the termination round and for the slowest rank.
  const double completion = records.empty() ? render_start : records.back().end;
  double busy = 0;
  for (const BandRecord& r : records) busy += r.end - r.start;
  const double idle = std::max(0.0, (render_end - render_start) - busy);
  const std::int64_t missing =
      comm.sum(comm.is_root() ? order.size() - sink.merged() : std::int64_t(0));
  progress_line.finish(static_cast<double>(order.size() - missing),
                       static_cast<double>(order.size()));
  if (missing > 0 && comm.is_root() && checkpointing) {
    report.timer.start("checkpoint");
    write_checkpoint(opt.checkpoint, {s.width, s.height, signature, done, frame_pixels});
    report.timer.stop();
  }

  const std::int64_t total_rays = comm.sum(rays);
  const std::int64_t total_tests = comm.sum(tests);
  const double render_time = render_end - render_start;
  report.fom_name = "ray_rate";
  report.fom_unit = "Mrays/s";
  report.fom_value = render_time > 0 ? static_cast<double>(total_rays) / render_time * 1e-6 : 0.0;
  if (comm.is_root()) {
    std::printf("  render: %.3f s (max over ranks), %lld rays, %.3f Mrays/s\n", render_time,
                static_cast<long long>(total_rays), report.fom_value);
    if (s.stats && total_rays > 0) {
      const double per_ray = static_cast<double>(total_tests) / static_cast<double>(total_rays);
      std::printf(
          "  stats: %.2f ray-triangle tests per ray; brute force %zu (%.5f of brute force, "
          "1/%.0f)\n",
          per_ray, ds.triangles, per_ray / static_cast<double>(ds.triangles),
          static_cast<double>(ds.triangles) / std::max(per_ray, 1e-9));
    }
  }
  report.scene["rays"] = total_rays;
  if (s.stats)
    report.scene["tests_per_ray"] = total_rays > 0 ? double(total_tests) / double(total_rays) : 0.0;

  if (missing > 0) {
    if (comm.is_root())
      std::fprintf(stderr, "sketchtrace: stopped (%s) with %lld of %zu pixels missing; %s\n",
                   stop_reason.empty() ? "peer stopped" : stop_reason.c_str(),
                   static_cast<long long>(missing), pixels_total,
                   checkpointing ? ("restart with --restart " + opt.checkpoint).c_str()
                                 : "no --checkpoint given, the work is lost");
    report.fom_name = "pixels_missing";
    report.fom_unit = "pixels";
    report.fom_value = static_cast<double>(missing);
    if (!opt.timings.empty())
      write_timings_file(opt.timings, comm, report, records, completion, idle, rays, rendered,
                         opt.input, to_string(balance));
    report.finish(comm, opt.summary);
    return kExitCheckpointed;
  }

  int exit_code = kExitOk;
  if (comm.is_root()) {
    report.timer.start("write");
    report.verification_hash = hash_pixels(frame_pixels, 0, s.needs_aov_pass());
    // Image statistics for the stability checks (issue 7): a non-finite pixel is a bug.
    double sum[3] = {0, 0, 0}, peak = 0;
    std::int64_t nonfinite = 0;
    for (const PixelResult& p : frame_pixels) {
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
    const double inv = 1.0 / std::max<double>(1.0, double(frame_pixels.size() - nonfinite));
    report.scene["image"] = {{"mean_rgb", {sum[0] * inv, sum[1] * inv, sum[2] * inv}},
                             {"max", peak},
                             {"nonfinite_pixels", nonfinite}};
    std::printf("  image: mean %.6g %.6g %.6g, max %.6g, %lld non-finite pixels\n", sum[0] * inv,
                sum[1] * inv, sum[2] * inv, peak, static_cast<long long>(nonfinite));
    if (!opt.output.empty() || !opt.reference.empty()) {
      const Frame frame = assemble_frame(frame_pixels, s.width, s.height);
      if (!opt.output.empty())
        for (const std::string& f : write_frame(opt.output, frame, s))
          std::printf("  wrote %s\n", f.c_str());
      if (!opt.reference.empty()) {
        const ImageErrors e = compare_images(frame.color, read_image(opt.reference), opt.reference);
        report.errors = {{"reference", opt.reference},
                         {"rmse", e.rmse},
                         {"rel_mse", e.rel_mse},
                         {"psnr", e.psnr},
                         {"ssim", e.ssim},
                         {"max_rmse", opt.max_rmse}};
        const bool ok = opt.max_rmse < 0 || e.rmse <= opt.max_rmse;
        std::printf(
            "  reference %s: RMSE %.6g, relative MSE %.6g, PSNR %.2f dB, SSIM %.5f (RMSE limit %g) "
            "%s\n",
            opt.reference.c_str(), e.rmse, e.rel_mse, e.psnr, e.ssim, opt.max_rmse,
            ok ? "PASS" : "FAIL");
        if (!ok) exit_code = kVerificationFailed;
      }
    }
    report.timer.stop();
  } else {
    report.timer.start("write");
    report.timer.stop();
  }
  if (!opt.timings.empty())
    write_timings_file(opt.timings, comm, report, records, completion, idle, rays, rendered,
                       opt.input, to_string(balance));
  report.finish(comm, opt.summary);
  return static_cast<int>(comm.max(static_cast<double>(exit_code)));
}

}  // namespace
}  // namespace rtmini::sketch

int main(int argc, char** argv) {
  return rtmini::app_main("sketchtrace", argc, argv, rtmini::sketch::run);
}
