#include <cstdint>
#include <cstring>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/srgb.hpp"

#ifdef RTMINI_HAVE_PNG
#include <png.h>
#endif

namespace rtmini {

#ifdef RTMINI_HAVE_PNG

void write_png(const std::string& path, const Image& image) {
  if (image.channels < 1 || image.channels > 4 || image.channels == 2)
    throw IoError(path + ": PNG needs a 1, 3 or 4 channel image");
  // Colour is stored linear and encoded to 8-bit sRGB here; alpha is coverage, not light, so it
  // is only clamped and rounded.
  std::vector<std::uint8_t> pixels(image.data.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const bool alpha = image.channels == 4 && i % 4 == 3;
    const float v = image.data[i];
    pixels[i] = alpha ? static_cast<std::uint8_t>(math::clamp(v, 0.f, 1.f) * 255.f + 0.5f)
                      : srgb_encode_8bit(v);
  }
  // libpng's simplified API (png_image): no setjmp/longjmp error handling to get right, and
  // errors come back as a message string.
  write_file_atomic(path, [&](const std::string& tmp) {
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = image.channels == 1   ? PNG_FORMAT_GRAY
                 : image.channels == 3 ? PNG_FORMAT_RGB
                                       : PNG_FORMAT_RGBA;
    const int ok = png_image_write_to_file(&png, tmp.c_str(), 0, pixels.data(), 0, nullptr);
    const std::string message = png.message;
    png_image_free(&png);
    if (!ok) throw IoError(path + ": PNG write failed: " + message);
  });
}

namespace {

// Decodes to RGB(A); colour codes go through `decode`, alpha is always code / 255.
template <class Decode>
Image read_png_with(const std::string& path, Decode decode) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw InputError(path, 0, std::string("cannot read PNG: ") + png.message);
  try {
    check_image_size(path, static_cast<long>(png.width), static_cast<long>(png.height));
  } catch (...) {
    png_image_free(&png);
    throw;
  }
  // Ask libpng for RGB(A) whatever the file holds (grey, palette, 16-bit): one decode path, and
  // a reference image compares channel by channel with a rendered RGB one.
  const bool alpha = (png.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  png.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height), alpha ? 4 : 3);
  std::vector<std::uint8_t> pixels(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(path, 0, "cannot read PNG: " + message);
  }
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const bool is_alpha = alpha && i % 4 == 3;
    image.data[i] = is_alpha ? pixels[i] / 255.f : decode(pixels[i]);
  }
  return image;
}

}  // namespace

Image read_png(const std::string& path) {
  return read_png_with(path, [](std::uint8_t c) { return srgb_decode_8bit(c); });
}

Image read_png_data(const std::string& path) {
  return read_png_with(path, [](std::uint8_t c) { return c / 255.f; });
}

#else

// Built without libpng: IoError (exit 3, a missing resource), not InputError, since the request
// is valid; tests that need PNG are skipped in such builds.
void write_png(const std::string& path, const Image&) { format_not_built(path); }
Image read_png(const std::string& path) { format_not_built(path); }
Image read_png_data(const std::string& path) { return read_png(path); }

#endif

}  // namespace rtmini
