#include "cli_options.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "rtmini/io/cli_values.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::sketch {
namespace {

bool on_off(const std::string& flag, const std::string& text) {
  if (text == "on" || text == "true" || text == "1") return true;
  if (text == "off" || text == "false" || text == "0") return false;
  throw InputError(flag + ": expected on or off, got '" + text + "'");
}

}  // namespace

void CliOverrides::add_to(CLI::App& app, RunOptions& run) {
  app_ = &app;
  app.add_option("input", run.input, "Scene (.toml) or mesh (.obj, .bs, .gltf, .glb)")->required();
  app.add_option("-o,--output", run.output,
                 "Image: .ppm, .png (8-bit sRGB) or .exr (linear + AOVs)");
  app.add_option("--width", width_, "Image width in pixels");
  app.add_option("--height", height_, "Image height in pixels");
  app.add_option("--spp", spp_, "Anti-aliasing samples per pixel (stratified, jittered)");
  app.add_option("--soft-shadows", soft_shadows_, "on|off: area lights sampled over their area");
  app.add_option("--shadow-samples", shadow_samples_,
                 "Shadow rays per area light at the first hit and behind mirrors and clear glass");
  app.add_option("--bounces", bounces_,
                 "Secondary rays (reflection/refraction) after the camera ray");
  app.add_option("--glossy-samples", glossy_, "Glossy branches at the first hit");
  app.add_option("--indirect", indirect_, "on|off: diffuse interreflection");
  app.add_option("--edge-thickness", edge_thickness_, "Stencil ring radius h in pixels");
  app.add_option("--crease-angle", crease_angle_,
                 "degrees: faces meeting at more are not smoothed across; crease line threshold");
  app.add_option("--depth-threshold", depth_threshold_,
                 "Relative depth jump of a self-occluding silhouette");
  app.add_option("--stencil-samples", stencil_samples_, "Stencil evaluations per pixel");
  app.add_option("--sphere-subdivisions", sphere_subdivisions_, "Icosphere level of [[spheres]]");
  app.add_option("--smooth", smooth_, "on|off: interpolated vertex normals");
  app.add_option("--displacement", displacement_,
                 "parallax|tessellate|off: height fields (MTL disp) marched, displaced or ignored");
  app.add_option("--displacement-level", displacement_level_,
                 "tessellate: 2^level x 2^level cells per displaced face");
  app.add_option("--texture-filter", texture_filter_,
                 "cone|none: mip level from ray cones, or always the finest (aliases)");
  app.add_option("--ambient", ambient_, "Ambient light r,g,b");
  app.add_option("--background", background_, "Background radiance r,g,b");
  app.add_option("--camera-pos", camera_pos_, "Camera position x,y,z");
  app.add_option("--look-at", look_at_, "Camera target x,y,z");
  app.add_option("--up", up_, "Camera up vector x,y,z");
  app.add_option("--fov", fov_, "Vertical field of view in degrees");
  app.add_option("--aperture", aperture_, "Lens diameter (0 = pinhole)");
  app.add_option("--focus-distance", focus_distance_,
                 "Focal plane distance (0 = distance to look-at)");
  app.add_option("--shutter", shutter_, "Shutter interval open,close");
  app.add_option("--camera-velocity", velocity_, "Camera velocity x,y,z per unit time");
  app.add_option("--seed", seed_, "Random seed");
  app.add_option("--bvh", bvh_, "lbvh|ploc|sah");
  app.add_option("--aov", aov_, "Comma list of depth,normal,object,cost,edge");
  app.add_option("--style", style_, "Hand-drawn post-process: sketch|color-pencil|none");
  app.add_option("--chunk-pixels", chunk_pixels_, "Pixels per render dispatch (0 = auto)");
  app.add_flag("--stats", stats_, "Count ray-triangle tests per ray (vs brute force)");
  // Testing and measurement: the kernel with every feature branch, whatever the scene uses.
  app.add_flag("--general-kernel", general_kernel_)->group("");
  app.add_option("--checkpoint", run.checkpoint, "Write progress to this HDF5 file");
  app.add_option("--checkpoint-interval", run.checkpoint_interval, "Seconds between checkpoints");
  app.add_option("--restart", run.restart, "Resume from this checkpoint");
  app.add_option(
      "--stop-after-chunks", run.stop_after_chunks,
      "Testing: stop as on SIGTERM after this many dispatches per rank (checkpoint, exit 4)");
  app.add_option("--time-limit", run.time_limit_minutes,
                 "Wall-clock minutes: stop in time to checkpoint and exit 4 (0 = none)");
  app.add_option("--balance", run.balance, "static|metric|chunks|bargain|queue|steal");
  app.add_option("--cost-map", run.cost_map,
                 "Keep the probed cost map in this HDF5 file and reuse it");
  app.add_option("--comm-thread", run.comm_thread,
                 "on|off: bargain/steal answer peers from a thread while the rank renders "
                 "(default on; off progresses messages between dispatches only)")
      ->transform(CLI::Transformer(std::map<std::string, bool>{{"on", true}, {"off", false}}))
      ->capture_default_str();
  app.add_option("--reference", run.reference, "Reference image: report the linear RGB RMSE");
  app.add_option("--max-rmse", run.max_rmse, "With --reference: exit 1 when the RMSE is larger");
}

bool CliOverrides::given(const char* name) const { return app_ && app_->count(name) > 0; }

void CliOverrides::apply(RenderSettings& s) const {
  if (given("--width")) s.width = width_;
  if (given("--height")) s.height = height_;
  if (given("--spp")) s.spp = spp_;
  if (given("--soft-shadows")) s.soft_shadows = on_off("--soft-shadows", soft_shadows_);
  if (given("--shadow-samples")) s.shadow_samples = shadow_samples_;
  if (given("--bounces")) s.bounces = bounces_;
  if (given("--glossy-samples")) s.glossy_samples = glossy_;
  if (given("--indirect")) s.indirect = on_off("--indirect", indirect_);
  if (given("--edge-thickness")) s.edge_thickness = edge_thickness_;
  if (given("--crease-angle")) s.crease_angle_deg = crease_angle_;
  if (given("--depth-threshold")) s.depth_threshold = depth_threshold_;
  if (given("--stencil-samples")) s.stencil_samples = stencil_samples_;
  if (given("--sphere-subdivisions")) s.sphere_subdivisions = sphere_subdivisions_;
  if (given("--smooth")) s.smooth = on_off("--smooth", smooth_);
  if (given("--chunk-pixels")) s.chunk_pixels = chunk_pixels_;
  if (given("--displacement")) s.displacement = displacement_;
  if (given("--displacement-level")) s.displacement_level = displacement_level_;
  if (given("--texture-filter")) s.texture_filter = texture_filter_;
  if (given("--ambient")) {
    const Vec3d a = parse_vec3("--ambient", ambient_);
    if (a.x < 0 || a.y < 0 || a.z < 0) throw InputError("--ambient: must be non-negative");
    s.ambient = Vec3f(a);
  }
  if (given("--background")) {
    const Vec3d b = parse_vec3("--background", background_);
    if (b.x < 0 || b.y < 0 || b.z < 0) throw InputError("--background: must be non-negative");
    s.background = Vec3f(b);
  }
  if (given("--seed")) s.seed = seed_;
  if (given("--bvh")) {
    if (!bvh::parse_build_quality(bvh_, s.bvh))
      throw InputError("--bvh: expected lbvh, ploc or sah, got '" + bvh_ + "'");
  }
  if (given("--aov")) {
    s.aov.clear();
    std::stringstream ss(aov_);
    std::string item;
    while (std::getline(ss, item, ','))
      if (!item.empty()) s.aov.push_back(item);
  }
  if (given("--style")) {
    s.style = style_;
    std::replace(s.style.begin(), s.style.end(), '-', '_');
  }
  if (stats_) s.stats = true;
  if (general_kernel_) s.general_kernel = true;
}

void CliOverrides::apply_camera(RenderSettings& s) const {
  if (given("--camera-pos")) s.camera.position = parse_vec3("--camera-pos", camera_pos_);
  if (given("--look-at")) s.camera.look_at = parse_vec3("--look-at", look_at_);
  if (given("--up")) s.camera.up = parse_vec3("--up", up_);
  if (given("--fov")) s.camera.fov_deg = fov_;
  if (given("--aperture")) s.camera.aperture = aperture_;
  if (given("--focus-distance")) s.camera.focus_distance = focus_distance_;
  if (given("--shutter")) {
    const auto v = parse_number_list("--shutter", shutter_, 2);
    s.camera.shutter_open = v[0];
    s.camera.shutter_close = v[1];
  }
  if (given("--camera-velocity")) s.camera.velocity = parse_vec3("--camera-velocity", velocity_);
  if (length(s.camera.look_at - s.camera.position) == 0.0)
    throw InputError("camera: position and look_at coincide");
}

}  // namespace rtmini::sketch
