#pragma once
// Line-oriented text helpers shared by the OBJ pre-scan and the Bake Shop reader:
// whitespace splitting and locale-independent number parsing (std::from_chars),
// so "1,5" or "abc" in a number field is an error rather than a silent 0.
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rtmini/config.hpp"

namespace rtmini::detail {

// Readers keep numbers in double but the kernels compute in Real (float by default):
// a coordinate of 1e39 is finite when read and infinite once uploaded, so it is refused.
inline bool fits_real(double v) {
  return std::fabs(v) <= static_cast<double>(std::numeric_limits<Real>::max());
}
// Names the build's precision in those errors.
inline const char* real_range_name() {
  return sizeof(Real) == 4 ? "single-precision" : "double-precision";
}

// Reads a whole file; InputError("path: cannot open ...") when it cannot be read.
std::string read_text_file(const std::string& path);

// Splits on spaces/tabs; a trailing '\r' (CRLF files) is treated as whitespace.
std::vector<std::string_view> split_fields(std::string_view line);

// The whole field must be a number; a leading '+' is accepted as in strtod.
template <class T>
std::optional<T> parse_number(std::string_view s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && s.front() == '-') return {};
  }
  T value{};
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) return {};
  return value;
}

// Iterates over the lines of a text buffer, 1-based line numbers, without copying.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  // False at end of text. The line excludes '\n' and a trailing '\r'.
  bool next(std::string_view& line);
  long line_number() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long line_ = 0;
};

}  // namespace rtmini::detail
