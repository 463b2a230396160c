#pragma once
// sketchtrace's command line (CLI11). Render parameters given here override the
// scene file's [settings]/[camera]/ambient; camera flags apply after the default
// framing, so `--fov 30` on a bare mesh keeps the framed position.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "render_settings.hpp"

namespace rtmini::sketch {

struct RunOptions {
  std::string input;
  std::string output;
  std::string summary, timings, checkpoint, restart;
  double checkpoint_interval = 60.0;  // seconds between checkpoint writes
  int stop_after_chunks = -1;         // testing: stop as on SIGTERM after this many dispatches
  double time_limit_minutes = 0;      // stop in time to checkpoint (0 = no limit)
  std::string balance = "static";     // load-balancing strategy (schedule.hpp)
  std::string cost_map;               // keep/reuse the probed cost map here
  bool progress = false;
  bool comm_thread = true;      // bargain/steal: answer peers from a thread while rendering
  std::string reference;        // compare the colour image with this image (linear RMSE)
  double max_rmse = -1.0;       // exit 1 when the RMSE exceeds this (when >= 0)
  std::int64_t max_memory = 0;  // --max-memory (report/memory_check.hpp): 0 = the machine's
};

class CliOverrides {
 public:
  // Registers every option on `app` but the shared group (report/common_options.hpp);
  // values land in this object and in `run`.
  void add_to(CLI::App& app, RunOptions& run);
  // Applies the render options the user gave (all but the camera ones).
  void apply(RenderSettings& s) const;
  // Applies the camera options (after the scene's default camera is known).
  void apply_camera(RenderSettings& s) const;

 private:
  CLI::App* app_ = nullptr;
  int width_ = 0, height_ = 0, spp_ = 0, shadow_samples_ = 0, bounces_ = 0, glossy_ = 0;
  int stencil_samples_ = 0, sphere_subdivisions_ = 0, chunk_pixels_ = 0, displacement_level_ = 0;
  std::string displacement_, texture_filter_;
  std::string soft_shadows_, indirect_, smooth_, bvh_, aov_, style_;
  double edge_thickness_ = 0, crease_angle_ = 0, depth_threshold_ = 0;
  std::string ambient_, background_, camera_pos_, look_at_, up_, shutter_, velocity_;
  double fov_ = 0, aperture_ = 0, focus_distance_ = 0;
  std::uint64_t seed_ = 0;
  bool stats_ = false;
  bool general_kernel_ = false;

  bool given(const char* name) const;
};

}  // namespace rtmini::sketch
