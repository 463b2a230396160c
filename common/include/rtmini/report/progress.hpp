#pragma once
// The one progress line of every long phase: "label: [####....]  42.0%  3.1 Mpx/s  12 s
// elapsed  ETA 0:00:17". The ETA divides the estimated cost of the remaining work by the
// cost rate measured so far, not the remaining item count by the item rate: early items are
// often cheap (sky pixels, empty batches), so a linear-in-items ETA is far too low at first.
// Callers that have no cost estimate pass the item counts as costs (then the ETA is linear).
//
// On a terminal the line redraws in place (\r) at most twice a second; elsewhere (a log file,
// with --progress) it is a new line every few seconds, so a log shows the ETA over time.
#include <chrono>
#include <cstdint>
#include <string>

namespace rtmini {

class ProgressLine {
 public:
  // `enabled` false makes every call a no-op (non-root ranks, no terminal and no --progress).
  ProgressLine(std::string label, std::string unit, bool enabled);

  // `done` of `total` items (shown), `done_cost` of `total_cost` (any consistent unit: the ETA).
  void update(double done, double total, double done_cost, double total_cost);
  void update(double done, double total) { update(done, total, done, total); }
  // The final line (always drawn when enabled), ending the \r redraws with a newline.
  void finish(double done, double total);

  bool enabled() const { return enabled_; }
  // Whether update() would draw now: lets callers skip computing costs that would not be shown.
  bool due() const;
  // Seconds between two drawn lines (0.5 on a terminal, 2 in a log): work split into pieces to
  // report progress need not be split finer than this.
  double period() const;

 private:
  using Clock = std::chrono::steady_clock;
  double elapsed() const;
  void draw(double done, double total, double eta, bool final);

  std::string label_, unit_;
  bool enabled_ = false, terminal_ = false;
  Clock::time_point start_;
  double last_draw_ = -1e30;
};

// Splits the items [0, total) of one parallel loop into dispatches a progress line can report
// between. Each dispatch ends in a barrier, and on a loaded host in a wait for every thread to be
// scheduled again (10-20 ms measured on a shared 2-core machine, results/progress/), so 64 equal
// dispatches cost up to a third of a render there. The pieces are sized by measured time
// instead: the first is 1/64 of the items (at least min_items) to measure the rate, every later
// one about max(line.period(), 1 s) at the rate so far, and a remainder under half a piece joins
// the last one. Without a drawn line: one dispatch of everything. Callers must give the same
// results for any split (independent items, integer sums).
class TimedChunks {
 public:
  TimedChunks(std::int64_t total, const ProgressLine* line, std::int64_t min_items);
  // The next piece [begin, end); false once everything has been handed out.
  bool next(std::int64_t& begin, std::int64_t& end);

 private:
  using Clock = std::chrono::steady_clock;
  std::int64_t total_, min_items_, done_ = 0;
  double period_;  // 0: no line, one dispatch
  Clock::time_point start_;
};

// Seconds of work as a x items + b x probe cost, fitted by least squares to the pieces done so
// far. A probe (one cheap sample of an item's work: the rays, or the BVH steps, of one camera
// ray) ranks items by cost but does not see everything (more samples, shading, per-item
// overhead); the constant part a carries that, without which the ETA over-weights the costly
// items still to come.
class CostFit {
 public:
  void add(double seconds, double items, double probe_cost);
  // Estimated seconds of `items` items whose probe costs sum to `probe_cost`.
  double cost(double items, double probe_cost) const;

 private:
  double nn_ = 0, nc_ = 0, cc_ = 0, tn_ = 0, tc_ = 0;
};

// Seconds as h:mm:ss.
std::string format_hms(double seconds);

}  // namespace rtmini
