// sketchtrace: the hand-drawn seed's ray tracer with the distribution seed's
// effects, as a Kokkos + MPI mini-app. Rank r renders rows [r H / P, (r+1) H / P)
// (the seed's naive split, §3.2) through the chunk interface that load balancers
// reuse; rank 0 gathers the pixels and writes the image, AOVs and post-process.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "checkpoint.hpp"
#include "cli_options.hpp"
#include "frame_output.hpp"
#include "render_scene.hpp"
#include "renderer.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/timings.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"

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
  p["camera"] = {{"position", vec_json(s.camera.position)},  {"look_at", vec_json(s.camera.look_at)},
                 {"up", vec_json(s.camera.up)},              {"fov_deg", s.camera.fov_deg},
                 {"aperture", s.camera.aperture},            {"focus_distance", s.camera.focus_distance},
                 {"shutter", {s.camera.shutter_open, s.camera.shutter_close}},
                 {"velocity", vec_json(s.camera.velocity)}};
  p["seed"] = s.seed;
  p["bvh"] = bvh::to_string(s.bvh);
  p["aov"] = s.aov;
  p["style"] = s.style;
  return p;
}

std::string extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// Rows [begin, end) of this rank not already done, cut into bands of at most band_rows.
std::vector<PixelChunk> my_bands(int rank, int ranks, const RenderSettings& s, const std::vector<std::uint8_t>& done) {
  const int begin = static_cast<int>(static_cast<long long>(rank) * s.height / ranks);
  const int end = static_cast<int>(static_cast<long long>(rank + 1) * s.height / ranks);
  std::vector<PixelChunk> bands;
  int y = begin;
  while (y < end) {
    if (!done.empty() && done[y]) {
      ++y;
      continue;
    }
    int h = 0;
    while (y + h < end && h < s.band_rows && (done.empty() || !done[y + h])) ++h;
    bands.push_back({0, y, s.width, h});
    y += h;
  }
  return bands;
}

struct BandRecord {
  double start, end;
  std::int64_t pixels, rays;
  std::int64_t iteration;
};

void write_timings_file(const std::string& path, const Communicator& comm, const RunReport& report,
                        const std::vector<BandRecord>& bands, double completion, double render_end,
                        std::int64_t rays, std::int64_t pixels, const std::string& scene_name) {
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
  const std::vector<double> mine_d = {completion, render_end - completion};
  const std::vector<std::int64_t> mine_i = {comm.messages_sent(), comm.bytes_sent(), rays, pixels};
  const auto all_d = comm.gatherv(mine_d);
  const auto all_i = comm.gatherv(mine_i);
  if (!comm.is_root()) return;
  TimingsData t;
  t.app = "sketchtrace";
  t.version = version_string();
  t.git_hash = git_hash();
  t.backend = compat::backend_name();
  t.strategy = "static";
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
  CLI::App app{"sketchtrace: distribution ray tracer with a hand-drawn post-process"};
  RunOptions opt;
  CliOverrides cli;
  cli.add_to(app, opt);
  app.set_version_flag("--version", build_banner());
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {
      if (comm.is_root()) app.exit(e);
      return kExitOk;
    }
    throw InputError(std::string("usage: ") + e.what() + " (see --help)");
  }

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
  validate_settings(s, "command line");
  if (!opt.output.empty()) check_output_path(opt.output);
#ifndef RTMINI_SKETCH_HAVE_NPR
  if (s.style != "none") throw InputError("--style " + s.style + ": this build has no hand-drawn passes");
#endif
  if (opt.stop_after_bands >= 0 && opt.checkpoint.empty())
    throw InputError("--stop-after-bands needs --checkpoint");
  const HostScene scene = build_scene(opt.input, desc.get(), s);
  cli.apply_camera(s);
  validate_settings(s, "command line");
  report.timer.stop();

  report.parameters = parameters_json(s);
  report.parameters["band_rows"] = s.band_rows;
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
  if (comm.is_root()) {
    const double frame_bytes = static_cast<double>(pixels_total) * (sizeof(PixelResult) + 11 * sizeof(float));
    std::printf("%s\n", build_banner().c_str());
    std::printf("sketchtrace: input %s, output %s\n", opt.input.c_str(),
                opt.output.empty() ? "(none)" : opt.output.c_str());
    std::printf("  parameters: %s\n", report.parameters.dump().c_str());
    std::printf("  scene: %s\n", report.scene.dump().c_str());
    std::printf("  kernel features: %s, ranks %d, threads per rank %d\n", feature_names(renderer.features()).c_str(),
                comm.size(), compat::concurrency());
    std::printf("  memory estimate: scene %.1f MiB per rank, frame %.1f MiB on rank 0\n",
                static_cast<double>(ds.bytes) / 1048576.0, frame_bytes / 1048576.0);
    std::fflush(stdout);
  }

  // Restart: rank 0 reads the finished rows, every rank learns which rows to skip.
  std::vector<std::uint8_t> done;
  std::vector<PixelResult> frame_pixels;  // rank 0: the whole image
  if (comm.is_root()) frame_pixels.assign(pixels_total, PixelResult{});
  const std::string signature = report.parameters.dump() + "|" + opt.input;
  if (!opt.restart.empty()) {
    if (comm.is_root()) {
      Checkpoint c = read_checkpoint(opt.restart);
      if (c.width != s.width || c.height != s.height || c.signature != signature)
        throw InputError(opt.restart + ": checkpoint was written with different parameters or scene");
      done = c.row_done;
      frame_pixels = std::move(c.pixels);
    }
    comm.broadcast(done);
  }

  const std::vector<PixelChunk> bands = my_bands(comm.rank(), comm.size(), s, done);
  const bool checkpointing = !opt.checkpoint.empty();
  const bool progress = opt.progress || isatty(STDERR_FILENO);
  const int iterations = checkpointing ? static_cast<int>(comm.max(static_cast<double>(bands.size())))
                                       : static_cast<int>(bands.size());
  std::vector<BandRecord> records;
  std::vector<PixelResult> mine, band_out;
  std::vector<std::int32_t> mine_rows;
  std::int64_t rays = 0, tests = 0, rendered = 0;
  double last_checkpoint = report.timer.now();
  if (comm.is_root() && done.empty()) done.assign(s.height, 0);
  int stopped_after = -1;
  for (int it = 0; it < iterations; ++it) {
    band_out.clear();
    std::vector<std::int32_t> rows;
    if (it < static_cast<int>(bands.size())) {
      report.timer.start("render");
      const double t0 = report.timer.now();
      renderer.render({bands[it]}, band_out);
      report.timer.stop();
      std::int64_t band_rays = 0;
      for (const PixelResult& p : band_out) {
        band_rays += p.rays;
        tests += static_cast<std::int64_t>(p.tests);
      }
      rays += band_rays;
      rendered += static_cast<std::int64_t>(band_out.size());
      records.push_back({t0, report.timer.now(), static_cast<std::int64_t>(band_out.size()), band_rays, it});
      for (int y = bands[it].y0; y < bands[it].y0 + bands[it].h; ++y) rows.push_back(y);
      if (progress && comm.is_root())
        std::fprintf(stderr, "sketchtrace: rank 0 band %d/%zu done\n", it + 1, bands.size());
    }
    if (!checkpointing) {
      mine.insert(mine.end(), band_out.begin(), band_out.end());
      mine_rows.insert(mine_rows.end(), rows.begin(), rows.end());
      continue;
    }
    report.timer.start("gather");
    const auto all_rows = comm.gatherv(rows);
    const auto all_pixels = comm.gatherv(band_out);
    report.timer.stop();
    if (comm.is_root()) {
      for (std::size_t k = 0; k < all_rows.size(); ++k) {
        std::copy_n(all_pixels.begin() + static_cast<std::ptrdiff_t>(k * s.width), s.width,
                    frame_pixels.begin() + static_cast<std::ptrdiff_t>(all_rows[k]) * s.width);
        done[all_rows[k]] = 1;
      }
      const bool stop = opt.stop_after_bands >= 0 && it + 1 >= opt.stop_after_bands;
      if (stop || it + 1 == iterations || report.timer.now() - last_checkpoint >= opt.checkpoint_interval) {
        report.timer.start("checkpoint");
        write_checkpoint(opt.checkpoint, {s.width, s.height, signature, done, frame_pixels});
        report.timer.stop();
        last_checkpoint = report.timer.now();
      }
    }
    if (opt.stop_after_bands >= 0 && it + 1 >= opt.stop_after_bands) {
      stopped_after = it + 1;
      break;
    }
  }
  const double completion = report.timer.now();
  if (!checkpointing) {
    report.timer.start("gather");
    const auto all_rows = comm.gatherv(mine_rows);
    const auto all_pixels = comm.gatherv(mine);
    report.timer.stop();
    if (comm.is_root())
      for (std::size_t k = 0; k < all_rows.size(); ++k)
        std::copy_n(all_pixels.begin() + static_cast<std::ptrdiff_t>(k * s.width), s.width,
                    frame_pixels.begin() + static_cast<std::ptrdiff_t>(all_rows[k]) * s.width);
  }
  const double render_end = comm.max(completion);

  const std::int64_t total_rays = comm.sum(rays);
  const std::int64_t total_tests = comm.sum(tests);
  const double render_time = comm.max(report.timer.total("render"));
  report.fom_name = "ray_rate";
  report.fom_unit = "Mrays/s";
  report.fom_value = render_time > 0 ? static_cast<double>(total_rays) / render_time * 1e-6 : 0.0;
  if (comm.is_root()) {
    std::printf("  render: %.3f s (max over ranks), %lld rays, %.3f Mrays/s\n", render_time,
                static_cast<long long>(total_rays), report.fom_value);
    if (s.stats && total_rays > 0) {
      const double per_ray = static_cast<double>(total_tests) / static_cast<double>(total_rays);
      std::printf("  stats: %.2f ray-triangle tests per ray; brute force %zu (%.5f of brute force, 1/%.0f)\n",
                  per_ray, ds.triangles, per_ray / static_cast<double>(ds.triangles),
                  static_cast<double>(ds.triangles) / std::max(per_ray, 1e-9));
    }
  }
  report.scene["rays"] = total_rays;
  if (s.stats) report.scene["tests_per_ray"] = total_rays > 0 ? double(total_tests) / double(total_rays) : 0.0;

  if (stopped_after >= 0) {
    if (comm.is_root())
      std::fprintf(stderr, "sketchtrace: stopped after %d bands as asked; checkpoint %s\n", stopped_after,
                   opt.checkpoint.c_str());
    report.fom_name = "bands_done";
    report.fom_unit = "bands";
    report.fom_value = stopped_after;
    report.finish(comm, opt.summary);
    return kExitOk;
  }

  int exit_code = kExitOk;
  if (comm.is_root()) {
    report.timer.start("write");
    report.verification_hash = hash_pixels(frame_pixels, 0, s.needs_aov_pass());
    if (!opt.output.empty() || !opt.reference.empty()) {
      const Frame frame = assemble_frame(frame_pixels, s.width, s.height);
      if (!opt.output.empty())
        for (const std::string& f : write_frame(opt.output, frame, s)) std::printf("  wrote %s\n", f.c_str());
      if (!opt.reference.empty()) {
        const double e = rmse(frame.color, read_image(opt.reference), opt.reference);
        report.errors = {{"reference", opt.reference}, {"rmse", e}, {"max_rmse", opt.max_rmse}};
        const bool ok = opt.max_rmse < 0 || e <= opt.max_rmse;
        std::printf("  reference %s: RMSE %.6g (limit %g) %s\n", opt.reference.c_str(), e, opt.max_rmse,
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
    write_timings_file(opt.timings, comm, report, records, completion, render_end, rays, rendered, opt.input);
  report.finish(comm, opt.summary);
  return static_cast<int>(comm.max(static_cast<double>(exit_code)));
}

}  // namespace
}  // namespace rtmini::sketch

int main(int argc, char** argv) { return rtmini::app_main("sketchtrace", argc, argv, rtmini::sketch::run); }
