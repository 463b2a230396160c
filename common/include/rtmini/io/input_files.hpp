#pragma once
// The content of a run's input files as its checkpoint remembers them (issue 17): an XXH64 of
// the bytes of every file the run read (scene file, meshes, material libraries), stored in the
// checkpoint and compared on restart, so that a restart after any input changed is refused
// (InputError naming the file: exit 2) instead of finishing one scene's image or map with
// another's.
#include <cstdint>
#include <string>
#include <vector>

namespace rtmini {

struct InputFileHash {
  std::string path;
  std::uint64_t hash = 0;
};

// XXH64 (seed 0) of the file's bytes; InputError when it cannot be read.
std::uint64_t file_content_hash(const std::string& path);

// The files' hashes, in the given order, duplicates dropped.
std::vector<InputFileHash> hash_input_files(const std::vector<std::string>& paths);

// As stored in a checkpoint: one "<16 hex digits> <path>" line per file.
std::string format_input_hashes(const std::vector<InputFileHash>& files);

// Compares a checkpoint's stored hashes (format_input_hashes) with the files now:
// InputError "<input>: changed since the checkpoint <checkpoint> was written ..." for the
// first stored file whose content differs or that is gone, or a file read now that the
// checkpoint does not list.
void verify_input_hashes(const std::string& checkpoint, const std::string& stored,
                         const std::vector<InputFileHash>& now);

}  // namespace rtmini
