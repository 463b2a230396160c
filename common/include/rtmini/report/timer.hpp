#pragma once
// Phase timers: named wall-clock phases that fence the device before reading
// the clock, each also a Kokkos profiling region so Kokkos Tools see it.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini {

class PhaseTimer {
 public:
  using Clock = std::chrono::steady_clock;
  PhaseTimer() : origin_(Clock::now()) {}

  void start(const std::string& name) {
    Kokkos::fence();
    Kokkos::Profiling::pushRegion("rtmini::" + name);
    current_ = name;
    begin_ = now();
  }
  double stop() {
    Kokkos::fence();
    Kokkos::Profiling::popRegion();
    const double end = now();
    phases_.push_back({current_, {begin_, end}});
    return end - begin_;
  }
  // Seconds since this timer was created (the run start).
  double now() const { return std::chrono::duration<double>(Clock::now() - origin_).count(); }
  double total(const std::string& name) const {
    double s = 0;
    for (const auto& p : phases_)
      if (p.first == name) s += p.second.second - p.second.first;
    return s;
  }
  const std::vector<std::pair<std::string, std::pair<double, double>>>& phases() const {
    return phases_;
  }

 private:
  Clock::time_point origin_;
  std::string current_;
  double begin_ = 0;
  std::vector<std::pair<std::string, std::pair<double, double>>> phases_;
};

}  // namespace rtmini
