#pragma once
// Every render parameter of the hand-drawn seed (resolution, camera, soft shadows,
// shadow samples, bounces, anti-aliasing samples, edge thickness, ambient) and of the
// distribution ray tracer (glossy samples, aperture, focus, shutter, camera motion),
// filled from the scene file's [settings]/[camera]/ambient and then from the CLI.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/bvh/build_quality.hpp"
#include "rtmini/io/scene_file.hpp"

namespace rtmini::sketch {

struct RenderSettings {
  int width = 640;
  int height = 480;
  int spp = 1;  // anti-aliasing samples per pixel (stratified, jittered)
  bool soft_shadows = true;
  int shadow_samples = 16;  // per area light at the first hit and behind mirrors/clear glass
  int bounces = 3;          // secondary rays (reflection/refraction/diffuse) after the camera ray
  int glossy_samples = 1;   // glossy branches at the first hit
  bool indirect = false;    // diffuse interreflection (off: Whitted/Cook shading + ambient)
  double edge_thickness = 1.5;  // stencil ring radius in pixels
  double crease_angle_deg = 60.0;
  double depth_threshold = 0.1;  // relative depth jump of a self-occluding silhouette
  int stencil_samples = 4;       // stencil evaluations per pixel (anti-aliased edges)
  int sphere_subdivisions = 5;
  bool smooth = true;  // interpolated vertex normals on meshes
  Vec3f background{0.f, 0.f, 0.f};
  Vec3f ambient{0.f, 0.f, 0.f};
  CameraDesc camera;
  bool has_camera = false;
  std::uint64_t seed = 1;
  bvh::BuildQuality bvh = bvh::BuildQuality::kSah;
  std::vector<std::string> aov;  // subset of depth, normal, object, cost, edge
  std::string style = "none";    // sketch | color_pencil | none
  bool stats = false;
  bool general_kernel = false;  // testing: skip the feature specialisation (same image, slower)
  // Height fields (MTL disp): parallax | tessellate | off (displace.hpp), and the
  // tessellation's level (2^level x 2^level cells per face).
  std::string displacement = "parallax";
  int displacement_level = 6;
  // Texture filtering: "cone" (mip level from ray cones) or "none" (always level 0: aliases;
  // for measuring what the cones buy).
  std::string texture_filter = "cone";
  int chunk_pixels = 0;  // pixels per dispatch (0: auto, about 1/64 of a rank's share, 256..65536)

  bool wants_aov(const std::string& name) const;
  bool needs_edges() const { return wants_aov("edge") || style != "none"; }
  bool needs_aov_pass() const { return !aov.empty() || style != "none"; }
};

// Reads [settings] (checked against the known keys), [camera] and ambient into s.
// InputError "file:line: reason" for unknown keys, wrong types and out-of-range values.
void apply_scene_settings(const SceneDescription& scene, RenderSettings& s);

// Range checks shared by the TOML and CLI paths; `where` prefixes the message.
void validate_settings(const RenderSettings& s, const std::string& where);

}  // namespace rtmini::sketch
