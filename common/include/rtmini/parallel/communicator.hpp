#pragma once
// The apps' only view of MPI: a communicator with the few collectives they
// use, or, in a build without MPI, a one-rank stand-in with the same interface
// (as the baking paper's serial build did). It counts messages and bytes sent
// so per-rank timings can report communication volume.
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "rtmini/kokkos_compat.hpp"

#ifdef RTMINI_HAVE_MPI
#include <mpi.h>
#endif

namespace rtmini {

class Communicator {
 public:
#ifdef RTMINI_HAVE_MPI
  explicit Communicator(MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
  }
  MPI_Comm native() const { return comm_; }
#else
  Communicator() = default;
#endif

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  void barrier() const {
#ifdef RTMINI_HAVE_MPI
    MPI_Barrier(comm_);
#endif
  }

  double max(double v) const { return reduce(v, kMax); }
  double min(double v) const { return reduce(v, kMin); }
  double sum(double v) const { return reduce(v, kSum); }
  std::int64_t sum(std::int64_t v) const {
#ifdef RTMINI_HAVE_MPI
    std::int64_t out = 0;
    MPI_Allreduce(&v, &out, 1, MPI_INT64_T, MPI_SUM, comm_);
    count(sizeof v);
    return out;
#else
    return v;
#endif
  }
  // Sum of 64-bit words modulo 2^64 (verification hashes).
  std::uint64_t sum_wrap(std::uint64_t v) const {
#ifdef RTMINI_HAVE_MPI
    std::uint64_t out = 0;
    MPI_Allreduce(&v, &out, 1, MPI_UINT64_T, MPI_SUM, comm_);
    count(sizeof v);
    return out;
#else
    return v;
#endif
  }

  // Every rank's `mine`, concatenated in rank order, on every rank (MPI_Allgatherv).
  template <class T>
  std::vector<T> allgatherv(const std::vector<T>& mine) const {
    static_assert(std::is_trivially_copyable<T>::value, "allgatherv needs trivially copyable data");
#ifdef RTMINI_HAVE_MPI
    const auto counts = byte_counts(mine.size() * sizeof(T));
    std::vector<int> displs(size_, 0);
    for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    const long long total = static_cast<long long>(displs[size_ - 1]) + counts[size_ - 1];
    std::vector<T> out(static_cast<std::size_t>(total) / sizeof(T));
    MPI_Allgatherv(mine.data(), counts[rank_], MPI_BYTE, out.data(), counts.data(), displs.data(),
                   MPI_BYTE, comm_);
    count(static_cast<std::size_t>(counts[rank_]) * static_cast<std::size_t>(size_ - 1));
    return out;
#else
    return mine;
#endif
  }

  // Every rank's `mine` concatenated in rank order on rank `root` (empty elsewhere).
  template <class T>
  std::vector<T> gatherv(const std::vector<T>& mine, int root = 0) const {
    static_assert(std::is_trivially_copyable<T>::value, "gatherv needs trivially copyable data");
#ifdef RTMINI_HAVE_MPI
    const auto counts = byte_counts(mine.size() * sizeof(T));
    std::vector<int> displs(size_, 0);
    for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    const long long total = static_cast<long long>(displs[size_ - 1]) + counts[size_ - 1];
    std::vector<T> out(rank_ == root ? static_cast<std::size_t>(total) / sizeof(T) : 0);
    MPI_Gatherv(mine.data(), counts[rank_], MPI_BYTE, out.data(), counts.data(), displs.data(),
                MPI_BYTE, root, comm_);
    if (rank_ != root) count(static_cast<std::size_t>(counts[rank_]));
    return out;
#else
    (void)root;
    return mine;
#endif
  }

  template <class T>
  void broadcast(std::vector<T>& data, int root = 0) const {
#ifdef RTMINI_HAVE_MPI
    std::uint64_t n = data.size();
    MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm_);
    data.resize(n);
    check_int(n * sizeof(T));
    MPI_Bcast(data.data(), static_cast<int>(n * sizeof(T)), MPI_BYTE, root, comm_);
    if (rank_ == root) count(n * sizeof(T) * static_cast<std::size_t>(size_ - 1));
#else
    (void)data;
    (void)root;
#endif
  }

  std::int64_t bytes_sent() const { return bytes_; }
  std::int64_t messages_sent() const { return messages_; }
  // For point-to-point code that talks to MPI directly but wants the counts.
  void count(std::size_t bytes) const {
    bytes_ += static_cast<std::int64_t>(bytes);
    ++messages_;
  }

 private:
  enum Op { kMax, kMin, kSum };
  double reduce(double v, Op op) const {
#ifdef RTMINI_HAVE_MPI
    double out = v;
    MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, op == kMax ? MPI_MAX : (op == kMin ? MPI_MIN : MPI_SUM),
                  comm_);
    count(sizeof v);
    return out;
#else
    (void)op;
    return v;
#endif
  }
  static void check_int(std::size_t bytes) {
    if (bytes > static_cast<std::size_t>(2147483647))
      throw std::runtime_error("rtmini: a single collective message exceeds 2 GiB; use more ranks");
  }
#ifdef RTMINI_HAVE_MPI
  std::vector<int> byte_counts(std::size_t my_bytes) const {
    check_int(my_bytes);
    int mine = static_cast<int>(my_bytes);
    std::vector<int> counts(size_);
    MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    long long total = 0;
    for (int c : counts) total += c;
    check_int(static_cast<std::size_t>(total));
    return counts;
  }
  MPI_Comm comm_ = MPI_COMM_WORLD;
#endif
  int rank_ = 0;
  int size_ = 1;
  mutable std::int64_t bytes_ = 0;
  mutable std::int64_t messages_ = 0;
};

// The thread level MPI granted (0 = single, or no MPI), and the lock that
// serialises MPI calls when a rank runs a communication thread beside the
// thread that renders (sketchtrace --comm-thread).
inline int& mpi_thread_level() {
  static int level = 0;
  return level;
}
inline std::mutex& mpi_mutex() {
  static std::mutex m;
  return m;
}
inline bool mpi_serialized_threads() {
#ifdef RTMINI_HAVE_MPI
  return mpi_thread_level() >= MPI_THREAD_SERIALIZED;
#else
  return false;
#endif
}

// Owns MPI and Kokkos for the lifetime of main(): MPI first (serialized
// threading: OpenMP threads never call MPI, and an optional communication
// thread takes turns with the main thread under mpi_mutex()), Kokkos second,
// reverse at exit.
class Environment {
 public:
  Environment(int& argc, char**& argv) {
#ifdef RTMINI_HAVE_MPI
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
    mpi_thread_level() = provided;
#endif
  }
  // Kokkos is started later, from the parsed options (report/common_options.hpp), and only
  // when the program goes on past its command line.
  ~Environment() {
    if (Kokkos::is_initialized()) Kokkos::finalize();
#ifdef RTMINI_HAVE_MPI
    MPI_Finalize();
#endif
  }
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;
};

}  // namespace rtmini
