#pragma once
// Clean early stop on a batch system's warning: SIGTERM (Slurm at the time limit,
// scancel), SIGUSR1 (sbatch --signal=USR1@T) and SIGINT (Ctrl-C, or mpirun forwarding it)
// set a flag that the apps read between units of work; they then checkpoint and exit with
// kExitCheckpointed (4). app_main installs the handlers as its first instruction, before MPI
// and Kokkos start, so a signal during a long start-up stops the run at its first check.
#include <csignal>

namespace rtmini {

namespace detail {
inline volatile std::sig_atomic_t g_stop_requested = 0;
extern "C" inline void rtmini_request_stop(int) { g_stop_requested = 1; }
}  // namespace detail

inline void install_stop_handlers() {
  std::signal(SIGTERM, detail::rtmini_request_stop);
  std::signal(SIGUSR1, detail::rtmini_request_stop);
  // SIGINT only where it is not ignored: shells start background jobs with SIGINT ignored so
  // that Ctrl-C at the terminal leaves them running, and they keep it that way.
  if (std::signal(SIGINT, SIG_IGN) != SIG_IGN) std::signal(SIGINT, detail::rtmini_request_stop);
}

inline bool stop_requested() { return detail::g_stop_requested != 0; }

}  // namespace rtmini
