#pragma once
// Load balancing of a render across MPI ranks (`--balance NAME`).
//
// Every strategy hands out ranges of one global pixel order: the pixels still to
// render, in 16x16 tiles (row-major tiles, row-major pixels inside a tile), so a
// range of 256 aligned positions is one screen tile. Pixels depend only on
// (scene, parameters, seed, pixel), so the image is identical for every strategy
// and rank count; only who renders what, and when, differs.
//
//   static   equal pixel counts per rank (the hand-drawn paper's naive split)
//   metric   equal probed cost per rank (one probe sample per 4x4 pixels)
//   chunks   chunks of ~64 pixels of mean cost, dealt round-robin
//   bargain  per-rank chunk queues; neighbours exchange remaining cost, a
//            non-blocking allreduce gives the average, ranks above it hand chunks
//            to a neighbour below it (non-blocking MPI progressed between batches)
//   queue    leader/worker: a tile counter in the leader's memory (an MPI window),
//            claimed with MPI_Fetch_and_op in guided-size batches; the leader renders
//   steal    each rank's tile range in an MPI window; owners take from the front,
//            idle ranks steal half of a random victim's rest (MPI_Compare_and_swap)
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rtmini/parallel/communicator.hpp"

namespace rtmini::sketch {

enum class Balance { kStatic, kMetric, kChunks, kBargain, kQueue, kSteal };

// InputError naming the accepted values on an unknown name.
Balance parse_balance(const std::string& name);
const char* to_string(Balance b);
// The strategies that cut the work by the probed cost map.
bool needs_cost_map(Balance b);

inline constexpr int kTile = 16;

// The pixels left to render (all, or those not `done` on a restart) in tile order.
class PixelOrder {
 public:
  PixelOrder(int width, int height, const std::vector<std::uint8_t>& done);
  std::int64_t size() const { return size_; }
  // The pixel index (y * width + x) at position pos in [0, size()).
  std::int64_t pixel(std::int64_t pos) const { return list_.empty() ? implicit(pos) : list_[pos]; }

 private:
  std::int64_t implicit(std::int64_t pos) const;
  int width_, height_;
  std::int64_t size_ = 0;
  std::vector<std::int64_t> list_;  // explicit when some pixels are done
};

// [begin, end) positions of a PixelOrder.
struct PosRange {
  std::int64_t begin = 0, end = 0;
  std::int64_t size() const { return end - begin; }
};

// Per-pixel cost estimates from a probe grid: one probe per stride x stride block.
struct CostMap {
  int width = 0, height = 0, stride = 4, grid_w = 0, grid_h = 0;
  std::vector<float> cost;  // [grid_h * grid_w], rays per camera sample
  double at(std::int64_t pixel) const {
    const int x = static_cast<int>(pixel % width), y = static_cast<int>(pixel / width);
    return cost[static_cast<std::size_t>(y / stride) * grid_w + x / stride];
  }
};

// Positions 0 = c[0] <= c[1] <= ... <= c[parts] = order.size() cutting the order into
// `parts` ranges of nearly equal cost (equal pixel counts without a cost map).
std::vector<std::int64_t> equal_cost_cuts(const PixelOrder& order, const CostMap* cost,
                                          std::int64_t parts);

// Consecutive chunks of about `pixels` pixels of mean cost each (cheap chunks are
// longer), covering the whole order; chunk k's cost is returned in costs[k].
std::vector<PosRange> cost_chunks(const PixelOrder& order, const CostMap& cost, std::int64_t pixels,
                                  std::vector<double>& costs);

class Scheduler {
 public:
  virtual ~Scheduler() = default;
  // The next ranges this rank renders (about the batch size in pixels). False when
  // the rank has no more work, or when should_stop() turned true while it waited.
  virtual bool next(std::vector<PosRange>& out, const std::function<bool()>& should_stop) = 0;
  // Leaves the schedule; collective. `stopping`: this rank stopped early.
  virtual void finish(bool stopping) { (void)stopping; }
  // Answers peers' messages; a communication thread calls it while this rank renders
  // (the caller serialises it with next()/finish() through rtmini::mpi_mutex()).
  virtual void progress() {}
  // Whether progress() does anything (peer-to-peer strategies).
  virtual bool has_progress() const { return false; }
};

// `cost` is needed by needs_cost_map(b) strategies; `batch` is the dispatch size in pixels.
std::unique_ptr<Scheduler> make_scheduler(Balance b, const Communicator& comm,
                                          const PixelOrder& order, const CostMap* cost,
                                          std::int64_t batch);

}  // namespace rtmini::sketch
