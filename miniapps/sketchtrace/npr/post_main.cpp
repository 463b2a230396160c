// sketchtrace-post: the hand-drawn passes on a saved render (EXR with AOV
// layers, or PNG/PPM colour only), so the cheap post-process never needs the
// ray tracer again.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "hatching.hpp"
#include "npr.hpp"
#include "post_inputs.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/srgb.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini::npr {
namespace {

struct PostOptions {
  std::string input, output, summary, dump_bitmaps;
  std::string passes = "hatch,edges,paper";
  std::string style = "sketch";
  bool stats = false;
  NprConfig config;
};

void parse_passes(const std::string& list, NprConfig& config) {
  config.pass_hatch = config.pass_edges = config.pass_paper = false;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item == "hatch")
      config.pass_hatch = true;
    else if (item == "edges")
      config.pass_edges = true;
    else if (item == "paper")
      config.pass_paper = true;
    else
      throw InputError("passes: unknown pass '" + item + "' (hatch, edges, paper)");
  }
}

// Floats as their shortest decimal (0.1, not 0.10000000149011612) in the summary.
double dec(float v) { return std::stod(std::to_string(v)); }
std::vector<double> dec(const std::vector<float>& v) {
  std::vector<double> out;
  for (float x : v) out.push_back(dec(x));
  return out;
}

nlohmann::json parameters_json(const PostOptions& o) {
  const NprConfig& c = o.config;
  return {{"input", o.input},
          {"output", o.output},
          {"passes", o.passes},
          {"style", style_name(c.style)},
          {"edge_darkness", dec(c.edge_darkness)},
          {"edge_threshold", dec(c.edge_threshold)},
          {"edge_full", dec(c.edge_full)},
          {"line_width", dec(c.line_width)},
          {"line_jitter", dec(c.line_jitter)},
          {"levels", c.levels},
          {"deviation_chance", dec(c.deviation_chance)},
          {"terminate_chance", dec(c.terminate_chance)},
          {"min_stroke_length", c.min_stroke_length},
          {"max_stroke_length", c.max_stroke_length},
          {"cell_size", c.cell_size},
          {"stroke_width", dec(c.stroke_width)},
          {"stroke_bend", dec(c.stroke_bend)},
          {"bitmap_size", c.bitmap_size},
          {"thresholds", dec(effective_thresholds(c))},
          {"angles", dec(effective_angles(c))},
          {"object_directions", c.object_directions},
          {"white_percentile", dec(c.white_percentile)},
          {"exposure", dec(c.exposure)},
          {"pencil_tone", dec(c.pencil_tone)},
          {"paper_scale", dec(c.paper_scale)},
          {"paper_octaves", c.paper_octaves},
          {"paper_levels", c.paper_levels},
          {"paper_strength", dec(c.paper_strength)},
          {"seed", c.seed}};
}

// The tonal art map's levels as PNGs, and their target/measured mean ink.
nlohmann::json write_bitmaps(const std::string& prefix, const NprConfig& config) {
  const ToneArtMap tam = build_tone_art_map(config);
  const float pencil = srgb_encode(config.pencil_tone);
  for (int k = 0; k < tam.levels; ++k) {
    const std::vector<float> ink = level_ink(tam, k);
    Image img(tam.size, tam.size, 1);
    for (std::size_t i = 0; i < ink.size(); ++i)
      img.data[i] = srgb_decode(1.f - ink[i] * (1.f - pencil));
    write_image(prefix + std::to_string(k) + ".png", img);
  }
  return {{"target_ink", tam.target}, {"measured_ink", tam.coverage}};
}

nlohmann::json stats_json(const QualityStats& q) {
  nlohmann::json j;
  if (q.has_tone)
    j["tone"] = {{"correlation", q.tone_correlation}, {"mean_abs_error", q.tone_mean_abs_error}};
  if (q.has_lines)
    j["lines"] = {{"silhouette_pixels", q.silhouette_pixels},
                  {"line_pixels", q.line_pixels},
                  {"recall", q.line_recall},
                  {"precision", q.line_precision},
                  {"darkness", q.line_darkness}};
  return j;
}

int run(Communicator& comm, int argc, char** argv) {
  PostOptions o;
  NprConfig& c = o.config;
  CLI::App app{"sketchtrace-post: hand-drawn passes (hatching, edges, paper) on a saved render",
               "sketchtrace-post"};
  CommonOptions common;
  add_common_options(app, common);
  app.add_option("input", o.input, "render: .exr with AOV layers, or .png/.ppm (colour only)")
      ->required();
  app.add_option("-o,--output", o.output, "output image (.png, .ppm, .exr)")->required();
  app.add_option("--passes", o.passes, "comma-separated subset of hatch,edges,paper")
      ->capture_default_str();
  app.add_option("--style", o.style, "sketch | color_pencil | none")->capture_default_str();
  app.add_option("--edge-darkness", c.edge_darkness, "darkening at edge.Y = 1")
      ->capture_default_str();
  app.add_option("--edge-threshold", c.edge_threshold, "edge.Y below this is ignored")
      ->capture_default_str();
  app.add_option("--edge-full", c.edge_full, "edge.Y drawn at full darkness")
      ->capture_default_str();
  app.add_option("--line-width", c.line_width, "pixels added to the stencil line's width")
      ->capture_default_str();
  app.add_option("--line-jitter", c.line_jitter, "pixels of line wobble")->capture_default_str();
  app.add_option("--levels", c.levels, "number of hatching tone levels K")->capture_default_str();
  app.add_option("--deviation-chance", c.deviation_chance, "per-step sideways move chance")
      ->capture_default_str();
  app.add_option("--terminate-chance", c.terminate_chance, "per-step stop chance")
      ->capture_default_str();
  app.add_option("--min-stroke-length", c.min_stroke_length, "pixels before a stroke may stop")
      ->capture_default_str();
  app.add_option("--max-stroke-length", c.max_stroke_length, "hard cap on stroke length")
      ->capture_default_str();
  app.add_option("--cell-size", c.cell_size, "stratification cell (pixels)")->capture_default_str();
  app.add_option("--stroke-width", c.stroke_width, "stroke width at full pressure (pixels)")
      ->capture_default_str();
  app.add_option("--stroke-bend", c.stroke_bend, "largest stroke curvature (degrees/pixel)")
      ->capture_default_str();
  app.add_option("--bitmap-size", c.bitmap_size, "stroke bitmap side (pixels)")
      ->capture_default_str();
  app.add_option("--thresholds", c.thresholds, "decreasing tone of each level (sRGB-encoded)")
      ->delimiter(',');
  app.add_option("--angles", c.angles, "stroke angle per level (degrees)")->delimiter(',');
  app.add_flag("!--fixed-directions", c.object_directions,
               "same hatching direction for every object");
  app.add_option("--white-percentile", c.white_percentile,
                 "luminance quantile drawn as paper white")
      ->capture_default_str();
  app.add_option("--exposure", c.exposure, "multiplies the luminance before hatching")
      ->capture_default_str();
  app.add_option("--pencil-tone", c.pencil_tone, "linear reflectance of a stroke")
      ->capture_default_str();
  app.add_option("--paper-scale", c.paper_scale, "pixels per noise cell, coarsest octave")
      ->capture_default_str();
  app.add_option("--paper-octaves", c.paper_octaves, "noise octaves")->capture_default_str();
  app.add_option("--paper-levels", c.paper_levels, "discretisation levels")->capture_default_str();
  app.add_option("--paper-strength", c.paper_strength, "darkening of the darkest grain")
      ->capture_default_str();
  app.add_option("--seed", c.seed, "run seed")->capture_default_str();
  app.add_option("--dump-bitmaps", o.dump_bitmaps, "also write level bitmaps PREFIX<k>.png");
  app.add_flag("--stats", o.stats, "measure tone fidelity and line quality against the render");
  if (const auto done = parse_command_line(app, argc, argv, common, comm.is_root())) return *done;
  o.summary = common.summary;
  // Every file the run writes, checked before the input is read (the apps' one rule).
  require_image_format(o.output);
  if (!o.dump_bitmaps.empty()) require_image_format(o.dump_bitmaps + "0.png");
  check_output_places({{o.output, 0}, {o.summary, 0}, {common.timings, 0}});
  c.style = parse_style(o.style);
  parse_passes(o.passes, c);
  validate(c);

  RunReport report;
  report.app = "sketchtrace-post";
  report.timer.start("read");
  const PostImages li = read_post_images(o.input);
  report.timer.stop();
  const NprInputs in = li.inputs();
  validate(in);

  const double pixels = double(li.color.width) * li.color.height;
  const double bytes = pixels * 4.0 * (3 + 3 + (in.edge ? 2 : 0)) +
                       double(c.bitmap_size) * c.bitmap_size * 4.0 +
                       2.0 * 256 * 4 * c.paper_octaves;
  report.parameters = parameters_json(o);
  report.scene = {{"width", li.color.width},
                  {"height", li.color.height},
                  {"edge_layer", in.edge != nullptr},
                  {"depth_layer", in.depth != nullptr},
                  {"object_layer", in.object != nullptr},
                  {"normal_layer", in.normal != nullptr}};
  if (comm.is_root()) {
    std::printf("%s\n", build_banner().c_str());
    std::printf("sketchtrace-post %s (%dx%d)\n", o.input.c_str(), li.color.width, li.color.height);
    std::printf("parameters %s\n", report.parameters.dump().c_str());
    if (c.pass_edges && in.edge == nullptr)
      std::printf("note: no edge.Y layer in the input, the edges pass does nothing\n");
    std::printf("memory estimate %.1f MiB\n", bytes / (1024.0 * 1024.0));
  }

  report.timer.start("passes");
  const Image out = apply_passes(in, c);
  const double seconds = report.timer.stop();

  report.timer.start("write");
  if (comm.is_root()) {
    write_image(o.output, out);
    if (!o.dump_bitmaps.empty()) report.scene["tone_art_map"] = write_bitmaps(o.dump_bitmaps, c);
  }
  report.timer.stop();

  if (o.stats) {
    const nlohmann::json stats = stats_json(measure_quality(in, out, c));
    report.scene["stats"] = stats;
    if (comm.is_root()) std::printf("stats %s\n", stats.dump().c_str());
  }

  std::uint64_t h = 0;
  for (std::size_t i = 0; i < out.data.size(); ++i)
    h += hash_term(i, compat::bit_cast<std::uint32_t>(out.data[i]));
  report.verification_hash = h;
  report.fom_name = "post-process rate";
  report.fom_unit = "Mpixel/s";
  report.fom_value = seconds > 0 ? pixels / seconds * 1e-6 : 0.0;
  // Phases only: the program has no dispatch loop of its own to record.
  if (!common.timings.empty())
    write_rank_timings(common.timings, comm, report.timer, RankTimings{},
                       {"sketchtrace-post", "", o.input, report.parameters.dump(), {}});
  report.finish(comm, o.summary);
  return kExitOk;
}

}  // namespace
}  // namespace rtmini::npr

int main(int argc, char** argv) {
  return rtmini::app_main("sketchtrace-post", argc, argv, rtmini::npr::run);
}
