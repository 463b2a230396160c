#pragma once
// Errors raised at the boundary (readers, CLI). The apps map InputError to exit
// code 2 and IoError to exit code 3; the core assumes validated data.
#include <stdexcept>
#include <string>

namespace rtmini {

inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitResource = 3;
// Stopped early (time limit, SIGTERM/SIGUSR1) with a valid checkpoint: resubmit with --restart.
inline constexpr int kExitCheckpointed = 4;

// Malformed input. what() is "file:line: reason" (or "file: reason" when no line).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, long line, const std::string& reason)
      : std::runtime_error(format(file, line, reason)) {}
  explicit InputError(const std::string& reason) : std::runtime_error(reason) {}

 private:
  static std::string format(const std::string& file, long line, const std::string& reason) {
    return line > 0 ? file + ":" + std::to_string(line) + ": " + reason : file + ": " + reason;
  }
};

// A resource or I/O failure (cannot open, disk full, memory limit exceeded).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rtmini
