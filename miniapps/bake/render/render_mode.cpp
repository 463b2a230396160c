// `bake render`: CLI, camera (flags or a sketchtrace scene's [camera]), the render, the image,
// and the comparison with a reference image. One rank renders; others only take part in the
// collective report (a full-HD frame of a baked map takes well under a second per core).
#include "render_mode.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render_map.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/cli_values.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/scene_file.hpp"
#include "rtmini/io/srgb.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/image_metrics.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"
#include "rtmini/scene/device_mesh.hpp"

namespace rtmini {
namespace {

// Exit status of a run whose image misses its --reference by more than --max-rmse.
constexpr int kExitReferenceMismatch = 1;

}  // namespace

void add_render_options(CLI::App& app, RenderOptions& o) {
  app.add_option("map", o.input, "baked map (.bs text or .bsb binary)")->required();
  app.add_option("-o,--output", o.output, "image: .png / .ppm (8-bit sRGB) or .exr (linear)");
  app.add_option("--scene", o.scene, "sketchtrace scene (.toml): take its [camera]");
  app.add_option("--camera-pos", o.camera_pos, "camera position x,y,z");
  app.add_option("--look-at", o.look_at, "camera target x,y,z");
  app.add_option("--up", o.up, "camera up vector x,y,z");
  app.add_option("--fov", o.fov, "vertical field of view in degrees (default 45)");
  app.add_option("--width", o.params.width, "image width in pixels (default 640)");
  app.add_option("--height", o.params.height, "image height in pixels (default 480)");
  app.add_option("--spp", o.params.spp,
                 "camera rays per pixel: 1 = pixel centre, more = stratified jitter");
  app.add_option("--background", o.background, "colour of pixels that miss the map, r,g,b");
  app.add_option("--seed", o.params.seed, "random seed of the pixel jitter");
  app.add_option("--lookup", o.lookup, "viewpoint lookup: grid (default), kdtree or sf");
  app.add_option("--bvh", o.bvh, "sah (default), lbvh or ploc");
  app.add_option("--reference", o.reference,
                 "reference image (.exr/.png/.ppm): print RMSE, relative MSE, PSNR, SSIM");
  app.add_option("--max-rmse", o.max_rmse, "with --reference: exit 1 when the RMSE is larger");
}

namespace {

// The build --bvh names (validate() has rejected any other name).
bvh::BuildQuality parsed_build_quality(const std::string& name) {
  bvh::BuildQuality q = bvh::BuildQuality::kSah;
  bvh::parse_build_quality(name, q);
  return q;
}

void validate(const RenderOptions& o, const CLI::App& app) {
  const bake::RenderParams& p = o.params;
  if (p.width < 1 || p.height < 1 || p.width > 65536 || p.height > 65536)
    throw InputError("--width/--height must be in [1, 65536] (got " + std::to_string(p.width) +
                     "x" + std::to_string(p.height) + ")");
  if (p.spp < 1 || p.spp > (1 << 20))
    throw InputError("--spp must be in [1, 1048576] (got " + std::to_string(p.spp) + ")");
  if (app.count("--fov") && !(o.fov > 0 && o.fov < 180))
    throw InputError("--fov must be in (0, 180) degrees (got " + std::to_string(o.fov) + ")");
  bake::Lookup lookup;
  if (!bake::parse_lookup(o.lookup, lookup))
    throw InputError("--lookup must be grid, kdtree or sf (got '" + o.lookup + "')");
  bvh::BuildQuality quality;
  if (!bvh::parse_build_quality(o.bvh, quality))
    throw InputError("--bvh must be lbvh, ploc or sah (got '" + o.bvh + "')");
  const std::string ext = lower_extension(o.output);
  if (!o.output.empty() && ext != ".png" && ext != ".ppm" && ext != ".exr")
    throw InputError(o.output + ": unknown image type '" + ext + "' (use .png, .ppm or .exr)");
  if (o.output.empty() && o.reference.empty())
    throw InputError("render: nothing to do: give -o IMAGE and/or --reference IMAGE");
  if (app.count("--max-rmse") && o.reference.empty())
    throw InputError("--max-rmse needs --reference");
}

void bounds_of(const Mesh& mesh, Vec3d& lo, Vec3d& hi) {
  lo = Vec3d(1e300);
  hi = Vec3d(-1e300);
  for (const Face& f : mesh.faces)
    for (int k = 0; k < f.count; ++k) {
      lo = vmin(lo, mesh.positions[f.v[k]]);
      hi = vmax(hi, mesh.positions[f.v[k]]);
    }
}

// Precedence: the flags, then the scene's [camera], then sketchtrace's default framing of the
// map's bounds (so `bake render MAP` sees what sketchtrace sees of a scene holding that mesh).
CameraDesc choose_camera(const RenderOptions& o, const CLI::App& app, const Mesh& mesh) {
  CameraDesc c;
  bool framed = true;
  if (!o.scene.empty()) {
    const SceneDescription scene = read_scene_file(o.scene);
    if (scene.has_camera) {
      c = scene.camera;
      framed = false;
      if (!(c.fov_deg > 0 && c.fov_deg < 180))
        throw InputError(o.scene, 0, "[camera] fov_deg must be in (0, 180)");
    }
  }
  if (framed) {
    Vec3d lo, hi;
    bounds_of(mesh, lo, hi);
    c = frame_bounds(lo, hi, app.count("--fov") ? o.fov : c.fov_deg);
  }
  if (app.count("--camera-pos")) c.position = parse_vec3("--camera-pos", o.camera_pos);
  if (app.count("--look-at")) c.look_at = parse_vec3("--look-at", o.look_at);
  if (app.count("--up")) c.up = parse_vec3("--up", o.up);
  if (app.count("--fov")) c.fov_deg = o.fov;
  if (!(length(c.look_at - c.position) > 0.0))
    throw InputError("camera: position and look_at coincide");
  if (!(length(cross(normalize(c.look_at - c.position), c.up)) > 1e-9))
    throw InputError("camera: up is parallel to the viewing direction (or zero)");
  return c;
}

nlohmann::json vec_json(const Vec3d& v) { return {v.x, v.y, v.z}; }

// An 8-bit reference (PNG, PPM) holds display values: clamped to [0, 1] and sRGB-quantised.
// The render goes through the same round trip before the comparison, so that an identical
// render scores 0 and the clamped highlights (the Cornell light at 17) do not dominate.
Image as_8bit_display(const Image& linear) {
  Image out = linear;
  for (float& v : out.data) v = srgb_decode_8bit(srgb_encode_8bit(v));
  return out;
}

}  // namespace

int run_render_mode(Communicator& comm, RenderOptions o, const CLI::App& app) {
  validate(o, app);
  const bool root = comm.is_root();
  if (!o.output.empty()) require_image_format(o.output);
  check_output_places(
      {{o.output, 3.0 * o.params.width * o.params.height}, {o.summary, 0}, {o.timings, 0}});
  bake::parse_lookup(o.lookup, o.params.lookup);  // validate() has rejected any other name
  if (!o.background.empty()) {
    const Vec3d b = parse_vec3("--background", o.background);
    if (b.x < 0 || b.y < 0 || b.z < 0) throw InputError("--background: must be non-negative");
    o.params.background = Vec3f(b);
  }

  RunReport report;
  report.app = "bake";
  report.timer.start("load");
  const bake::BakedMapHost map = bake::read_baked_map(o.input);
  const CameraDesc cam = choose_camera(o, app, map.mesh);
  // Every rank reads the reference, so a bad one is an input error on all ranks together.
  Image reference;
  if (!o.reference.empty()) {
    reference = read_image(o.reference);
    if (reference.width != o.params.width || reference.height != o.params.height)
      throw InputError(o.reference, 0,
                       "reference is " + std::to_string(reference.width) + "x" +
                           std::to_string(reference.height) + ", the render " +
                           std::to_string(o.params.width) + "x" + std::to_string(o.params.height) +
                           " (give the same --width/--height)");
  }
  report.timer.stop();
  const bake::RenderParams& p = o.params;
  report.parameters = {{"mode", "render"},
                       {"input", o.input},
                       {"output", o.output},
                       {"scene", o.scene},
                       {"camera_pos", vec_json(cam.position)},
                       {"look_at", vec_json(cam.look_at)},
                       {"up", vec_json(cam.up)},
                       {"fov_deg", cam.fov_deg},
                       {"width", p.width},
                       {"height", p.height},
                       {"spp", p.spp},
                       {"seed", p.seed},
                       {"background", {p.background.x, p.background.y, p.background.z}},
                       {"lookup", o.lookup},
                       {"bvh", o.bvh},
                       {"reference", o.reference},
                       {"max_rmse", o.max_rmse}};
  report.scene = {{"input", o.input},
                  {"vertices", map.mesh.positions.size()},
                  {"faces", map.mesh.faces.size()},
                  {"triangles", map.mesh.triangle_count()},
                  {"viewpoints", map.viewpoints},
                  {"directions", map.hemisphere ? "hemisphere" : "sphere"},
                  {"view_dependent_vertices", map.view_dependent_vertices},
                  {"colors", map.colors.size()}};
  // Only rank 0 renders: the map and its BVH, the image (linear floats), its 8-bit output rows
  // and, from a device, its host copy.
  MemoryNeed need;
  if (root) {
    const double pixels = static_cast<double>(p.width) * p.height;
    need.views = static_cast<double>(map.colors.size()) * sizeof(Vec3f) +
                 device_mesh_bytes(map.mesh.triangle_count(), map.mesh.positions.size()) +
                 pixels * sizeof(Vec3f);
    need.host = pixels * (4 + (compat::kDeviceMemory ? sizeof(Vec3f) : 0));
  }
  const MemoryPeak peak = require_memory(comm, need, o.max_memory);
  report.scene["memory_estimate_bytes"] = comm.max(peak.host + peak.device);
  if (root) {
    std::printf("%s\n", build_banner().c_str());
    std::printf("bake render: map %s, output %s\n", o.input.c_str(),
                o.output.empty() ? "(none)" : o.output.c_str());
    std::printf("  parameters: %s\n", report.parameters.dump().c_str());
    std::printf("  scene: %s\n", report.scene.dump().c_str());
    std::printf("  ranks %d (rank 0 renders), threads %d, memory estimate %.1f MiB peak resident\n",
                comm.size(), compat::concurrency(), (peak.host + peak.device) / 1048576.0);
    if (!o.scene.empty())
      std::printf("  camera from %s (pinhole: aperture and motion ignored)\n", o.scene.c_str());
    std::fflush(stdout);
  }

  int exit_code = kExitOk;
  report.fom_name = "ray_rate";
  report.fom_unit = "Mrays/s";
  if (root) {
    report.timer.start("upload");
    const bake::BakedMapDevice device = bake::upload_baked_map(map, parsed_build_quality(o.bvh));
    report.timer.stop();
    report.timer.start("render");
    const double t0 = report.timer.now();
    ProgressLine render_line("bake render", "px", o.progress);  // only rank 0 renders
    const bake::RenderResult r =
        bake::render_baked_map(device, make_camera(cam, p.width, p.height), p, &render_line);
    const double pixels = static_cast<double>(p.width) * p.height;
    render_line.finish(pixels, pixels);
    const double seconds = report.timer.now() - t0;
    report.timer.stop();
    report.fom_value = seconds > 0 ? static_cast<double>(r.rays) / seconds * 1e-6 : 0.0;
    report.verification_hash = r.verification;
    report.scene["rays"] = r.rays;
    report.scene["hit_fraction"] =
        r.rays > 0 ? static_cast<double>(r.hits) / static_cast<double>(r.rays) : 0.0;
    std::printf("  rendered %dx%d, %lld rays (%.1f %% hit the map) in %.3f s\n", p.width, p.height,
                static_cast<long long>(r.rays), 100.0 * report.scene["hit_fraction"].get<double>(),
                seconds);
    report.timer.start("write");
    if (!o.output.empty()) {
      write_image(o.output, r.image);
      std::printf("  wrote %s\n", o.output.c_str());
    }
    if (!o.reference.empty()) {
      const bool display = lower_extension(o.reference) != ".exr";
      const ImageErrors e =
          compare_images(display ? as_8bit_display(r.image) : r.image, reference, o.reference);
      const bool ok = o.max_rmse < 0 || e.rmse <= o.max_rmse;
      report.errors = {
          {"reference", o.reference},
          {"rmse", e.rmse},
          {"rel_mse", e.rel_mse},
          {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json("inf")},
          {"ssim", e.ssim},
          {"max_rmse", o.max_rmse},
          {"pass", ok},
          {"space", display ? "8-bit sRGB, clamped" : "linear"}};
      std::printf(
          "  reference %s: RMSE %.6g, relative MSE %.6g, PSNR %.3f dB, SSIM %.5f (limit %g) %s\n",
          o.reference.c_str(), e.rmse, e.rel_mse, e.psnr, e.ssim, o.max_rmse, ok ? "PASS" : "FAIL");
      if (!ok) exit_code = kExitReferenceMismatch;
    }
    report.timer.stop();
  }
  // Phases only: the program has no dispatch loop of its own to record.
  if (!o.timings.empty())
    write_rank_timings(o.timings, comm, report.timer, RankTimings{},
                       {"bake", "", o.input, report.parameters.dump(), {}});
  report.finish(comm, o.summary);
  return static_cast<int>(comm.max(static_cast<double>(exit_code)));
}

}  // namespace rtmini
