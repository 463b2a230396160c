#pragma once
// The apps' only view of MPI: a communicator with the few collectives they
// use, or, in a build without MPI, a one-rank stand-in with the same interface
// (as the baking paper's serial build did). It counts messages and bytes sent
// so per-rank timings can report communication volume.
//
// Failures are collective (issue 17): a rank that fails sends its exit code and
// one-line message to every rank over a private duplicate of the communicator
// (notify_failure). Every collective here is a non-blocking one completed by
// wait(), which also polls that channel, so a rank waiting for a peer that will
// never arrive throws PeerFailure instead of hanging; app_main() then agrees on
// the outcome (agree_outcome) and rank 0 prints the one line.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "rtmini/kokkos_compat.hpp"

#ifdef RTMINI_HAVE_MPI
#include <mpi.h>
#endif

namespace rtmini {

// Thrown on a rank that learns, inside a collective, that another rank failed:
// it unwinds this rank's stack so that every rank reaches app_main's agreement.
class PeerFailure : public std::runtime_error {
 public:
  PeerFailure(int rank, int code, const std::string& message)
      : std::runtime_error(message), rank_(rank), code_(code) {}
  int rank() const { return rank_; }
  int code() const { return code_; }

 private:
  int rank_, code_;
};

// What app_main reports once every rank has agreed: the exit code all ranks
// return and, on rank 0, the line to print (empty when nothing failed).
struct Outcome {
  int code = 0;
  std::string line;
  bool agreed = true;  // false: a peer never reached the agreement (the job must be aborted)
};

class Communicator {
 public:
#ifdef RTMINI_HAVE_MPI
  explicit Communicator(MPI_Comm comm = MPI_COMM_WORLD) : comm_(comm) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    MPI_Comm_dup(comm_, &fail_);
    // Ranks sharing this node's memory (the memory check divides the node among them).
    // Counted once here, where every rank passes, so that no later step blocks on it.
    MPI_Comm node = split_node();
    MPI_Comm_size(node, &node_size_);
    MPI_Comm_rank(node, &node_rank_);
    node_ranks_.resize(static_cast<std::size_t>(node_size_));
    MPI_Allgather(&rank_, 1, MPI_INT, node_ranks_.data(), 1, MPI_INT, node);
    MPI_Comm_free(&node);
  }
  MPI_Comm native() const { return comm_; }

  // Collective: a new communicator of this rank's node, the ranks that share its memory
  // (MPI_COMM_TYPE_SHARED), in this communicator's order; the caller frees it. Test hook:
  // RTMINI_TEST_RANKS_PER_NODE=k cuts every node into groups of k consecutive ranks, so that
  // one machine runs what a job across nodes runs (ctest bake.distributed: node sharing with
  // halos between nodes). Each group still shares memory, as a node's ranks do.
  MPI_Comm split_node() const {
    MPI_Comm node = MPI_COMM_NULL;
    MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    const char* k = std::getenv("RTMINI_TEST_RANKS_PER_NODE");
    const int per_node = k ? std::atoi(k) : 0;
    if (per_node <= 0) return node;
    int node_rank = 0;
    MPI_Comm_rank(node, &node_rank);
    MPI_Comm group = MPI_COMM_NULL;
    MPI_Comm_split(node, node_rank / per_node, rank_, &group);
    MPI_Comm_free(&node);
    return group;
  }
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;

  // Completes `req`, throwing PeerFailure as soon as another rank reports a
  // failure. Spins briefly (collectives are usually microseconds), then backs
  // off to sleeps of up to 1 ms so an idle rank does not take a core from a
  // rank that still computes.
  void wait(MPI_Request& req) const {
    int done = 0;
    for (int spin = 0;; ++spin) {
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
      if (done) return;
      check_peers();
      if (spin > 1000)
        std::this_thread::sleep_for(std::chrono::microseconds(spin > 3000 ? 1000 : 50));
    }
  }
  // wait() for a collective whose buffers `owned` holds (vectors, moved from on failure). A
  // collective that a failed peer never joins stays in MPI's progress engine, which may go on
  // reading and writing its buffers while the ranks agree on the exit code; freed under it, they
  // crash or corrupt that agreement. So on PeerFailure the buffers move to abandoned_, kept until
  // the process exits, before the exception unwinds the caller.
  template <class... Owned>
  void wait_keeping(MPI_Request& req, Owned&... owned) const {
    try {
      wait(req);
    } catch (const PeerFailure&) {
      (keep_until_exit(owned), ...);
      throw;
    }
  }
  // Moves `buffers` to abandoned_, kept until the process exits. For an object destroyed while
  // requests on its buffers may still be in flight (a failure unwinding past it), for the
  // reason wait_keeping() gives.
  template <class T>
  void keep_until_exit(T& buffers) const {
    static_assert(!std::is_const<T>::value, "a const buffer would be copied, not kept");
    abandoned_.push_back(std::make_shared<T>(std::move(buffers)));
  }
  // MPI_Probe on `comm` (a duplicate of this one) that throws PeerFailure
  // instead of waiting forever for a failed peer.
  MPI_Status probe(int source, int tag, MPI_Comm comm) const {
    MPI_Status st;
    int flag = 0;
    for (int spin = 0;; ++spin) {
      MPI_Iprobe(source, tag, comm, &flag, &st);
      if (flag) return st;
      check_peers();
      if (spin > 1000)
        std::this_thread::sleep_for(std::chrono::microseconds(spin > 3000 ? 1000 : 50));
    }
  }
  // A private duplicate for point-to-point traffic of one component (its own
  // tag space); non-blocking so that a failed peer cannot hang it.
  MPI_Comm duplicate() const {
    std::vector<MPI_Comm> out(1, MPI_COMM_NULL);
    MPI_Request req;
    MPI_Comm_idup(comm_, out.data(), &req);
    wait_keeping(req, out);
    return out[0];
  }
  // Throws PeerFailure when another rank has reported a failure. For loops
  // that wait on their own point-to-point traffic.
  void check_peers() const {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, kFailTag, fail_, &flag, &st);
    if (!flag) return;
    const FailureNote& n = receive_note(st.MPI_SOURCE);
    throw PeerFailure(st.MPI_SOURCE, n.code, n.text);
  }
#else
  Communicator() = default;
  void check_peers() const {}
#endif

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }
  // Ranks on this rank's node (shared memory), and this rank's number among them.
  int node_size() const { return node_size_; }
  int node_rank() const { return node_rank_; }
  // The ranks on this rank's node, ascending (split_node keeps this communicator's order).
  const std::vector<int>& node_ranks() const { return node_ranks_; }

  void barrier() const {
#ifdef RTMINI_HAVE_MPI
    MPI_Request req;
    MPI_Ibarrier(comm_, &req);
    wait(req);
#endif
  }

  double max(double v) const { return reduce(v, kMax); }
  double min(double v) const { return reduce(v, kMin); }
  double sum(double v) const { return reduce(v, kSum); }
  std::int64_t sum(std::int64_t v) const { return reduce(v, kSum); }
  // Sum of 64-bit words modulo 2^64 (verification hashes).
  std::uint64_t sum_wrap(std::uint64_t v) const { return reduce(v, kSum); }

  // Every rank's `mine`, concatenated in rank order, on every rank (MPI_Allgatherv).
  template <class T>
  std::vector<T> allgatherv(const std::vector<T>& mine) const {
    static_assert(std::is_trivially_copyable<T>::value, "allgatherv needs trivially copyable data");
#ifdef RTMINI_HAVE_MPI
    auto counts = byte_counts(mine.size() * sizeof(T));  // not const: wait_keeping may move it
    std::vector<int> displs(size_, 0);
    for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    const long long total = static_cast<long long>(displs[size_ - 1]) + counts[size_ - 1];
    std::vector<T> out(static_cast<std::size_t>(total) / sizeof(T));
    std::vector<T> send(mine);  // the caller's may be freed while a failed collective holds it
    MPI_Request req;
    MPI_Iallgatherv(send.data(), counts[rank_], MPI_BYTE, out.data(), counts.data(), displs.data(),
                    MPI_BYTE, comm_, &req);
    wait_keeping(req, send, out, counts, displs);
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
    auto counts = byte_counts(mine.size() * sizeof(T));  // not const: wait_keeping may move it
    std::vector<int> displs(size_, 0);
    for (int r = 1; r < size_; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    const long long total = static_cast<long long>(displs[size_ - 1]) + counts[size_ - 1];
    std::vector<T> out(rank_ == root ? static_cast<std::size_t>(total) / sizeof(T) : 0);
    std::vector<T> send(mine);  // the caller's may be freed while a failed collective holds it
    MPI_Request req;
    MPI_Igatherv(send.data(), counts[rank_], MPI_BYTE, out.data(), counts.data(), displs.data(),
                 MPI_BYTE, root, comm_, &req);
    wait_keeping(req, send, out, counts, displs);
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
    std::vector<std::uint64_t> size{data.size()};
    MPI_Request req;
    MPI_Ibcast(size.data(), 1, MPI_UINT64_T, root, comm_, &req);
    wait_keeping(req, size);
    const std::uint64_t n = size[0];
    data.resize(n);
    check_int(n * sizeof(T));
    MPI_Ibcast(data.data(), static_cast<int>(n * sizeof(T)), MPI_BYTE, root, comm_, &req);
    wait_keeping(req, data);
    if (rank_ == root) count(n * sizeof(T) * static_cast<std::size_t>(size_ - 1));
#else
    (void)data;
    (void)root;
#endif
  }

  // Tells every other rank, once, that this rank failed with `code` and the
  // one-line `message`. Never blocks: the notes are small (eager) sends whose
  // buffer outlives the communicator.
  void notify_failure(int code, const std::string& message) const {
#ifdef RTMINI_HAVE_MPI
    if (notified_ || size_ == 1) return;
    notified_ = true;
    static FailureNote note;  // sends complete after this object is gone
    note = make_note(code, message);
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      MPI_Request req;
      MPI_Isend(&note, sizeof note, MPI_BYTE, r, kFailTag, fail_, &req);
      MPI_Request_free(&req);
    }
#else
    (void)code;
    (void)message;
#endif
  }

  // Every rank's outcome, agreed: `failed` says whether this rank's own body
  // failed (with `code` and `message`); a rank that merely saw a peer fail, or
  // succeeded, passes false. The first failing rank (lowest number) decides
  // the code; rank 0 gets the line to print, naming that rank unless every
  // rank failed. A rank that already knows of a failure waits at most
  // `patience` seconds for the others and then returns agreed = false.
  Outcome agree_outcome(int code, bool failed, const std::string& message, const std::string& app,
                        double patience) const {
    Outcome out;
    out.code = code;
#ifdef RTMINI_HAVE_MPI
    if (size_ > 1) return agree_across_ranks(code, failed, message, app, patience);
#endif
    (void)patience;
    if (failed) out.line = app + ": " + message;
    return out;
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
  // One value through MPI_Iallreduce (double, int64 or uint64; unsigned sums wrap mod 2^64).
  template <class T>
  T reduce(T v, Op op) const {
    static_assert(std::is_same<T, double>::value || std::is_same<T, std::int64_t>::value ||
                      std::is_same<T, std::uint64_t>::value,
                  "reduce: double, int64 or uint64");
#ifdef RTMINI_HAVE_MPI
    const MPI_Datatype type = std::is_same<T, double>::value         ? MPI_DOUBLE
                              : std::is_same<T, std::int64_t>::value ? MPI_INT64_T
                                                                     : MPI_UINT64_T;
    std::vector<T> in_out{v, v};
    MPI_Request req;
    MPI_Iallreduce(&in_out[0], &in_out[1], 1, type,
                   op == kMax ? MPI_MAX : (op == kMin ? MPI_MIN : MPI_SUM), comm_, &req);
    wait_keeping(req, in_out);
    count(sizeof v);
    return in_out[1];
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
  static constexpr int kFailTag = 17;
  struct FailureNote {
    int code = 0;
    char text[1020] = {};  // below every transport's eager limit with the code
  };
  static FailureNote make_note(int code, const std::string& message) {
    FailureNote n;
    n.code = code;
    std::strncpy(n.text, message.c_str(), sizeof n.text - 1);
    return n;
  }
  // Rank `src`'s failure note: received now (it was sent before `src` could
  // reach any later step) or remembered from an earlier check_peers().
  const FailureNote& receive_note(int src) const {
    auto it = notes_.find(src);
    if (it != notes_.end()) return it->second;
    FailureNote n;
    MPI_Recv(&n, sizeof n, MPI_BYTE, src, kFailTag, fail_, MPI_STATUS_IGNORE);
    return notes_[src] = n;
  }
  Outcome agree_across_ranks(int code, bool failed, const std::string& message,
                             const std::string& app, double patience) const {
    using Clock = std::chrono::steady_clock;
    Outcome out;
    out.code = code;
    if (failed) notify_failure(code, message);
    int mine[2] = {failed ? 1 : 0, code};
    std::vector<int> all(2 * static_cast<std::size_t>(size_));
    MPI_Request req;
    MPI_Iallgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, fail_, &req);
    bool known = failed || !notes_.empty();
    Clock::time_point since = Clock::now();
    for (int spin = 0;; ++spin) {
      int done = 0;
      MPI_Test(&req, &done, MPI_STATUS_IGNORE);
      if (done) break;
      if (!known) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, kFailTag, fail_, &flag, &st);
        if (flag) {
          receive_note(st.MPI_SOURCE);
          known = true;
          since = Clock::now();
        }
      } else if (std::chrono::duration<double>(Clock::now() - since).count() > patience) {
        // A peer is stuck outside any collective: report what this rank knows.
        out.agreed = false;
        if (!failed) {
          const FailureNote& n = notes_.begin()->second;
          out.code = n.code;
          out.line = app + " (rank " + std::to_string(notes_.begin()->first) + "): " + n.text;
        } else {
          out.line = app + " (rank " + std::to_string(rank_) + "): " + message;
        }
        return out;
      }
      if (spin > 1000) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    int first = -1, failures = 0;
    for (int r = 0; r < size_; ++r) {
      if (!all[2 * static_cast<std::size_t>(r)]) continue;
      if (first < 0) first = r;
      ++failures;
    }
    if (first < 0) return out;
    out.code = all[2 * static_cast<std::size_t>(first) + 1];
    if (rank_ == 0) {
      const std::string text = first == 0 ? message : std::string(receive_note(first).text);
      out.line = failures == size_ ? app + ": " + text
                                   : app + " (rank " + std::to_string(first) + "): " + text;
    }
    return out;
  }
  std::vector<int> byte_counts(std::size_t my_bytes) const {
    check_int(my_bytes);
    std::vector<int> mine{static_cast<int>(my_bytes)};
    std::vector<int> counts(size_);
    MPI_Request req;
    MPI_Iallgather(mine.data(), 1, MPI_INT, counts.data(), 1, MPI_INT, comm_, &req);
    wait_keeping(req, mine, counts);
    long long total = 0;
    for (int c : counts) total += c;
    check_int(static_cast<std::size_t>(total));
    return counts;
  }
  MPI_Comm comm_ = MPI_COMM_WORLD;
  MPI_Comm fail_ = MPI_COMM_NULL;  // failure notes and the final agreement only
  mutable std::map<int, FailureNote> notes_;
  mutable bool notified_ = false;
  mutable std::vector<std::shared_ptr<void>> abandoned_;  // see wait_keeping()
#endif
  int rank_ = 0;
  int size_ = 1;
  int node_size_ = 1;
  int node_rank_ = 0;
  std::vector<int> node_ranks_{0};
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
  // Ends every rank now with `code`: only for a job whose ranks cannot agree
  // (one is stuck outside any collective), after the one line was printed.
  [[noreturn]] void abort(int code) {
    std::fflush(nullptr);
#ifdef RTMINI_HAVE_MPI
    MPI_Abort(MPI_COMM_WORLD, code);
#endif
    std::_Exit(code);
  }
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;
};

}  // namespace rtmini
