#pragma once
// Host loops on plain threads, for the host-side steps of a run whose Kokkos host space may be
// Serial (the CUDA build's): reading a mesh, expanding instances for the device. Each call starts
// and joins its own threads; use it for steps of milliseconds or more, not in inner loops.
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

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

// Calls fn(begin, end) over [0, n) cut into contiguous blocks of at least `min_block` items, one
// per thread, on at most `max_threads` threads (and at most the host's cores). The blocks depend
// only on n, min_block and the thread count; fn must make each item's result independent of which
// block holds it (so results are the same for any thread count).
template <class Fn>
void for_blocks_on_threads(std::size_t n, std::size_t min_block, std::size_t max_threads,
                           const Fn& fn) {
  const std::size_t cores = std::max<unsigned>(1, std::thread::hardware_concurrency());
  const std::size_t by_size = std::max<std::size_t>(1, n / std::max<std::size_t>(min_block, 1));
  const std::size_t threads = std::max<std::size_t>(1, std::min({cores, max_threads, by_size}));
  on_threads(threads, [&](std::size_t t) { fn(n * t / threads, n * (t + 1) / threads); });
}

}  // namespace rtmini
