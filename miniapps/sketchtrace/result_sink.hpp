#pragma once
// Brings finished pixels to rank 0 while the render runs: other ranks send what
// they finished in batches (non-blocking, at most every flush interval or when a
// batch is large), rank 0 receives between its own dispatches. So rank 0 always
// holds a recent partial image to checkpoint (not per pixel: the hand-drawn paper
// hit the file system's limits that way), and the end of a run needs no big gather.
#include <cstdint>
#include <deque>
#include <vector>

#include "rtmini/parallel/communicator.hpp"
#include "schedule.hpp"
#include "trace_kernel.hpp"

namespace rtmini::sketch {

class ResultSink {
 public:
  // `frame` and `done` (rank 0: the whole image and its per-pixel done mask) receive
  // the pixels. flush_interval <= 0: other ranks send only when a batch is large or at the end.
  ResultSink(const Communicator& comm, const PixelOrder& order, std::vector<PixelResult>& frame,
             std::vector<std::uint8_t>& done, double flush_interval);
  ~ResultSink();
  ResultSink(const ResultSink&) = delete;
  ResultSink& operator=(const ResultSink&) = delete;

  // This rank finished `pixels` (in the order of `ranges`); `now` in seconds.
  void add(const std::vector<PosRange>& ranges, const std::vector<PixelResult>& pixels, double now);
  // Progresses sends; rank 0 merges what has arrived. Returns pixels merged on rank 0.
  std::int64_t poll(double now);
  // Collective: every rank's pixels are on rank 0 afterwards.
  void finish();
  // Rank 0: pixels of this run known to be finished so far.
  std::int64_t merged() const { return merged_; }

 private:
  struct Send {
    std::vector<std::uint8_t> bytes;
#ifdef RTMINI_HAVE_MPI
    MPI_Request req;
#endif
  };
  void merge(const std::int64_t* ranges, std::int64_t count, const PixelResult* pixels);
  void flush(bool final);
  void receive(bool block);

  const Communicator& comm_;
  const PixelOrder& order_;
  std::vector<PixelResult>& frame_;
  std::vector<std::uint8_t>& done_;
  double interval_, last_flush_ = 0;
  std::vector<std::int64_t> ranges_;  // buffered ranges, begin/end pairs
  std::vector<PixelResult> pixels_;   // buffered pixels
  std::deque<Send> sends_;
  std::int64_t merged_ = 0;
  int finals_ = 0;
#ifdef RTMINI_HAVE_MPI
  MPI_Comm mpi_ = MPI_COMM_NULL;
#endif
};

}  // namespace rtmini::sketch
