#pragma once
// File-name helpers for the readers and writers. Inline, so the host-only library (scene and
// glTF readers, built without Kokkos) uses the same ones as rtmini_common.
#include <algorithm>
#include <cctype>
#include <string>

namespace rtmini {

// The extension of the last path component with its dot, lower-cased (".png" for "A.PNG"); ""
// when that component has no dot. A dot in a directory name does not count ("a.b/c" has none).
inline std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  // Through unsigned char: std::tolower of a negative char (a UTF-8 byte) is undefined.
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The directory part of `path` with its trailing slash ("a/b/" for "a/b/c.gltf"), "" for a bare
// file name: prepended to a file name that a scene or glTF file gives relative to itself.
inline std::string directory_prefix(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace rtmini
