#include "rtmini/report/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rtmini {

namespace {
// Redraw period: fast enough to look alive on a terminal, sparse enough in a log file.
constexpr double kTerminalPeriod = 0.5;
constexpr double kLogPeriod = 2.0;
// Shortest dispatch TimedChunks aims for: a barrier wait of 10-20 ms on a loaded host then costs
// 1-2 %, and a terminal line still moves every second.
constexpr double kMinDispatchSeconds = 1.0;
}  // namespace

std::string format_hms(double seconds) {
  // Rounded to the nearest second and never negative: an ETA a little past due shows 0:00:00.
  const long s = static_cast<long>(std::max(0.0, seconds) + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  return buf;
}

ProgressLine::ProgressLine(std::string label, std::string unit, bool enabled)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      enabled_(enabled),
      // Checked once: whether stderr is a terminal does not change during a run.
      terminal_(::isatty(STDERR_FILENO) != 0),
      start_(Clock::now()) {}

double ProgressLine::elapsed() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

double ProgressLine::period() const { return terminal_ ? kTerminalPeriod : kLogPeriod; }

bool ProgressLine::due() const { return enabled_ && elapsed() - last_draw_ >= period(); }

void ProgressLine::update(double done, double total, double done_cost, double total_cost) {
  if (!due()) return;
  const double now = elapsed();
  last_draw_ = now;
  // No ETA before any cost is measured: a guess from nothing would be the least trustworthy.
  const double eta = done_cost > 0 ? (total_cost - done_cost) * now / done_cost : -1.0;
  draw(done, total, eta, false);
}

void ProgressLine::finish(double done, double total) {
  if (!enabled_) return;
  draw(done, total, 0.0, true);
}

void ProgressLine::draw(double done, double total, double eta, bool final) {
  const double now = elapsed();
  const double fraction = total > 0 ? std::min(1.0, done / total) : 1.0;
  const int width = 24, filled = static_cast<int>(fraction * width + 0.5);
  const double rate = now > 0 ? done / now : 0.0;
  // Three significant digits with an SI prefix: a rate that fits the line at any scale.
  const char* scale = rate >= 1e6 ? "M" : rate >= 1e3 ? "k" : "";
  const double shown = rate >= 1e6 ? rate * 1e-6 : rate >= 1e3 ? rate * 1e-3 : rate;
  const std::string eta_text = eta < 0 ? "ETA ?" : "ETA " + format_hms(eta);
  std::fprintf(stderr, "%s%s: [%s%s] %5.1f%%  %.3g %s%s/s  %.1f s elapsed  %s%s",
               terminal_ ? "\r" : "", label_.c_str(), std::string(filled, '#').c_str(),
               std::string(width - filled, '.').c_str(), 100.0 * fraction, shown, scale,
               unit_.c_str(), now, final ? "done" : eta_text.c_str(),
               terminal_ && !final ? "" : "\n");
  std::fflush(stderr);
}

TimedChunks::TimedChunks(std::int64_t total, const ProgressLine* line, std::int64_t min_items)
    : total_(std::max<std::int64_t>(0, total)),
      min_items_(std::max<std::int64_t>(1, min_items)),
      period_(line && line->enabled() ? std::max(line->period(), kMinDispatchSeconds) : 0.0),
      start_(Clock::now()) {}

bool TimedChunks::next(std::int64_t& begin, std::int64_t& end) {
  if (done_ >= total_) return false;
  const std::int64_t left = total_ - done_;
  std::int64_t size = left;
  if (period_ > 0 && done_ == 0) {
    size = std::max(min_items_, total_ / 64);
  } else if (period_ > 0) {
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    const double rate = seconds > 0 ? static_cast<double>(done_) / seconds : 1e30;
    size = std::max(min_items_, static_cast<std::int64_t>(std::min(rate * period_, 1e18)));
  }
  if (left - size < size / 2) size = left;
  begin = done_;
  end = done_ + size;
  done_ = end;
  return true;
}

void CostFit::add(double seconds, double items, double probe_cost) {
  nn_ += items * items;
  nc_ += items * probe_cost;
  cc_ += probe_cost * probe_cost;
  tn_ += seconds * items;
  tc_ += seconds * probe_cost;
}

double CostFit::cost(double items, double probe_cost) const {
  // The normal equations of min sum (t - a n - b c)^2 over the pieces added.
  const double det = nn_ * cc_ - nc_ * nc_;
  const bool solvable = det > 1e-12 * nn_ * cc_;
  double a = solvable ? (tn_ * cc_ - tc_ * nc_) / det : -1.0;
  double b = solvable ? (tc_ * nn_ - tn_ * nc_) / det : -1.0;
  if (a < 0 || b < 0) {  // one piece, or one term explains the data: the probe cost alone
    a = 0;
    b = cc_ > 0 ? tc_ / cc_ : 0.0;
  }
  return a * items + b * probe_cost;
}

}  // namespace rtmini
