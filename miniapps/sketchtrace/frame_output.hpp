#pragma once
// From gathered pixels to files: the colour image (.ppm/.png/.exr by extension),
// the AOV layers of an EXR (R,G,B, depth.Z, normal.X/Y/Z, object.Y, cost.Y,
// edge.Y), and the optional hand-drawn post-process.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render_settings.hpp"
#include "rtmini/io/image.hpp"
#include "trace_kernel.hpp"

namespace rtmini::sketch {

struct Frame {
  Image color;  // linear RGB
  Image depth, normal, object, cost, edge;
};

// pixels: the whole image in row-major order.
Frame assemble_frame(const std::vector<PixelResult>& pixels, int width, int height);

// Order-independent verification hash of a set of pixels (colour, and the AOVs when computed).
std::uint64_t hash_pixels(const std::vector<PixelResult>& pixels, std::int64_t first_index,
                          bool aov);

// Before the render: InputError unless the extension is .ppm, .png or .exr; IoError for a format
// this build cannot write, the output's or (AOVs beside an 8-bit image) the .aov.exr's.
void check_output_path(const std::string& path, const RenderSettings& s);

// Writes -o (styled when a style is set) and the AOV EXR when asked; returns the files written.
std::vector<std::string> write_frame(const std::string& path, const Frame& frame,
                                     const RenderSettings& s);

}  // namespace rtmini::sketch
