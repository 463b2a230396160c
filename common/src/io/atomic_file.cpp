#include "rtmini/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "rtmini/io/error.hpp"

namespace rtmini {

void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& tmp_path)>& write) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot rename temporary file into place: " + std::strerror(err));
  }
}

void write_text_atomic(const std::string& path, std::string_view bytes) {
  write_file_atomic(path, [&](const std::string& tmp) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw IoError(path + ": cannot create file: " + std::strerror(errno));
    const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    // fclose flushes, so its failure (e.g. disk full) is a write failure too.
    const bool closed = std::fclose(f) == 0;
    if (!wrote || !closed) throw IoError(path + ": write failed: " + std::strerror(errno));
  });
}

}  // namespace rtmini
