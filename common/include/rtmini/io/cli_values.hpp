#pragma once
// Comma-separated numbers on the command line ("--camera-pos 0,1,4.5"), shared by the apps'
// CLIs so that every vector flag is parsed and reported the same way.
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini {

// Exactly `count` finite numbers separated by commas; InputError naming the flag otherwise.
inline std::vector<double> parse_number_list(const std::string& flag, const std::string& text,
                                             std::size_t count) {
  const std::string problem =
      flag + ": '" + text + "' is not a list of " + std::to_string(count) + " numbers";
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      const double v = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(v)) throw std::invalid_argument(item);
      out.push_back(v);
    } catch (const std::exception&) {
      throw InputError(problem);
    }
  }
  if (out.size() != count) throw InputError(problem);
  return out;
}

// A byte count with an optional binary unit ("2G", "512M", "1.5GiB", "1000000"), for
// --max-memory; InputError naming the flag for anything else, NaN/Inf and negatives.
inline std::int64_t parse_byte_size(const std::string& flag, const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(flag + ": not a size: '" + text + "' (e.g. 2G, 512M, 1000000)");
  }
  const std::string suffix = text.substr(used);
  double scale = 1;
  if (suffix == "K" || suffix == "k" || suffix == "KiB")
    scale = 1024.0;
  else if (suffix == "M" || suffix == "MiB")
    scale = 1024.0 * 1024.0;
  else if (suffix == "G" || suffix == "GiB")
    scale = 1024.0 * 1024.0 * 1024.0;
  else if (suffix == "T" || suffix == "TiB")
    scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else if (!suffix.empty() && suffix != "B")
    throw InputError(flag + ": unknown unit '" + suffix + "' (use K, M, G or T)");
  if (!(value >= 0) || !std::isfinite(value) || value * scale > 9.0e18)
    throw InputError(flag + " must be >= 0 (got " + text + ")");
  return static_cast<std::int64_t>(value * scale);
}

inline Vec3d parse_vec3(const std::string& flag, const std::string& text) {
  const std::vector<double> v = parse_number_list(flag, text, 3);
  return {v[0], v[1], v[2]};
}

}  // namespace rtmini
