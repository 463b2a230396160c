#pragma once
// Linear float images and their files. 8-bit formats (PPM P6 -- the hand-drawn
// seed's output -- and PNG) are sRGB-encoded on write and decoded on read; EXR
// stays linear. Every write is atomic (temporary file + rename).
#include <string>
#include <utility>
#include <vector>

namespace rtmini {

// Row-major, top row first, interleaved channels (1 = grey/Y, 3 = RGB, 4 = RGBA).
struct Image {
  int width = 0;
  int height = 0;
  int channels = 3;
  std::vector<float> data;

  Image() = default;
  Image(int w, int h, int c = 3)
      : width(w), height(h), channels(c), data(static_cast<std::size_t>(w) * h * c, 0.f) {}

  float& at(int x, int y, int c) { return data[index(x, y, c)]; }
  float at(int x, int y, int c) const { return data[index(x, y, c)]; }

 private:
  std::size_t index(int x, int y, int c) const {
    return (static_cast<std::size_t>(y) * width + x) * channels + c;
  }
};

// Readers refuse larger images before allocating anything (8192 x 8192: twice 4K in each
// dimension), so a corrupt header cannot claim gigabytes (a 1000000 x 1000000 PNG reference
// ended in std::bad_alloc; found by fuzzing).
inline constexpr long kMaxImagePixels = 1L << 26;
// InputError "path: reason" when width x height exceeds kMaxImagePixels.
void check_image_size(const std::string& path, long width, long height);

enum class ExrPixel { kHalf, kFloat };

// Before any work, for an image a run will write (or, second form, read): InputError for an
// extension that is no image format (or an input that cannot be opened), IoError (exit 3, what
// the writer would raise at the end) for a format this build lacks (.png without libpng, .exr
// without OpenEXR), so that a render is never computed for a file it cannot write.
void require_image_format(const std::string& path);
void require_readable_image(const std::string& path);
// The IoError of a format this build lacks (the one message of the checks above and of the
// writers' and readers' stand-ins in such a build).
[[noreturn]] void format_not_built(const std::string& path);

// Dispatch on the extension (.ppm, .png, .exr; case-insensitive); InputError otherwise.
void write_image(const std::string& path, const Image& image);
Image read_image(const std::string& path);

// P6, 8-bit sRGB. Grey images are written as RGB; alpha is dropped.
void write_ppm(const std::string& path, const Image& image);
// P3 or P6, maxval up to 65535; returns 3 linear channels. InputError "file:line: reason".
Image read_ppm(const std::string& path);

// 8-bit sRGB (grey, RGB or RGBA; alpha stored linearly). IoError without libpng.
void write_png(const std::string& path, const Image& image);
Image read_png(const std::string& path);
// The same file as data (normal, bump and height maps): each 8-bit code c becomes c / 255,
// with no transfer function.
Image read_png_data(const std::string& path);

// Linear RGB(A) in channels R, G, B (A). IoError without OpenEXR.
void write_exr(const std::string& path, const Image& image, ExrPixel pixel = ExrPixel::kHalf);
// The unprefixed R, G, B (A) channels, or Y alone as a 1-channel image.
Image read_exr(const std::string& path);

// AOV layers as channels of one EXR file. A layer named "normal" with 3 (4) channels
// becomes normal.R/G/B(/A); "" is the unprefixed beauty image; a 1-channel layer named
// "depth.Z" keeps its name, one without a dot ("cost") becomes "cost.Y". All images
// must have the same size.
void write_exr_layers(const std::string& path,
                      const std::vector<std::pair<std::string, Image>>& layers,
                      ExrPixel pixel = ExrPixel::kFloat);
// Inverse of write_exr_layers: R/G/B(/A) groups come back under their layer name,
// any other channel as a 1-channel image under its full channel name.
std::vector<std::pair<std::string, Image>> read_exr_layers(const std::string& path);

}  // namespace rtmini
