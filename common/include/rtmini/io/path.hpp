#pragma once
// File-name helpers for every reader and writer that picks a format by the file's extension.
#include <string>

namespace rtmini {

// The extension of the last path component with its dot, lower-cased (".png" for "A.PNG"); ""
// when that component has no dot. A dot in a directory name does not count ("a.b/c" has none).
std::string lower_extension(const std::string& path);

}  // namespace rtmini
