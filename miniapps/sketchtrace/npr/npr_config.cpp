#include <cmath>
#include <string>

#include "hatching.hpp"
#include "npr.hpp"
#include "paper.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::npr {

std::vector<float> effective_thresholds(const NprConfig& config) {
  if (!config.thresholds.empty()) return config.thresholds;
  // The tone each default ink target displays as: 1 - ink * (1 - pencil).
  const float pencil = srgb_encode(config.pencil_tone);
  std::vector<float> t;
  for (double ink : level_ink_targets(config)) t.push_back(1.f - float(ink) * (1.f - pencil));
  return t;
}

std::vector<float> effective_angles(const NprConfig& config) {
  if (!config.angles.empty()) return config.angles;
  // Lighter half in one direction, darker half cross-hatched (Lake et al. 2000).
  std::vector<float> a(static_cast<std::size_t>(config.levels > 0 ? config.levels : 0));
  for (int k = 0; k < config.levels; ++k) a[k] = 2 * k < config.levels ? 45.f : 135.f;
  return a;
}

namespace {
void require(bool ok, const std::string& what, const std::string& reason) {
  if (!ok) throw InputError(what + ": " + reason);
}
bool finite(float x) { return std::isfinite(x); }
}  // namespace

void validate(const NprConfig& c) {
  require(finite(c.edge_darkness) && c.edge_darkness >= 0.f && c.edge_darkness <= 1.f,
          "edge-darkness", "must be in [0, 1]");
  require(finite(c.edge_threshold) && c.edge_threshold >= 0.f && c.edge_threshold <= 1.f,
          "edge-threshold", "must be in [0, 1]");
  require(finite(c.edge_full) && c.edge_full > c.edge_threshold && c.edge_full <= 1.f, "edge-full",
          "must be in (edge-threshold, 1]");
  require(finite(c.line_width) && c.line_width >= 0.f && c.line_width <= 32.f, "line-width",
          "must be in [0, 32] pixels");
  require(finite(c.line_jitter) && c.line_jitter >= 0.f && c.line_jitter <= 8.f, "line-jitter",
          "must be in [0, 8] pixels");
  require(c.levels >= 1 && c.levels <= kMaxLevels, "levels",
          "must be in [1, " + std::to_string(kMaxLevels) + "]");
  require(finite(c.deviation_chance) && c.deviation_chance >= 0.f && c.deviation_chance <= 1.f,
          "deviation-chance", "must be in [0, 1]");
  require(finite(c.terminate_chance) && c.terminate_chance > 0.f && c.terminate_chance <= 1.f,
          "terminate-chance", "must be in (0, 1]");
  require(c.min_stroke_length >= 1, "min-stroke-length", "must be at least 1");
  require(c.max_stroke_length >= c.min_stroke_length, "max-stroke-length",
          "must be at least min-stroke-length");
  require(c.bitmap_size >= 8 && c.bitmap_size <= 8192, "bitmap-size", "must be in [8, 8192]");
  require(c.cell_size >= 1 && c.cell_size <= c.bitmap_size, "cell-size",
          "must be in [1, bitmap-size]");
  require(finite(c.stroke_width) && c.stroke_width >= 0.5f && c.stroke_width <= 16.f,
          "stroke-width", "must be in [0.5, 16] pixels");
  require(finite(c.stroke_bend) && c.stroke_bend >= 0.f && c.stroke_bend <= 30.f, "stroke-bend",
          "must be in [0, 30] degrees per pixel");
  require(finite(c.white_percentile) && c.white_percentile > 0.f && c.white_percentile <= 1.f,
          "white-percentile", "must be in (0, 1]");
  require(finite(c.exposure) && c.exposure > 0.f && c.exposure <= 1e6f, "exposure",
          "must be in (0, 1e6]");
  require(c.thresholds.empty() || static_cast<int>(c.thresholds.size()) == c.levels, "thresholds",
          "need one value per level (" + std::to_string(c.levels) + ")");
  for (std::size_t k = 0; k < c.thresholds.size(); ++k) {
    require(finite(c.thresholds[k]) && c.thresholds[k] > 0.f && c.thresholds[k] <= 1.f,
            "thresholds", "must be in (0, 1]");
    require(k == 0 || c.thresholds[k] < c.thresholds[k - 1], "thresholds",
            "must be strictly decreasing (brightest level first)");
  }
  require(c.angles.empty() || static_cast<int>(c.angles.size()) == c.levels, "angles",
          "need one value per level (" + std::to_string(c.levels) + ")");
  for (float a : c.angles) require(finite(a), "angles", "must be finite");
  require(finite(c.pencil_tone) && c.pencil_tone >= 0.f && c.pencil_tone <= 1.f, "pencil-tone",
          "must be in [0, 1]");
  require(finite(c.paper_scale) && c.paper_scale >= 0.5f && c.paper_scale <= 4096.f, "paper-scale",
          "must be in [0.5, 4096] pixels");
  require(c.paper_octaves >= 1 && c.paper_octaves <= kMaxOctaves, "paper-octaves",
          "must be in [1, " + std::to_string(kMaxOctaves) + "]");
  require(c.paper_levels >= 2 && c.paper_levels <= 256, "paper-levels", "must be in [2, 256]");
  require(finite(c.paper_strength) && c.paper_strength >= 0.f && c.paper_strength <= 1.f,
          "paper-strength", "must be in [0, 1]");
}

void validate(const NprInputs& in) {
  if (in.color == nullptr) throw InputError("npr: a colour image is required");
  require(in.color->width > 0 && in.color->height > 0, "colour image", "is empty");
  const Image* aovs[] = {in.edge, in.depth, in.object, in.normal};
  const char* names[] = {"edge", "depth", "object", "normal"};
  for (int i = 0; i < 4; ++i)
    if (aovs[i] != nullptr)
      require(aovs[i]->width == in.color->width && aovs[i]->height == in.color->height, names[i],
              "AOV is " + std::to_string(aovs[i]->width) + "x" + std::to_string(aovs[i]->height) +
                  ", colour is " + std::to_string(in.color->width) + "x" +
                  std::to_string(in.color->height));
}

const char* style_name(NprStyle style) {
  switch (style) {
    case NprStyle::kSketch:
      return "sketch";
    case NprStyle::kColorPencil:
      return "color_pencil";
    case NprStyle::kNone:
      return "none";
  }
  return "unknown";
}

NprStyle parse_style(const std::string& name) {
  if (name == "sketch") return NprStyle::kSketch;
  // The renderer's CLI spells it with a hyphen; both name the same style.
  if (name == "color_pencil" || name == "color-pencil") return NprStyle::kColorPencil;
  if (name == "none") return NprStyle::kNone;
  throw InputError("style: unknown '" + name + "' (sketch, color_pencil, none)");
}

}  // namespace rtmini::npr
