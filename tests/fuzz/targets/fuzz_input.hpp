#pragma once
// What every fuzz target shares: the input bytes as files (the readers take paths, as the
// apps hand them what a user names), and the verdict. A reader given bad bytes must throw
// rtmini::InputError (the apps' exit 2, one "file:line: reason" line); any other exception,
// a crash, a sanitizer report, a leak or a timeout is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>

#include "rtmini/io/error.hpp"

// libhdf5 sizes some metadata buffers from the file: a corrupt size asks malloc for
// petabytes, malloc returns null and libhdf5 reports an error, which the reader turns into
// InputError; that is the behaviour to test, so ASan returns null too instead of stopping.
// Allocations that could succeed are still bounded: libFuzzer stops at any single malloc
// above -malloc_limit_mb (default: the 2 GiB RSS limit) and reports it as a finding.
extern "C" const char* __asan_default_options() { return "allocator_may_return_null=1"; }
// libhdf5 1.10 (Debian's) loses a few dozen bytes on some error paths for corrupt metadata
// (tests/data/bad/h5_lost_metadata.h5). That memory is libhdf5's own, unreachable from
// rtmini; handles rtmini leaves open stay reachable through libhdf5's ID table and are not
// what this hides. Every other leak is a finding. results/reliability/fuzz.md says so too.
extern "C" const char* __lsan_default_suppressions() { return "leak:libhdf5\n"; }

namespace rtmini::fuzz {

// A private directory of this process, removed at exit: in $TMPDIR if set, else in
// /dev/shm (memory: a disk-backed /tmp made every input cost milliseconds on a busy
// machine), else in /tmp.
inline const std::string& scratch_dir() {
  static const std::string dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::error_code ignored;
    const std::string base = tmp && *tmp                                          ? tmp
                             : std::filesystem::is_directory("/dev/shm", ignored) ? "/dev/shm"
                                                                                  : "/tmp";
    std::string d = base + "/rtmini-fuzz.XXXXXX";
    if (::mkdtemp(d.data()) == nullptr) {
      std::perror("rtmini fuzz: mkdtemp");
      std::abort();
    }
    static const std::string kept = d;
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(kept, ignored);
    });
    return d;
  }();
  return dir;
}

// Writes `bytes` to scratch_dir()/name; returns the path.
inline std::string write_scratch(const std::string& name, std::string_view bytes) {
  const std::string path = scratch_dir() + "/" + name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() ||
      std::fclose(f) != 0) {
    std::perror(path.c_str());
    std::abort();
  }
  return path;
}

inline std::string_view as_view(const std::uint8_t* data, std::size_t size) {
  return std::string_view(reinterpret_cast<const char*>(data), size);
}

// Splits at the first line "#%<name>" (a comment in OBJ and TOML, so a seed without the
// marker stays valid): the text before it and the text after it (empty when absent). Lets
// one input carry a second file, e.g. the MTL library of an OBJ.
inline std::pair<std::string_view, std::string_view> split_at_marker(std::string_view all,
                                                                     std::string_view name) {
  const std::string marker = "\n#%" + std::string(name) + "\n";
  const std::size_t at = all.find(marker);
  if (at == std::string_view::npos) return {all, std::string_view()};
  return {all.substr(0, at), all.substr(at + marker.size())};
}

// Runs `read`; an InputError is the right answer to bad bytes, anything else aborts with
// what was thrown (libFuzzer then saves the input as a crash).
template <class Fn>
void expect_input_error_only(Fn&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtmini fuzz: a reader threw %s, not InputError: %s\n", typeid(e).name(),
                 e.what());
    std::abort();
  }
}

}  // namespace rtmini::fuzz
