#pragma once
// `bake render MAP.bs ...`: the offline renderer of baked maps (issue 9). bake's main registers
// the options on its `render` subcommand and runs the mode with the parsed values.
#include <CLI/CLI.hpp>
#include <string>

#include "render_map.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini {

struct RenderOptions {
  std::string input, output, scene, summary, timings, reference;
  std::string camera_pos, look_at, up, background;
  double fov = 45.0;
  double max_rmse = -1.0;
  std::string lookup = "grid", bvh = "sah";
  bake::RenderParams params;
  bool progress = false;
  std::int64_t max_memory = 0;  // --max-memory (report/memory_check.hpp)
};

// Registers every `bake render` option on `app` (the shared group is added by the caller).
void add_render_options(CLI::App& app, RenderOptions& o);

// Checks the parsed options (`app` tells which were given) and renders. Collective.
int run_render_mode(Communicator& comm, RenderOptions o, const CLI::App& app);

}  // namespace rtmini
