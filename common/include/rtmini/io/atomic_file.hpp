#pragma once
// Atomic output: every writer produces "path.tmp.<pid>" next to the target and
// renames it into place, so a crash or a full disk never leaves a half-written file.
#include <functional>
#include <string>
#include <string_view>

namespace rtmini {

// Calls write(tmp_path), then renames tmp_path to path. On any exception the
// temporary is removed and the exception propagates. Rename failure is an IoError.
void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& tmp_path)>& write);

// Writes bytes to path atomically (IoError on failure).
void write_text_atomic(const std::string& path, std::string_view bytes);

}  // namespace rtmini
