#include "rtmini/io/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "rtmini/io/error.hpp"

namespace rtmini {
namespace {

std::string parent_directory(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Flushes tmp's data to stable storage: on filesystems with delayed allocation
// a full disk is only reported here.
bool sync_file(const std::string& tmp) {
  const int fd = ::open(tmp.c_str(), O_RDONLY);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  return ::close(fd) == 0 && ok;
}

// The directory entry of the rename must survive a crash too (best effort:
// some filesystems refuse fsync on directories).
void sync_directory(const std::string& path) {
  const int fd = ::open(parent_directory(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

// Checked before any work: renaming over a directory fails only at the end of a long run, and
// a device (-o /dev/null) would be replaced by a regular file. stat() follows symbolic links,
// so a link to a regular file is accepted (the rename then replaces the link itself).
void check_replaceable(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;  // absent (or unreachable: creating it will say)
  if (!S_ISREG(st.st_mode))
    throw IoError(path + ": refusing to replace something that is not a regular file");
}

void check_output_place(const std::string& path, double expected_bytes) {
  const std::string dir = parent_directory(path);
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw IoError(path + ": cannot write here: the directory " + dir + " does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw IoError(path + ": cannot write here: the directory " + dir + " is not writable (" +
                  std::strerror(errno) + ")");
  check_replaceable(path);
  struct statvfs fs {};
  if (expected_bytes > 0 && ::statvfs(dir.c_str(), &fs) == 0) {
    const double free_bytes = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
    if (free_bytes < expected_bytes)
      throw IoError(path + ": needs ~" + std::to_string(static_cast<long long>(expected_bytes)) +
                    " bytes, " + std::to_string(static_cast<long long>(free_bytes)) +
                    " free on its filesystem");
  }
}

void check_output_places(const std::vector<std::pair<std::string, double>>& outputs) {
  // One file named for two outputs (-o out.bs --summary out.bs) ran to exit 0 with the second
  // writer's bytes in it and the first output lost.
  std::vector<std::filesystem::path> seen;
  for (const auto& [path, bytes] : outputs) {
    if (path.empty()) continue;
    std::error_code ec;
    const std::filesystem::path p =
        std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    if (std::find(seen.begin(), seen.end(), p) != seen.end())
      throw InputError(path + ": named for two outputs of this run; give each its own file");
    seen.push_back(p);
  }
  for (const auto& [path, bytes] : outputs)
    if (!path.empty()) check_output_place(path, bytes);
}

// Removes PATH.tmp.<pid> files left by runs that died before their rename. Only when the pid
// is gone (kill(pid, 0) fails with ESRCH): a live run's temporary, or another user's (EPERM),
// is left alone. At most 9 digits, so std::stol cannot overflow on a crafted name.
void remove_stale_temporaries(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string prefix = (slash == std::string::npos ? path : path.substr(slash + 1)) + ".tmp.";
  const std::string dir = parent_directory(path);
  DIR* d = ::opendir(dir.c_str());
  if (!d) return;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(digits);
    if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours
    const std::string full = dir + "/" + name;
    struct stat st {};
    if (::lstat(full.c_str(), &st) == 0 && S_ISREG(st.st_mode)) std::remove(full.c_str());
  }
  ::closedir(d);
}

void commit_temporary(const std::string& tmp, const std::string& path,
                      std::int64_t expected_bytes) {
  struct stat st {};
  std::string problem;
  if (::stat(tmp.c_str(), &st) != 0)
    problem = "the temporary file vanished";
  else if (expected_bytes >= 0 && static_cast<std::int64_t>(st.st_size) != expected_bytes)
    problem = "short write (" + std::to_string(st.st_size) + " of " +
              std::to_string(expected_bytes) + " bytes reached the disk)";
  else if (!sync_file(tmp))
    problem = std::string("cannot sync to disk: ") + std::strerror(errno);
  else if (std::rename(tmp.c_str(), path.c_str()) != 0)
    problem = std::string("cannot rename temporary file into place: ") + std::strerror(errno);
  if (!problem.empty()) {
    std::remove(tmp.c_str());
    throw IoError(path + ": " + problem);
  }
  sync_directory(path);
}

void write_file_atomic(const std::string& path,
                       const std::function<void(const std::string& tmp_path)>& write,
                       std::int64_t expected_bytes) {
  check_replaceable(path);
  remove_stale_temporaries(path);
  // Same directory as the target (rename is atomic only within one filesystem); the pid keeps
  // two runs writing the same path apart and tells a dead run's leftovers from a live one's.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  commit_temporary(tmp, path, expected_bytes);
}

void write_text_atomic(const std::string& path, std::string_view bytes) {
  write_file_atomic(
      path,
      [&](const std::string& tmp) {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw IoError(path + ": cannot create file: " + std::strerror(errno));
        const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        // fclose flushes, so its failure (e.g. disk full) is a write failure too.
        const bool closed = std::fclose(f) == 0;
        if (!wrote || !closed) throw IoError(path + ": write failed: " + std::strerror(errno));
      },
      static_cast<std::int64_t>(bytes.size()));
}

}  // namespace rtmini
