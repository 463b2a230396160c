#pragma once
// Atomic, verified output: every writer produces "path.tmp.<pid>" next to the
// target, checks what reached the file (its size after close, then fsync) and
// only then renames it into place, so a crash or a full disk never leaves a
// half-written file at the final path (issue 17). Only regular files are ever
// replaced: an output path naming a device, fifo or directory is refused.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rtmini {

// Calls write(tmp_path), verifies the temporary (expected_bytes when >= 0, else
// only that it exists) and renames it to path. On any failure the temporary is
// removed and the exception propagates; verification and rename failures are
// IoErrors.
void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& tmp_path)>& write,
                       std::int64_t expected_bytes = -1);

// Writes bytes to path atomically (IoError on failure).
void write_text_atomic(const std::string& path, std::string_view bytes);

// IoError unless path is absent or a regular file (a writer may replace it).
void check_replaceable(const std::string& path);

// Checks, before a run computes anything, that an output can be written at `path`: its
// directory exists and is writable (a read-only filesystem included), the path itself is
// replaceable, and the filesystem has `expected_bytes` free (statvfs; 0 = no size check).
// IoError with one line naming the path otherwise (exit 3).
void check_output_place(const std::string& path, double expected_bytes = 0);
// check_output_place for each (path, expected bytes) whose path is not empty; first an
// InputError (exit 2) when two of them name the same file.
void check_output_places(const std::vector<std::pair<std::string, double>>& outputs);

// Removes "path.tmp.<pid>" files that killed runs left behind: regular files
// only, and only when no process <pid> exists on this host any more.
void remove_stale_temporaries(const std::string& path);

// The size of tmp must be expected_bytes (when >= 0); then it is fsync'ed and
// renamed to path. On failure tmp is removed and an IoError names path.
void commit_temporary(const std::string& tmp, const std::string& path, std::int64_t expected_bytes);

}  // namespace rtmini
