#include "rtmini/io/input_files.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "rtmini/io/error.hpp"

#ifdef RTMINI_HAVE_HDF5
// The checkpoints' dataset checksum (io/hdf5_file.cpp); only checkpoints use these hashes,
// and a build without HDF5 has none.
#define XXH_INLINE_ALL
#include <xxhash.h>
#else
#include "rtmini/report/hash.hpp"
#endif

namespace rtmini {
namespace {

std::string hex16(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::uint64_t file_content_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open the input to hash it");
  std::vector<char> buffer(1 << 20);
#ifdef RTMINI_HAVE_HDF5
  XXH64_state_t* state = XXH64_createState();
  XXH64_reset(state, 0);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    XXH64_update(state, buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  const std::uint64_t h = XXH64_digest(state);
  XXH64_freeState(state);
#else
  std::uint64_t h = fnv1a(nullptr, 0);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    h = fnv1a(buffer.data(), static_cast<std::size_t>(in.gcount()), h);
  }
#endif
  if (in.bad()) throw InputError(path, 0, "cannot read the input to hash it");
  return h;
}

std::vector<InputFileHash> hash_input_files(const std::vector<std::string>& paths) {
  std::vector<InputFileHash> out;
  for (const std::string& p : paths) {
    if (std::any_of(out.begin(), out.end(), [&](const InputFileHash& f) { return f.path == p; }))
      continue;
    out.push_back({p, file_content_hash(p)});
  }
  return out;
}

std::string format_input_hashes(const std::vector<InputFileHash>& files) {
  std::string out;
  for (const InputFileHash& f : files) out += hex16(f.hash) + " " + f.path + "\n";
  return out;
}

void verify_input_hashes(const std::string& checkpoint, const std::string& stored,
                         const std::vector<InputFileHash>& now) {
  const auto changed = [&](const std::string& input, const std::string& why) {
    throw InputError(input, 0,
                     why + " since the checkpoint " + checkpoint +
                         " was written; restart refused (run without --restart)");
  };
  std::istringstream lines(stored);
  std::string hash, path;
  std::vector<std::string> listed;
  while (lines >> hash && std::getline(lines >> std::ws, path)) {
    listed.push_back(path);
    const auto it = std::find_if(now.begin(), now.end(),
                                 [&](const InputFileHash& f) { return f.path == path; });
    if (it == now.end()) changed(path, "no longer an input of this run");
    if (hex16(it->hash) != hash) changed(path, "content changed");
  }
  for (const InputFileHash& f : now)
    if (std::find(listed.begin(), listed.end(), f.path) == listed.end())
      changed(f.path, "became an input");
}

}  // namespace rtmini
