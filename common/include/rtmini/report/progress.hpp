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

 private:
  using Clock = std::chrono::steady_clock;
  double elapsed() const;
  void draw(double done, double total, double eta, bool final);

  std::string label_, unit_;
  bool enabled_ = false, terminal_ = false;
  Clock::time_point start_;
  double last_draw_ = -1e30;
};

// Seconds as h:mm:ss.
std::string format_hms(double seconds);

}  // namespace rtmini
