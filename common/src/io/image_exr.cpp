#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"

#ifdef RTMINI_HAVE_EXR
#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#endif

namespace rtmini {

#ifdef RTMINI_HAVE_EXR
namespace {

// OpenEXR's channel naming convention: "layer.R" etc., the unprefixed R, G, B being the main
// image. Viewers (and sketchtrace's AOVs) rely on it to group channels into layers.
constexpr const char* kColorSuffixes[] = {"R", "G", "B", "A"};

struct ChannelSource {
  std::string name;
  const Image* image;
  int channel;
};

void write_channels(const std::string& path, const std::vector<ChannelSource>& channels, int width,
                    int height, ExrPixel pixel) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  const Imf::PixelType type = pixel == ExrPixel::kHalf ? Imf::HALF : Imf::FLOAT;
  // One plane per channel: OpenEXR reads each channel with its own stride.
  std::vector<std::vector<float>> floats(channels.size());
  std::vector<std::vector<Imath::half>> halves(channels.size());
  Imf::Header header(width, height);
  Imf::FrameBuffer frame;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const ChannelSource& src = channels[c];
    header.channels().insert(src.name, Imf::Channel(type));
    floats[c].resize(n);
    for (std::size_t i = 0; i < n; ++i)
      floats[c][i] = src.image->data[i * src.image->channels + src.channel];
    char* base;
    std::size_t size;
    if (pixel == ExrPixel::kHalf) {
      halves[c].assign(floats[c].begin(), floats[c].end());
      base = reinterpret_cast<char*>(halves[c].data());
      size = sizeof(Imath::half);
    } else {
      base = reinterpret_cast<char*>(floats[c].data());
      size = sizeof(float);
    }
    frame.insert(src.name, Imf::Slice(type, base, size, size * width));
  }
  write_file_atomic(path, [&](const std::string& tmp) {
    // Through a stream of our own: OpenEXR's OutputFile writes its offset table and closes
    // its file in the destructor, which swallows errors, so a small image that fit in the
    // stream's buffer was "written" to a full disk without a word. The stream's state after
    // the file is finished and the close are the checks.
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    try {
      Imf::StdOFStream stream(os, tmp.c_str());
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    } catch (const std::exception& e) {
      throw IoError(path + ": EXR write failed: " + e.what());
    }
    os.close();
    if (!os) throw IoError(path + ": EXR write failed: " + std::strerror(errno));
  });
}

void check_layer_size(const std::string& path, const Image& image, int width, int height) {
  if (image.width != width || image.height != height)
    throw IoError(path + ": EXR layers must all have the same size");
}

}  // namespace

void write_exr(const std::string& path, const Image& image, ExrPixel pixel) {
  write_exr_layers(path, {{"", image}}, pixel);
}

void write_exr_layers(const std::string& path,
                      const std::vector<std::pair<std::string, Image>>& layers, ExrPixel pixel) {
  if (layers.empty()) throw IoError(path + ": no layers to write");
  const int width = layers.front().second.width;
  const int height = layers.front().second.height;
  std::vector<ChannelSource> channels;
  for (const auto& [name, image] : layers) {
    check_layer_size(path, image, width, height);
    const std::string prefix = name.empty() ? std::string() : name + ".";
    // A one-channel layer is "name.Y" (the luminance convention), unless its name already
    // spells out the channel ("depth.Z").
    if (image.channels == 1) {
      const bool has_dot = name.find('.') != std::string::npos;
      channels.push_back({has_dot ? name : prefix + "Y", &image, 0});
    } else if (image.channels == 3 || image.channels == 4) {
      for (int c = 0; c < image.channels; ++c)
        channels.push_back({prefix + kColorSuffixes[c], &image, c});
    } else {
      throw IoError(path + ": EXR layer '" + name + "' needs 1, 3 or 4 channels");
    }
  }
  write_channels(path, channels, width, height, pixel);
}

std::vector<std::pair<std::string, Image>> read_exr_layers(const std::string& path) {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> planes;  // full channel name -> pixels
  try {
    // Every channel is read as float, whatever it is stored as (half, float, uint): one path
    // for all files; OpenEXR converts while reading.
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    width = window.max.x - window.min.x + 1;
    height = window.max.y - window.min.y + 1;
    check_image_size(path, width, height);
    Imf::FrameBuffer frame;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      std::vector<float>& plane = planes[it.name()];
      plane.assign(static_cast<std::size_t>(width) * height, 0.f);
      frame.insert(it.name(), Imf::Slice::Make(Imf::FLOAT, plane.data(), window, sizeof(float),
                                               sizeof(float) * width));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    throw InputError(path, 0, std::string("cannot read EXR: ") + e.what());
  }

  // Channels are grouped by the prefix before their last dot; a group with R, G and B becomes
  // one colour layer, every other channel a one-channel layer of its full name.
  std::map<std::string, std::map<std::string, const std::vector<float>*>> groups;
  for (const auto& [name, plane] : planes) {
    const std::size_t dot = name.find_last_of('.');
    const std::string prefix = dot == std::string::npos ? std::string() : name.substr(0, dot);
    groups[prefix][dot == std::string::npos ? name : name.substr(dot + 1)] = &plane;
  }
  std::vector<std::pair<std::string, Image>> layers;
  for (auto& [prefix, members] : groups) {
    if (members.count("R") && members.count("G") && members.count("B")) {
      const int nc = members.count("A") ? 4 : 3;
      Image image(width, height, nc);
      for (int c = 0; c < nc; ++c) {
        const std::vector<float>& plane = *members.at(kColorSuffixes[c]);
        for (std::size_t i = 0; i < plane.size(); ++i) image.data[i * nc + c] = plane[i];
        members.erase(kColorSuffixes[c]);
      }
      layers.emplace_back(prefix, std::move(image));
    }
    for (const auto& [suffix, plane] : members) {
      Image image(width, height, 1);
      image.data = *plane;
      layers.emplace_back(prefix.empty() ? suffix : prefix + "." + suffix, std::move(image));
    }
  }
  return layers;
}

Image read_exr(const std::string& path) {
  auto layers = read_exr_layers(path);
  for (auto& [name, image] : layers)
    if (name.empty() && image.channels >= 3) return std::move(image);
  for (auto& [name, image] : layers)
    if (name == "Y") return std::move(image);
  throw InputError(path, 0, "EXR has no unprefixed R, G, B or Y channels");
}

#else

void write_exr(const std::string& path, const Image&, ExrPixel) { format_not_built(path); }
void write_exr_layers(const std::string& path, const std::vector<std::pair<std::string, Image>>&,
                      ExrPixel) {
  format_not_built(path);
}
std::vector<std::pair<std::string, Image>> read_exr_layers(const std::string& path) {
  format_not_built(path);
}
Image read_exr(const std::string& path) { format_not_built(path); }

#endif

}  // namespace rtmini
