#include "frame_output.hpp"

#include <cmath>
#include <cstring>

#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/report/hash.hpp"

#ifdef RTMINI_SKETCH_HAVE_NPR
#include "npr/npr.hpp"
#endif

namespace rtmini::sketch {
namespace {

// AOVs beside an 8-bit image go to "<stem>.aov.exr".
std::string aov_path_of(const std::string& path) {
  return path.substr(0, path.find_last_of('.')) + ".aov.exr";
}

std::uint64_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

Image final_image(const Frame& frame, const RenderSettings& s) {
  if (s.style == "none") return frame.color;
#ifdef RTMINI_SKETCH_HAVE_NPR
  npr::NprConfig config;
  config.style = npr::parse_style(s.style);
  config.seed = s.seed;
  npr::NprInputs in;
  in.color = &frame.color;
  in.edge = &frame.edge;
  in.depth = &frame.depth;
  in.object = &frame.object;
  in.normal = &frame.normal;
  return npr::apply_passes(in, config);
#else
  throw InputError("--style " + s.style +
                   ": this build has no hand-drawn passes (miniapps/sketchtrace/npr)");
#endif
}

}  // namespace

Frame assemble_frame(const std::vector<PixelResult>& pixels, int width, int height) {
  Frame f;
  f.color = Image(width, height, 3);
  f.depth = Image(width, height, 1);
  f.normal = Image(width, height, 3);
  f.object = Image(width, height, 1);
  f.cost = Image(width, height, 1);
  f.edge = Image(width, height, 1);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const PixelResult& p = pixels[i];
    const int x = static_cast<int>(i % static_cast<std::size_t>(width));
    const int y = static_cast<int>(i / static_cast<std::size_t>(width));
    f.color.at(x, y, 0) = p.r;
    f.color.at(x, y, 1) = p.g;
    f.color.at(x, y, 2) = p.b;
    f.depth.at(x, y, 0) = p.depth;
    f.normal.at(x, y, 0) = p.nx;
    f.normal.at(x, y, 1) = p.ny;
    f.normal.at(x, y, 2) = p.nz;
    f.object.at(x, y, 0) = static_cast<float>(p.object);
    f.cost.at(x, y, 0) = static_cast<float>(p.rays);
    f.edge.at(x, y, 0) = p.edge;
  }
  return f;
}

std::uint64_t hash_pixels(const std::vector<PixelResult>& pixels, std::int64_t first_index,
                          bool aov) {
  std::uint64_t h = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const PixelResult& p = pixels[i];
    std::uint64_t v = mix64(bits(p.r) | bits(p.g) << 32) ^ mix64(bits(p.b) ^ 0x5bd1e995ULL);
    if (aov) {
      v ^= mix64(bits(p.depth) | bits(p.edge) << 32) ^
           mix64(static_cast<std::uint32_t>(p.object) + 0x1234ULL);
      v ^= mix64(bits(p.nx) | bits(p.ny) << 32) ^ mix64(bits(p.nz) + 0x9876ULL);
    }
    h += hash_term(static_cast<std::uint64_t>(first_index) + i, v);
  }
  return h;
}

void check_output_path(const std::string& path, const RenderSettings& s) {
  require_image_format(path);
  if (!s.aov.empty()) require_image_format(aov_path_of(path));
}

std::vector<std::string> write_frame(const std::string& path, const Frame& frame,
                                     const RenderSettings& s) {
  std::vector<std::string> written;
  const Image image = final_image(frame, s);
  std::vector<std::pair<std::string, Image>> layers;
  auto single = [&](const Image& src, int c) {
    Image out(src.width, src.height, 1);
    for (int y = 0; y < src.height; ++y)
      for (int x = 0; x < src.width; ++x) out.at(x, y, 0) = src.at(x, y, c);
    return out;
  };
  if (s.wants_aov("depth")) layers.emplace_back("depth.Z", frame.depth);
  if (s.wants_aov("normal")) {
    layers.emplace_back("normal.X", single(frame.normal, 0));
    layers.emplace_back("normal.Y", single(frame.normal, 1));
    layers.emplace_back("normal.Z", single(frame.normal, 2));
  }
  if (s.wants_aov("object")) layers.emplace_back("object.Y", frame.object);
  if (s.wants_aov("cost")) layers.emplace_back("cost.Y", frame.cost);
  if (s.wants_aov("edge")) layers.emplace_back("edge.Y", frame.edge);
  if (lower_extension(path) == ".exr") {
    layers.insert(layers.begin(), {"", image});
    write_exr_layers(path, layers);
    written.push_back(path);
    return written;
  }
  write_image(path, image);
  written.push_back(path);
  if (!layers.empty()) {
    // AOVs of an 8-bit output go next to it, with the unstyled linear colour.
    const std::string aov_path = aov_path_of(path);
    layers.insert(layers.begin(), {"", frame.color});
    write_exr_layers(aov_path, layers);
    written.push_back(aov_path);
  }
  return written;
}

}  // namespace rtmini::sketch
