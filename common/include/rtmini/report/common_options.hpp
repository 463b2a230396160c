#pragma once
// The option group every rtmini program shares (--threads, --summary, --timings, --progress,
// --max-memory, --version, --kokkos-help), defined once so that the programs agree on spelling,
// defaults and behaviour, and the one parse step that turns a command line into either "go on"
// (Kokkos started from these settings) or an exit code (help, version: 0; bad usage: InputError ->
// 2).
//
// Kokkos is started here from the parsed settings, never from argv: Kokkos 3.4 parses argv
// itself and aborts on spellings it half-recognises (`--threads 1` without '='), and prints its
// own 40-line help in front of ours on `--help`.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

namespace rtmini {

struct CommonOptions {
  int threads = 0;         // host threads; 0 = OMP_NUM_THREADS / KOKKOS_NUM_THREADS / every core
  std::string summary;     // JSON run summary (rank 0)
  std::string timings;     // per-rank timings, HDF5 (rank 0 writes everyone's)
  bool progress = false;   // progress lines on stderr even when stderr is not a terminal
  std::string max_memory;  // per-rank memory limit for the up-front check, or "unlimited"

  // --max-memory as report/memory_check.hpp takes it (0 = check against the machine,
  // kMemoryUnlimited, or bytes); InputError for a malformed size.
  std::int64_t memory_limit() const;
};

// Adds the shared group to `app` (and makes `app` show every option's default in --help).
// Call it on each CLI11 subcommand too: options do not fall through from the parent.
void add_common_options(CLI::App& app, CommonOptions& options);

// Parses argv with `app`. Returns an exit code when the program should stop here (--help,
// --version, --kokkos-help; printed on rank 0 only), or nullopt after starting Kokkos with
// `options`. A malformed command line throws InputError with CLI11's one-line reason.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      const CommonOptions& options, bool root);

// Starts Kokkos from `options` (idempotent). For programs whose command line needs checks
// after parsing that must not start Kokkos first; parse_command_line calls it otherwise.
// `root` prints the one note of a capped host thread count (host_thread_request).
void start_kokkos(const CommonOptions& options, bool root = true);

// Kokkos' OpenMP backend (3.4 and 4.x alike) keeps its per-thread data in a fixed array of 512
// and writes past its end with more threads: every rtmini program died of a segfault at
// start-up with OMP_NUM_THREADS=600. The host threads a run asks Kokkos for, given what was
// requested (--threads, else KOKKOS_NUM_THREADS, else OMP_NUM_THREADS) or, with none, what the
// node offers (`available`): an explicit request above `limit` is bad input
// (InputError naming its source); the node's own count is capped at `limit` (*capped = true).
// 0 = leave the choice to Kokkos.
int host_thread_request(int threads_option, const char* kokkos_num_threads,
                        const char* omp_num_threads, int available, int limit, bool* capped);

// Whether a progress reporter should draw: asked for, or stderr is a terminal.
bool progress_wanted(const CommonOptions& options);

}  // namespace rtmini
