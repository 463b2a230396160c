#include "rtmini/io/image.hpp"

#include <fstream>

#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"

namespace rtmini {
namespace {

[[noreturn]] void unknown_extension(const std::string& path) {
  throw InputError(
      path, 0,
      "unknown image format '" + lower_extension(path) + "' (expected .ppm, .png or .exr)");
}

}  // namespace

void format_not_built(const std::string& path) {
  const bool png = lower_extension(path) == ".png";
  throw IoError(path + (png ? ": built without PNG support (libpng not found at configure time)"
                            : ": built without OpenEXR support (OpenEXR not found at configure "
                              "time)"));
}

void require_image_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ppm") return;
  if (ext == ".png") {
#ifndef RTMINI_HAVE_PNG
    format_not_built(path);
#endif
    return;
  }
  if (ext == ".exr") {
#ifndef RTMINI_HAVE_EXR
    format_not_built(path);
#endif
    return;
  }
  unknown_extension(path);
}

void require_readable_image(const std::string& path) {
  if (!std::ifstream(path)) throw InputError(path + ": cannot open the image");
  require_image_format(path);
}

void check_image_size(const std::string& path, long width, long height) {
  if (width > 0 && height > 0 && width <= kMaxImagePixels / height) return;
  throw InputError(path, 0,
                   "image of " + std::to_string(width) + " x " + std::to_string(height) +
                       " pixels is empty or larger than the " + std::to_string(kMaxImagePixels) +
                       " pixels a reader accepts");
}

// The format follows the file name, never the content: a writer must choose before any byte
// exists, and the reader follows the same rule so write_image/read_image round-trip. A format
// this build lacks (no libpng/OpenEXR) fails inside write_png/write_exr with its own message.
void write_image(const std::string& path, const Image& image) {
  const std::string ext = lower_extension(path);
  if (ext == ".ppm") return write_ppm(path, image);
  if (ext == ".png") return write_png(path, image);
  if (ext == ".exr") return write_exr(path, image);
  unknown_extension(path);
}

Image read_image(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ppm") return read_ppm(path);
  if (ext == ".png") return read_png(path);
  if (ext == ".exr") return read_exr(path);
  unknown_extension(path);
}

}  // namespace rtmini
