#pragma once
// sketchtrace's hand-drawn post-process (hand-drawn seed §4-6): tone hatching or
// colour pencil, then silhouette darkening, then the paper texture, last. The
// passes only read images (colour + AOVs), so they never need the ray tracer.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/io/image.hpp"
#include "rtmini/io/srgb.hpp"
#include "rtmini/kokkos_compat.hpp"

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

  // Lines from the renderer's ray stencil (edge.Y: fraction of ring rays that see
  // a silhouette, self-occluding silhouette or crease; Choudhury & Parker 2009).
  // Line ink = clamp((e - edge_threshold) / (edge_full - edge_threshold)), grown by
  // line_width pixels (anti-aliased disc dilation), then pixel *= 1 - edge_darkness * ink.
  float edge_darkness = 1.0f;
  float edge_threshold = 0.05f;
  float edge_full = 0.2f;    // stencil fraction drawn at full darkness
  float line_width = 1.5f;   // pixels added to the stencil line (resolution-independent)
  float line_jitter = 0.0f;  // pixels of smooth wobble of the lines (0 = straight)

  // Hatching: a tonal art map of `levels` nested, calibrated stroke bitmaps.
  int levels = 6;
  float deviation_chance = 0.05f;  // per step, move one pixel perpendicular
  float terminate_chance = 0.08f;  // per step once min_stroke_length is reached
  int min_stroke_length = 10;      // pixels before a stroke may terminate
  int max_stroke_length = 512;     // hard cap so a kernel's loop is bounded
  int cell_size = 8;               // stratification cell (pixels) = stroke spacing
  float stroke_width = 1.4f;       // pixels at full pen pressure
  float stroke_bend = 0.4f;        // largest curvature, degrees per pixel
  int bitmap_size = 256;           // square, toroidal; tiled with a random offset per object
  // Displayed (sRGB-encoded) tone of each level, brightest first, strictly
  // decreasing; level k's strokes are added until its mean tone reaches
  // thresholds[k]. Empty = ink evenly spaced up to 95 % coverage.
  std::vector<float> thresholds;
  // Stroke direction (degrees, 0 = +x, counter-clockwise) per level; empty =
  // 45 for the lighter half of the levels, cross-hatching at 135 for the darker.
  std::vector<float> angles;
  // Every object's hatching is turned by its own angle (golden-angle sequence
  // over the object-id AOV), so neighbouring objects read apart.
  bool object_directions = true;
  float pencil_tone = 0.004f;  // linear reflectance of a graphite stroke (sketch style)
  // Exposure: the render's luminance is divided by its white_percentile
  // quantile (times 1/exposure), so the brightest pixels stay pure paper white.
  float white_percentile = 0.99f;
  float exposure = 1.0f;

  // Paper (seed §6): improved Perlin noise (Perlin 2002), fBm, discretised.
  float paper_scale = 8.0f;  // pixels per lattice cell of the coarsest octave
  int paper_octaves = 4;
  int paper_levels = 4;          // discretisation levels
  float paper_strength = 0.06f;  // darkest paper grain multiplies the pixel by 1 - strength

  std::uint64_t seed = 1;
};

// Thresholds (level tones) and angles with defaults filled in (length == levels).
std::vector<float> effective_thresholds(const NprConfig& config);
std::vector<float> effective_angles(const NprConfig& config);

// Throws InputError("what: reason") for an invalid configuration.
void validate(const NprConfig& config);

// Throws InputError when an AOV's size does not match the colour image.
void validate(const NprInputs& inputs);

// The enabled passes in order; returns a 3-channel linear RGB image.
Image apply_passes(const NprInputs& inputs, const NprConfig& config);

// The single passes (each maps a 3-channel image to a new 3-channel image).
// `object` (may be null) turns each object's hatching direction.
Image tone_pass(const Image& color, const NprConfig& config, const Image* object = nullptr);
Image edge_pass(const Image& color, const Image& edge, const NprConfig& config);
Image paper_pass(const Image& color, const NprConfig& config);

// Luminance that maps to paper white: the white_percentile quantile of the
// render's luminance over 1/exposure (1 when the image is black).
float exposure_white(const Image& color, const NprConfig& config);

// Displayed tone the hatching reproduces: sRGB-encoded luminance / white, in [0, 1].
KOKKOS_INLINE_FUNCTION float render_tone(float r, float g, float b, float inv_white) {
  const float lum = 0.2126f * r + 0.7152f * g + 0.0722f * b;
  return srgb_encode(math::clamp(lum * inv_white, 0.f, 1.f));
}

// Line ink in [0, 1] per pixel (1 channel) as the edges pass draws it.
Image line_ink(const Image& edge, const NprConfig& config);

// Measured quality of a drawing against its render (sketchtrace-post --stats).
struct QualityStats {
  // Tone: drawing and render tone, both blurred with a Gaussian of sigma
  // cell_size / 2 (the stroke spacing), over every pixel.
  bool has_tone = false;
  double tone_correlation = 0, tone_mean_abs_error = 0;
  // Lines against the geometric silhouettes of the object-id AOV (pixels whose
  // 4-neighbour belongs to another object and lies behind them); a drawn line
  // pixel has line ink >= 0.5. Recall: silhouette pixels with a line pixel within
  // 1 pixel; precision: line pixels within 1 + ceil(line_width / 2) pixels of a
  // silhouette (creases and self-occluding silhouettes count against it).
  bool has_lines = false;
  double silhouette_pixels = 0, line_pixels = 0;
  double line_recall = 0, line_precision = 0;
  double line_darkness = 0;  // mean 1 - drawn tone on the drawn line pixels
};
QualityStats measure_quality(const NprInputs& inputs, const Image& drawing,
                             const NprConfig& config);

// Style names for the CLI and summaries: "sketch", "color_pencil", "none".
const char* style_name(NprStyle style);
NprStyle parse_style(const std::string& name);  // InputError on an unknown name

}  // namespace rtmini::npr
