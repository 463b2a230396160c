// bake: view-dependent ray-trace maps (the baking seed's Chef and Kitchen). Parses the command
// line into a BakeConfig and dispatches: the map bake (default), --mode ao, or `bake render`.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "ao_mode.hpp"
#include "bake_config.hpp"
#include "kitchen.hpp"
#include "reference_tracer.hpp"
#include "rtmini/io/cli_values.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/report/app_main.hpp"
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

// Returns -1 to go on baking, or an exit code (--help, --version).
int parse(int argc, char** argv, BakeConfig& c, bool root) {
  CLI::App app{
      "bake: view-dependent ray-trace maps of semi-reflective scenes (.bs/.obj in, .bs/.bsb out)",
      "bake"};
  std::string lookup = "kdtree", balance = "cost", bvh_kind = "lbvh", mode = "map";
  std::string max_memory, background;
  bool version = false;
  bool no_cache = false;
  app.add_option("input", c.input, "raw Bake Shop (.bs) or OBJ/MTL scene")->required();
  app.add_option("-o,--output", c.output,
                 "baked map: .bsb = binary form, else .bs text (default: <input stem>_baked.bs)");
  app.add_option("--mode", mode, "map (default) or ao");
  app.add_option("-n,--viewpoints", c.viewpoints, "viewpoints per vertex (Fibonacci sphere)");
  app.add_option("-k,--iterations", c.iterations, "reflection iterations after the base map");
  app.add_option("-s,--shadow-samples", c.shadow_samples, "stratified shadow samples per light");
  app.add_option("--gather-rays", c.gather_rays, "diffuse gather rays per vertex (0 = seed model)");
  app.add_option("--seed", c.seed, "random seed");
  app.add_option("--summary", c.summary, "JSON run summary");
  app.add_option("--timings", c.timings, "per-rank timings (HDF5)");
  app.add_option("--checkpoint", c.checkpoint, "HDF5 checkpoint written after each iteration");
  app.add_option("--restart", c.restart, "resume from this checkpoint");
  app.add_option("--reference", c.reference,
                 "baked .bs map of the same scene and N to compare with (errors in the summary)");
  app.add_flag("--trace-reference", c.trace_reference,
               "write the reference map instead: every colour traced directly (K mirror bounces, "
               "no map lookups)");
  app.add_option("--lookup", lookup, "viewpoint lookup: kdtree or sf (spherical Fibonacci)");
  app.add_option("--balance", balance,
                 "batch cuts: cost (default: equal work), static (equal vertex counts) or "
                 "spatial (blocks in Morton order, equal work per rank)");
  app.add_option("--batch-size", c.batch_size, "vertices per batch (default vertices/ranks)");
  app.add_option("--max-memory", max_memory, "refuse runs estimated above this (e.g. 2G)");
  app.add_option("--time-limit", c.time_limit_minutes,
                 "minutes; checkpoint and exit 4 if the next iteration would not fit");
  app.add_option("--background", background, "colour of rays that leave the scene, r,g,b");
  app.add_option("--bvh", bvh_kind, "lbvh or sah");
  app.add_flag("--no-hit-cache", no_cache, "re-trace mirror rays every iteration");
  // Measurement only: store N colours for view-independent vertices too (same colours).
  app.add_flag("--all-view-dependent", c.all_view_dependent)->group("");
  app.add_flag("--progress", c.progress, "progress on stderr");
  app.add_flag("--version", version, "print version and exit");
  app.add_option("--stop-after-iteration", c.stop_after_iteration)->group("");  // test hook
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--version") == 0) {
      if (root) std::cout << build_banner() << "\n";
      return kExitOk;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    if (root) std::cout << app.help();
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    throw InputError(e.what());
  }
  if (mode != "map") throw InputError("--mode must be map or ao (got '" + mode + "')");
  if (lookup == "kdtree")
    c.lookup = Lookup::kKdTree;
  else if (lookup == "sf")
    c.lookup = Lookup::kSphericalFibonacci;
  else
    throw InputError("--lookup must be kdtree or sf (got '" + lookup + "')");
  if (balance == "static")
    c.balance = Balance::kStatic;
  else if (balance == "cost")
    c.balance = Balance::kCost;
  else if (balance == "spatial")
    c.balance = Balance::kSpatial;
  else
    throw InputError("--balance must be static, cost or spatial (got '" + balance + "')");
  if (bvh_kind != "lbvh" && bvh_kind != "sah")
    throw InputError("--bvh must be lbvh or sah (got '" + bvh_kind + "')");
  c.sah = bvh_kind == "sah";
  c.cache_hits = !no_cache;
  require_at_least("--viewpoints", c.viewpoints, 1);
  require_at_least("--iterations", c.iterations, 0);
  require_at_least("--shadow-samples", c.shadow_samples, 1);
  require_at_least("--gather-rays", c.gather_rays, 0);
  require_at_least("--batch-size", c.batch_size, std::int64_t(0));
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
  if (!max_memory.empty()) c.max_memory = parse_byte_size("--max-memory", max_memory);
  if (!background.empty()) c.background = parse_color(background);
  if (c.output.empty()) c.output = default_output(c.input);
  return -1;
}

bool wants_mode(int argc, char** argv, const char* mode) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--mode") == 0 && i + 1 < argc && std::strcmp(argv[i + 1], mode) == 0)
      return true;
    if (std::strncmp(argv[i], "--mode=", 7) == 0 && std::strcmp(argv[i] + 7, mode) == 0)
      return true;
  }
  return false;
}

}  // namespace
}  // namespace rtmini::bake

int main(int argc, char** argv) {
  return rtmini::app_main("bake", argc, argv, [](rtmini::Communicator& comm, int ac, char** av) {
    using namespace rtmini;
    if (ac > 1 && std::strcmp(av[1], "render") == 0) {
#ifdef RTMINI_BAKE_HAVE_RENDER
      return run_render_mode(comm, ac, av);
#else
      throw InputError("`bake render` is not part of this build (miniapps/bake/render missing)");
#endif
    }
    if (bake::wants_mode(ac, av, "ao")) {
      return run_ao_mode(comm, ac, av);
    }
    bake::BakeConfig config;
    const int early = bake::parse(ac, av, config, comm.is_root());
    if (early >= 0) return early;
    return bake::run_bake(comm, config);
  });
}
