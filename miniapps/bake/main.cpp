// bake: view-dependent ray-trace maps (the baking seed's Chef and Kitchen). One CLI11 app with
// the map bake's options at the top and two subcommands, `bake ao` and `bake render`; the old
// spelling `bake --mode ao` is rewritten to `bake ao` before parsing.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "ao_mode.hpp"
#include "bake_config.hpp"
#include "kitchen.hpp"
#include "node_share.hpp"
#include "reference_tracer.hpp"
#include "rtmini/io/cli_values.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/version.hpp"
#ifdef RTMINI_BAKE_HAVE_RENDER
#include "render/render_mode.hpp"
#endif

namespace rtmini::bake {
namespace {

Vec3f parse_color(const std::string& text) {
  std::istringstream in(text);
  float v[3];
  char sep;
  if (!(in >> v[0] >> sep >> v[1] >> sep >> v[2]) || !in.eof() || !std::isfinite(v[0]) ||
      !std::isfinite(v[1]) || !std::isfinite(v[2]) || v[0] < 0 || v[1] < 0 || v[2] < 0)
    throw InputError("--background must be r,g,b with finite values >= 0 (got '" + text + "')");
  return {v[0], v[1], v[2]};
}

template <class T>
void require_at_least(const char* name, T value, T lo) {
  if (value < lo)
    throw InputError(std::string(name) + " must be >= " + std::to_string(lo) + " (got " +
                     std::to_string(value) + ")");
}

std::string default_output(const std::string& input) {
  std::string stem = input.substr(input.find_last_of('/') + 1);
  const std::size_t dot = stem.find_last_of('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  return stem + "_baked.bs";
}

// The map bake's options and the values that need converting after parsing.
struct MapCli {
  std::string lookup = "grid", balance = "cost", bvh_kind = "lbvh", mode = "map";
  std::string exchange = "changed";
  std::string node_sharing = "off";
  std::string node_map = "on";
  std::string directions = "sphere";
  std::string background;
  bool no_cache = false;
  void add_to(CLI::App& app, BakeConfig& c);
  void finish(BakeConfig& c) const;
  void finish_directions(BakeConfig& c) const;
};

void MapCli::add_to(CLI::App& app, BakeConfig& c) {
  app.add_option("input", c.input, "raw Bake Shop (.bs) or OBJ/MTL scene");
  app.add_option("-o,--output", c.output,
                 "baked map: .bsb = binary form, else .bs text (default: <input stem>_baked.bs)");
  app.add_option("--mode", mode, "map (`--mode ao` is the old spelling of `bake ao`)")
      ->check(CLI::IsMember({"map"}));
  app.add_option("-n,--viewpoints", c.viewpoints, "viewpoints per vertex (Fibonacci sphere)");
  app.add_option("-k,--iterations", c.iterations, "reflection iterations after the base map");
  app.add_option("-s,--shadow-samples", c.shadow_samples, "stratified shadow samples per light");
  app.add_option("--gather-rays", c.gather_rays, "diffuse gather rays per vertex (0 = seed model)");
  app.add_option("--seed", c.seed, "random seed");
  app.add_option("--checkpoint", c.checkpoint, "HDF5 checkpoint written after each iteration");
  app.add_option("--restart", c.restart, "resume from this checkpoint");
  app.add_option("--reference", c.reference,
                 "baked .bs map of the same scene and N to compare with (errors in the summary)");
  app.add_flag("--trace-reference", c.trace_reference,
               "write the reference map instead: every colour traced directly (K mirror bounces, "
               "no map lookups)");
  app.add_option("--lookup", lookup,
                 "viewpoint lookup: grid (default), kdtree or sf (spherical Fibonacci); the same "
                 "map from each");
  app.add_option("--balance", balance,
                 "batch cuts: cost (equal work, counted at the traced mirror hits), static (equal "
                 "vertex counts), spatial (blocks in Morton order, equal colours per rank) or "
                 "pilot (equal work as a pilot of 8 rays per vertex estimates it) or measured "
                 "(cost, then recut once by each rank's measured time of the first mirror "
                 "iteration: the ownership, not the output, varies from run to run)");
  app.add_option("--exchange", exchange,
                 "halo exchanges after the first: changed (only colours that changed since the "
                 "last one; same output) or full (every halo colour every time)");
  app.add_option("--node-sharing", node_sharing,
                 "what the ranks of a node share through MPI shared memory (host backends; same "
                 "output): scene (one copy of the mesh and BVH per node), work (each other's "
                 "unfinished pieces of the mirror iterations), on (both) or off (default)");
  app.add_option("--node-map", node_map,
                 "with --node-sharing work or on and every rank on one node: on (default), the "
                 "node keeps one map in shared memory that every rank reads (no halo, no "
                 "exchange), or off, each rank its part and a halo (as across nodes); same output");
  app.add_option("--batch-size", c.batch_size, "vertices per batch (0 = vertices/ranks)");
  app.add_option("--max-colors", c.color_cap,
                 "most colours a batch (a rank) may own, as a multiple of the mean, under the "
                 "cost cuts: a rank's memory grows with them; a rank may own several ranges to "
                 "fit the cap and the cost (0 = no cap; default 1.1)");
  app.add_option("--time-limit", c.time_limit_minutes,
                 "minutes; checkpoint and exit 4 if the next iteration would not fit (0 = none)");
  app.add_option("--background", background, "colour of rays that leave the scene, r,g,b");
  app.add_option("--bvh", bvh_kind, "lbvh, ploc or sah");
  app.add_flag("--no-hit-cache", no_cache, "re-trace mirror rays every iteration");
  app.add_flag("--two-sided", c.two_sided,
               "mirrors reflect on both sides (default: one-sided, a viewpoint behind a vertex is "
               "folded to the front)");
  app.add_option("--directions", directions,
                 "viewpoints a reflective vertex stores: sphere (N shared directions) or "
                 "hemisphere (the N/2 on its front side: half the colours and rays; one-sided "
                 "mirrors, even N)");
  // Measurement only: store N colours for view-independent vertices too (same colours).
  app.add_flag("--all-view-dependent", c.all_view_dependent)->group("");
  app.add_option("--stop-after-iteration", c.stop_after_iteration)->group("");  // test hook
  app.add_option("--recut-test-skew", c.recut_test_skew)->group("");            // test hook
  app.add_option("--share-test-delay", c.share_test_delay)->group("");          // test hook
}

// A hemisphere map relies on the fold of one-sided mirrors (a viewpoint behind a vertex has the
// colour of its mirror image in front), and stores the front half of an even N exactly.
void MapCli::finish_directions(BakeConfig& c) const {
  if (directions == "sphere") return;
  if (directions != "hemisphere")
    throw InputError("--directions must be sphere or hemisphere (got '" + directions + "')");
  c.directions = Directions::kHemisphere;
  if (c.two_sided)
    throw InputError(
        "--directions hemisphere needs one-sided mirrors: with --two-sided a viewpoint behind a "
        "vertex reflects on its back, so both hemispheres hold their own colours");
  if (c.viewpoints < 2 || c.viewpoints % 2 != 0)
    throw InputError("--directions hemisphere needs an even --viewpoints >= 2 (got " +
                     std::to_string(c.viewpoints) + "): it stores the front N/2 of them");
  if (c.trace_reference)
    throw InputError(
        "--trace-reference writes a full-sphere map (the reference of every layout): drop "
        "--directions hemisphere");
  if (c.all_view_dependent)
    throw InputError("--all-view-dependent measures the sphere layout only");
}

void MapCli::finish(BakeConfig& c) const {
  if (c.input.empty()) throw InputError("input is required (or a subcommand: ao, render)");
  if (mode != "map") throw InputError("--mode must be map or ao (got '" + mode + "')");
  if (exchange != "changed" && exchange != "full")
    throw InputError("--exchange must be changed or full (got '" + exchange + "')");
  c.changed_exchanges = exchange == "changed";
  if (!parse_lookup(lookup, c.lookup))
    throw InputError("--lookup must be grid, kdtree or sf (got '" + lookup + "')");
  if (balance == "static")
    c.balance = Balance::kStatic;
  else if (balance == "cost")
    c.balance = Balance::kCost;
  else if (balance == "spatial")
    c.balance = Balance::kSpatial;
  else if (balance == "pilot")
    c.balance = Balance::kPilot;
  else if (balance == "measured")
    c.balance = Balance::kMeasured;
  else
    throw InputError("--balance must be static, cost, spatial, pilot or measured (got '" + balance +
                     "')");
  if (!bvh::parse_build_quality(bvh_kind, c.bvh))
    throw InputError("--bvh must be lbvh, ploc or sah (got '" + bvh_kind + "')");
  finish_directions(c);
  c.cache_hits = !no_cache;
  if (node_sharing != "on" && node_sharing != "off" && node_sharing != "scene" &&
      node_sharing != "work")
    throw InputError("--node-sharing must be off, scene, work or on (got '" + node_sharing + "')");
  c.share_scene = node_sharing == "scene" || node_sharing == "on";
  c.share_work = node_sharing == "work" || node_sharing == "on";
  if (node_map != "on" && node_map != "off")
    throw InputError("--node-map must be on or off (got '" + node_map + "')");
  c.node_map = node_map == "on";
  if (c.share_work && c.balance == Balance::kMeasured)
    throw InputError("--node-sharing " + node_sharing +
                     " takes no --balance measured: the recut moves vertices between ranks after "
                     "iteration 1, where shared work balances within each iteration instead");
  if ((c.share_scene || c.share_work) && !node_sharing_possible())
    throw InputError("--node-sharing " + node_sharing +
                     " needs a host backend: this build keeps the scene and the map in device "
                     "memory (one rank per GPU has nothing to share)");
  require_at_least("--viewpoints", c.viewpoints, 1);
  require_at_least("--iterations", c.iterations, 0);
  require_at_least("--shadow-samples", c.shadow_samples, 1);
  require_at_least("--gather-rays", c.gather_rays, 0);
  require_at_least("--batch-size", c.batch_size, std::int64_t(0));
  if (c.color_cap != 0 && !(c.color_cap >= 1))
    throw InputError("--max-colors must be 0 or >= 1 (got " + std::to_string(c.color_cap) + ")");
  if (c.shadow_samples > (1 << 24))
    throw InputError("--shadow-samples must be <= 16777216 (got " +
                     std::to_string(c.shadow_samples) + ")");
  if (static_cast<std::int64_t>(c.gather_rays) * (c.iterations + 1) > (1 << 30))
    throw InputError("--gather-rays x --iterations is too large for the random streams");
  if (!(c.time_limit_minutes >= 0))
    throw InputError("--time-limit must be >= 0 minutes (got " +
                     std::to_string(c.time_limit_minutes) + ")");
  if (c.trace_reference) {
    if (c.gather_rays > 0)
      throw InputError("--trace-reference models no diffuse gather (use --gather-rays 0)");
    if (!c.checkpoint.empty() || !c.restart.empty())
      throw InputError("--trace-reference takes no --checkpoint or --restart");
    if (c.iterations > kMaxReferenceIterations)
      throw InputError("--trace-reference needs --iterations <= " +
                       std::to_string(kMaxReferenceIterations) + " (up to 3^K rays per colour)");
    c.cache_hits = false;
  }
  if (!background.empty()) c.background = parse_color(background);
  if (c.output.empty()) c.output = default_output(c.input);
}

// The old spellings `--mode ao` / `--mode=ao` anywhere on the line become the `ao` subcommand.
std::vector<char*> with_mode_alias(int argc, char** argv) {
  static char ao_word[] = "ao";
  std::vector<char*> args{argv[0]};
  bool ao = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--mode") == 0 && i + 1 < argc &&
        std::strcmp(argv[i + 1], "ao") == 0) {
      ao = true;
      ++i;
    } else if (std::strcmp(argv[i], "--mode=ao") == 0) {
      ao = true;
    } else {
      args.push_back(argv[i]);
    }
  }
  if (ao) args.insert(args.begin() + 1, ao_word);
  return args;
}

int run(Communicator& comm, int argc, char** argv) {
  CLI::App app{
      "bake: view-dependent ray-trace maps of semi-reflective scenes (.bs/.obj in, .bs/.bsb out)",
      "bake"};
  CommonOptions common;
  add_common_options(app, common);
  app.require_subcommand(0, 1);
  BakeConfig config;
  MapCli map;
  map.add_to(app, config);

  CLI::App* ao_app =
      app.add_subcommand("ao", "bake ao: ambient-occlusion baking onto mesh vertices");
  add_common_options(*ao_app, common);
  ao::AoOptions ao_options;
  ao::AoCli ao_cli;
  ao_cli.add_to(*ao_app, ao_options);

  CLI::App* render_app =
      app.add_subcommand("render",
                         "bake render: offline renderer of baked maps (per pixel: the visible "
                         "face, each corner's colour looked "
                         "up at the camera-ray direction, mixed barycentrically)");
  add_common_options(*render_app, common);
#ifdef RTMINI_BAKE_HAVE_RENDER
  RenderOptions render_options;
  add_render_options(*render_app, render_options);
#endif

  std::vector<char*> args = with_mode_alias(argc, argv);
  if (const auto done = parse_command_line(app, static_cast<int>(args.size()), args.data(), common,
                                           comm.is_root()))
    return *done;
  const bool progress = progress_wanted(common);
  if (*ao_app) {
    ao_cli.finish(ao_options);
    ao_options.summary = common.summary;
    ao_options.timings = common.timings;
    ao_options.progress = progress;
    ao_options.max_memory = common.memory_limit();
    return run_ao_mode(comm, ao_options);
  }
  if (*render_app) {
#ifdef RTMINI_BAKE_HAVE_RENDER
    render_options.summary = common.summary;
    render_options.timings = common.timings;
    render_options.progress = progress;
    render_options.max_memory = common.memory_limit();
    return run_render_mode(comm, render_options, *render_app);
#else
    throw InputError("`bake render` is not part of this build (miniapps/bake/render missing)");
#endif
  }
  map.finish(config);
  config.max_memory = common.memory_limit();
  config.summary = common.summary;
  config.timings = common.timings;
  config.progress = progress;
  return run_bake(comm, config);
}

}  // namespace
}  // namespace rtmini::bake

int main(int argc, char** argv) { return rtmini::app_main("bake", argc, argv, rtmini::bake::run); }
