#include "rtmini/io/path.hpp"

#include <algorithm>
#include <cctype>

namespace rtmini {

std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  // Through unsigned char: std::tolower of a negative char (a UTF-8 byte) is undefined.
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace rtmini
