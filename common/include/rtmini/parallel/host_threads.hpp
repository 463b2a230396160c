#pragma once
// Host work on plain threads, for host-side steps of a run whose Kokkos host space may be Serial
// (the CUDA build's), such as reading a mesh, or whose OpenMP workers would spin-wait after it
// (the host SAH build). Each call starts and joins its own threads; use it for steps of
// milliseconds or more, not in inner loops.
#include <cstddef>
#include <thread>
#include <vector>
#if defined(__linux__)
#include <sched.h>
#endif

namespace rtmini {

// Calls fn(i) for i < n, each on a thread of its own, fn(0) on the calling thread (fn must not
// throw: an exception on a std::thread ends the process).
template <class Fn>
void on_threads(std::size_t n, const Fn& fn) {
  std::vector<std::thread> threads;
  for (std::size_t i = 1; i < n; ++i) threads.emplace_back(fn, i);
  if (n > 0) fn(0);
  for (std::thread& t : threads) t.join();
}

// The CPUs the calling thread may run on, which threads it starts inherit: one where OpenMP
// pinned it (OMP_PROC_BIND) or MPI bound its rank to a core.
inline std::size_t cpus_for_new_threads() {
#if defined(__linux__)
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return static_cast<std::size_t>(CPU_COUNT(&set));
#endif
  return std::thread::hardware_concurrency();
}

}  // namespace rtmini
