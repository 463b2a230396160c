#include <cctype>
#include <string_view>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/srgb.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini {
namespace {

// Whitespace- and comment-separated tokens of a PPM header or P3 body, with lines.
class PpmTokens {
 public:
  PpmTokens(const std::string& path, std::string_view bytes) : path_(path), bytes_(bytes) {}

  std::string_view next(const char* what) {
    skip_space_and_comments();
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    if (start == pos_) fail(std::string("unexpected end of file, expected ") + what);
    return bytes_.substr(start, pos_ - start);
  }

  long integer(const char* what, long lo, long hi) {
    const std::string_view token = next(what);
    const auto value = detail::parse_number<long>(token);
    if (!value) fail("invalid " + std::string(what) + " '" + std::string(token) + "'");
    if (*value < lo || *value > hi)
      fail(std::string(what) + " " + std::to_string(*value) + " out of range [" +
           std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return *value;
  }

  // Bytes after the current position (P3: every sample takes at least two of them).
  std::size_t remaining() const { return bytes_.size() - pos_; }

  // P6: exactly one whitespace byte separates maxval from the raster.
  std::size_t raster_start() {
    if (pos_ >= bytes_.size() || !std::isspace(static_cast<unsigned char>(bytes_[pos_])))
      fail("missing whitespace before the binary raster");
    return pos_ + 1;
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_, line_, reason);
  }

 private:
  void skip_space_and_comments() {
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n') ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        if (c == '\n') ++line_;
        ++pos_;
      } else {
        break;
      }
    }
  }

  const std::string& path_;
  std::string_view bytes_;
  std::size_t pos_ = 0;
  long line_ = 1;
};

// Samples are sRGB-encoded display values; images in memory are linear. maxval 255 goes through
// the exact 8-bit table, so an 8-bit PPM written by write_ppm reads back to the same floats.
float decode_sample(long value, long maxval) {
  if (maxval == 255) return srgb_decode_8bit(static_cast<std::uint8_t>(value));
  return srgb_decode(static_cast<float>(value) / static_cast<float>(maxval));
}

}  // namespace

// Always P6, 8-bit sRGB: the one flavour every viewer reads. A grey image repeats its channel in
// R, G and B; a fourth (alpha) channel is dropped, PPM has none.
void write_ppm(const std::string& path, const Image& image) {
  if (image.channels < 1 || image.channels > 4 || image.channels == 2)
    throw IoError(path + ": PPM needs a 1, 3 or 4 channel image");
  std::string out =
      "P6\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n255\n";
  const std::size_t header = out.size();
  out.resize(header + static_cast<std::size_t>(image.width) * image.height * 3);
  std::size_t o = header;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = image.at(x, y, image.channels == 1 ? 0 : c);
        out[o++] = static_cast<char>(srgb_encode_8bit(v));
      }
    }
  }
  write_text_atomic(path, out);
}

Image read_ppm(const std::string& path) {
  const std::string bytes = detail::read_text_file(path);
  PpmTokens tokens(path, bytes);
  const std::string_view magic = tokens.next("magic number P3 or P6");
  if (magic != "P3" && magic != "P6")
    tokens.fail("unsupported magic '" + std::string(magic) + "' (expected P3 or P6)");
  // Bounded sizes: a corrupt header cannot make the reader allocate terabytes before the
  // raster-length check below.
  const long width = tokens.integer("width", 1, 1 << 16);
  const long height = tokens.integer("height", 1, 1 << 16);
  const long maxval = tokens.integer("maxval", 1, 65535);
  check_image_size(path, width, height);
  // The raster must be there before the image is allocated: a header alone must not
  // claim gigabytes.
  const std::size_t samples = static_cast<std::size_t>(width) * height * 3;
  if (magic == "P3") {
    if (tokens.remaining() + 1 < 2 * samples)
      tokens.fail("ASCII raster truncated: " + std::to_string(samples) + " samples need at least " +
                  std::to_string(2 * samples - 1) + " bytes, file has " +
                  std::to_string(tokens.remaining()));
    Image image(static_cast<int>(width), static_cast<int>(height), 3);
    for (float& v : image.data) v = decode_sample(tokens.integer("sample", 0, maxval), maxval);
    return image;
  }
  const std::size_t start = tokens.raster_start();
  const std::size_t sample_bytes = maxval > 255 ? 2 : 1;
  if (bytes.size() - start < samples * sample_bytes)
    tokens.fail("binary raster truncated: expected " + std::to_string(samples * sample_bytes) +
                " bytes, file has " + std::to_string(bytes.size() - start));
  Image image(static_cast<int>(width), static_cast<int>(height), 3);
  const auto* raster = reinterpret_cast<const unsigned char*>(bytes.data() + start);
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    // 16-bit samples are big-endian (netpbm).
    const long value = sample_bytes == 2 ? (raster[2 * i] << 8) | raster[2 * i + 1] : raster[i];
    if (value > maxval) tokens.fail("sample " + std::to_string(value) + " exceeds maxval");
    image.data[i] = decode_sample(value, maxval);
  }
  return image;
}

}  // namespace rtmini
