#include "rtmini/report/common_options.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <regex>
#include <string>

#include "rtmini/io/error.hpp"
#include "rtmini/kokkos_compat.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini {
namespace {

// Thrown from the --kokkos-help callback so that it wins over missing required arguments,
// exactly as CLI11 does for --help and --version.
struct CallForKokkosHelp : CLI::Success {
  CallForKokkosHelp() : CLI::Success("kokkos help", CLI::ExitCodes::Success) {}
};

// Kokkos reads some KOKKOS_* variables itself. Kokkos 4 aborts every rank (a backtrace each)
// on a value it cannot parse, where Kokkos 3.4 read "ON" as true and other words as false; the
// first CUDA run of the fault tests met exactly that with KOKKOS_DISABLE_WARNINGS=ON. So the
// values both versions read alike are checked before Kokkos starts, and anything else is bad
// input: one line and exit 2 on every rank.
void check_kokkos_environment() {
  static const std::regex boolean("yes|true|1|no|false|0", std::regex::icase);
  static const std::regex integer("-?[0-9]+");
  const auto check = [](const char* name, const std::regex& form, const char* allowed) {
    const char* value = std::getenv(name);
    if (value && !std::regex_match(value, form))
      throw InputError(std::string("environment: ") + name + "=" + value + ": Kokkos takes " +
                       allowed);
  };
  for (const char* name :
       {"KOKKOS_DISABLE_WARNINGS", "KOKKOS_PRINT_CONFIGURATION", "KOKKOS_TUNE_INTERNALS"})
    check(name, boolean, "yes, true, 1, no, false or 0");
  for (const char* name : {"KOKKOS_NUM_THREADS", "KOKKOS_DEVICE_ID"})
    check(name, integer, "an integer");
}

}  // namespace

void add_common_options(CLI::App& app, CommonOptions& options) {
  // Every option's default in --help, including the ones added after this call.
  app.option_defaults()->always_capture_default();
  app.add_option("--threads", options.threads,
                 "host threads per rank (0 = OMP_NUM_THREADS, else every core)")
      ->check(CLI::NonNegativeNumber)
      ->group("Common");
  app.add_option("--summary", options.summary, "write the JSON run summary here")->group("Common");
  app.add_option("--timings", options.timings, "write per-rank timings (HDF5) here")
      ->group("Common");
  app.add_flag("--progress", options.progress,
               "progress with rate and ETA on stderr (default: only when stderr is a terminal)")
      ->group("Common");
  app.add_option("--max-memory", options.max_memory,
                 "memory per rank the run may use (e.g. 2G, 512M, or 'unlimited'); default: "
                 "what the node (cgroup limit, MemAvailable) and device offer, shared among the "
                 "ranks on them")
      ->group("Common");
  app.add_flag_callback(
         "--version", [] { throw CLI::CallForVersion(); }, "print the build banner and exit")
      ->group("Common");
  app.add_flag_callback(
         "--kokkos-help", [] { throw CallForKokkosHelp(); },
         "print Kokkos' own runtime options and exit (rtmini takes them from KOKKOS_* "
         "environment variables, not from the command line)")
      ->group("Common");
}

int host_thread_request(int threads_option, const char* kokkos_num_threads,
                        const char* omp_num_threads, int available, int limit, bool* capped) {
  *capped = false;
  const auto refuse = [limit](const std::string& source) {
    throw InputError(source + ": Kokkos' OpenMP backend runs at most " + std::to_string(limit) +
                     " threads per process; run more ranks per node instead");
  };
  if (threads_option > limit) refuse("--threads " + std::to_string(threads_option));
  if (threads_option > 0) return threads_option;
  if (kokkos_num_threads && std::atoi(kokkos_num_threads) > limit)
    refuse(std::string("KOKKOS_NUM_THREADS=") + kokkos_num_threads);
  if (kokkos_num_threads) return 0;
  // OMP_NUM_THREADS may be a list (nested levels): its first value is this level's.
  if (omp_num_threads && std::atoi(omp_num_threads) > limit)
    refuse(std::string("OMP_NUM_THREADS=") + omp_num_threads);
  if (omp_num_threads && std::atoi(omp_num_threads) > 0) return 0;
  if (available <= limit) return 0;
  *capped = true;
  return limit;
}

void start_kokkos(const CommonOptions& options, bool root) {
  if (Kokkos::is_initialized()) return;
  // Kokkos' OpenMP backend warns on every run when OMP_PROC_BIND is unset. The OpenMP runtime
  // has read its environment when the program was loaded, so saying "false" here changes no
  // binding (unset with no OMP_PLACES means unbound in libgomp); it only tells Kokkos that the
  // choice was made. Users who want pinned threads set OMP_PROC_BIND/OMP_PLACES themselves,
  // and those are passed through untouched.
  if (!std::getenv("OMP_PROC_BIND") && !std::getenv("OMP_PLACES") &&
      !std::getenv("GOMP_CPU_AFFINITY"))
    setenv("OMP_PROC_BIND", "false", 0);
  check_kokkos_environment();
  int threads = options.threads;
#ifdef KOKKOS_ENABLE_OPENMP
  constexpr int kOpenMPMaxThreads = 512;  // OpenMPTraits::MAX_THREAD_COUNT in 3.4 and 4.x
  bool capped = false;
  threads = host_thread_request(options.threads, std::getenv("KOKKOS_NUM_THREADS"),
                                std::getenv("OMP_NUM_THREADS"), omp_get_max_threads(),
                                kOpenMPMaxThreads, &capped);
  if (capped && root)
    std::fprintf(stderr,
                 "note: %d hardware threads here; Kokkos' OpenMP backend runs at most %d per "
                 "process, so this rank uses %d (more ranks per node use them all)\n",
                 omp_get_max_threads(), kOpenMPMaxThreads, kOpenMPMaxThreads);
#endif
  compat::initialize(threads);
}

// Every rank parses the same argv and so takes the same branch: help and version are printed
// once (rank 0) and every rank returns the same exit code, so none is left in a collective. A
// malformed command line becomes an InputError (exit 2, one line), never CLI11's own exit codes.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      const CommonOptions& options, bool root) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    if (root) std::fputs(app.help().c_str(), stdout);
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    if (root) std::printf("%s\n", build_banner().c_str());
    return kExitOk;
  } catch (const CallForKokkosHelp&) {
    if (root) compat::print_kokkos_help(argv[0]);
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    throw InputError(std::string(e.what()) + " (see --help)");
  }
  start_kokkos(options, root);
  return std::nullopt;
}

std::int64_t CommonOptions::memory_limit() const {
  return parse_memory_limit("--max-memory", max_memory);
}

bool progress_wanted(const CommonOptions& options) {
  return options.progress || ::isatty(STDERR_FILENO);
}

}  // namespace rtmini
