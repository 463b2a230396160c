#pragma once
// sketchtrace's hand-drawn post-process (hand-drawn seed §4-6): tone hatching or
// colour pencil, then silhouette darkening, then the paper texture, last. The
// passes only read images (colour + AOVs), so they never need the ray tracer.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/io/image.hpp"

namespace rtmini::npr {

// Any pointer but `color` may be null. All images must have color's size;
// edge/depth/object are 1-channel (channel 0 is used otherwise), normal 3-channel.
struct NprInputs {
  const Image* color = nullptr;
  const Image* edge = nullptr;
  const Image* depth = nullptr;
  const Image* object = nullptr;
  const Image* normal = nullptr;
};

enum class NprStyle { kSketch, kColorPencil, kNone };

// Bounds for arrays that kernels capture by value.
inline constexpr int kMaxLevels = 16;

struct NprConfig {
  NprStyle style = NprStyle::kSketch;
  // Which passes run (in this fixed order when enabled): tone, edges, paper.
  bool pass_hatch = true;
  bool pass_edges = true;
  bool pass_paper = true;

  // Edges: pixel *= 1 - edge_darkness * e for e = edge.Y >= edge_threshold, so the
  // darkening is proportional to the stencil's fraction of differing hits (seed §5.2).
  float edge_darkness = 1.0f;
  float edge_threshold = 0.1f;

  // Hatching (seed §4, after Lake et al. 2000): `levels` nested stroke bitmaps.
  int levels = 5;
  float deviation_chance = 0.05f;  // per step, move one pixel perpendicular
  float terminate_chance = 0.1f;   // per step once min_stroke_length is reached
  int min_stroke_length = 12;      // pixels before a stroke may terminate
  int max_stroke_length = 512;     // hard cap so a kernel's loop is bounded
  int cell_size = 14;              // stratification cell (pixels)
  int strokes_per_cell = 1;        // new strokes per cell per level
  int bitmap_size = 512;           // square, toroidal; tiled with a random offset per region
  // Tone thresholds on sRGB-encoded luminance, strictly decreasing, one per level:
  // tone >= thresholds[0] stays white (the brightest level), tone < thresholds[k]
  // gets bitmap k. Empty = evenly spaced 1 - (k+1)/(levels+1).
  std::vector<float> thresholds;
  // Stroke direction (degrees, 0 = +x, counter-clockwise) per level; empty =
  // cross-hatching 45, 45, 135, 135, 0, 90, then repeating.
  std::vector<float> angles;
  float pencil_tone = 0.06f;  // linear reflectance of a graphite stroke (sketch style)

  // Paper (seed §6): improved Perlin noise (Perlin 2002), fBm, discretised.
  float paper_scale = 8.0f;  // pixels per lattice cell of the coarsest octave
  int paper_octaves = 4;
  int paper_levels = 4;          // discretisation levels
  float paper_strength = 0.15f;  // darkest paper grain multiplies the pixel by 1 - strength

  std::uint64_t seed = 1;
};

// Thresholds and angles with defaults filled in (length == levels).
std::vector<float> effective_thresholds(const NprConfig& config);
std::vector<float> effective_angles(const NprConfig& config);

// Throws InputError("what: reason") for an invalid configuration.
void validate(const NprConfig& config);

// Throws InputError when an AOV's size does not match the colour image.
void validate(const NprInputs& inputs);

// The enabled passes in order; returns a 3-channel linear RGB image.
Image apply_passes(const NprInputs& inputs, const NprConfig& config);

// The single passes (each maps a 3-channel image to a new 3-channel image).
Image tone_pass(const Image& color, const NprConfig& config);
Image edge_pass(const Image& color, const Image& edge, const NprConfig& config);
Image paper_pass(const Image& color, const NprConfig& config);

// Style names for the CLI and summaries: "sketch", "color_pencil", "none".
const char* style_name(NprStyle style);
NprStyle parse_style(const std::string& name);  // InputError on an unknown name

}  // namespace rtmini::npr
