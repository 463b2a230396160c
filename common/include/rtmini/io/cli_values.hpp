#pragma once
// Comma-separated numbers on the command line ("--camera-pos 0,1,4.5"), shared by the apps'
// CLIs so that every vector flag is parsed and reported the same way.
#include <cmath>
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

inline Vec3d parse_vec3(const std::string& flag, const std::string& text) {
  const std::vector<double> v = parse_number_list(flag, text, 3);
  return {v[0], v[1], v[2]};
}

}  // namespace rtmini
