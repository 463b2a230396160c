#pragma once
// The remaining time of bake's iterate phase, from measured costs: the iterations differ in cost
// by hit-cache mode (the base map, the iteration that fills the cache and the ones that reuse it
// trace very different ray counts), so a remaining iteration is estimated by the last measured
// iteration of its own mode (or the last one of any mode until its mode has run), and the
// current iteration by its own rate over the colour entries done so far.
#include <cstdint>
#include <map>
#include <vector>

namespace rtmini::bake {

class IterationEta {
 public:
  // Call when an iteration of mode `mode` (any integer label) ends after `seconds`.
  void iteration_done(int mode, double seconds) {
    last_of_mode_[mode] = seconds;
    last_ = seconds;
  }
  // Estimated seconds left: `done`/`total` entries of the current iteration took `spent` s so
  // far; `upcoming_modes` lists the modes of the iterations after it.
  template <class Modes>
  double remaining(double spent, std::int64_t done, std::int64_t total,
                   const Modes& upcoming_modes) const {
    double left =
        done > 0 ? spent * static_cast<double>(total - done) / static_cast<double>(done) : last_;
    for (const int m : upcoming_modes) {
      const auto it = last_of_mode_.find(m);
      left += it != last_of_mode_.end() ? it->second : last_;
    }
    return left;
  }

 private:
  std::map<int, double> last_of_mode_;
  double last_ = 0;
};

// Modes (0 = no cache, 1 = fill, 2 = use: chef.hpp's HitCacheMode order) of iterations
// it+1..last, given whether the hit cache is filled once iteration `it` ends.
inline std::vector<int> modes_after(int it, int last, bool cache_filled) {
  std::vector<int> modes;
  for (int j = it + 1; j <= last; ++j) {
    const int m = j == 0 ? 0 : cache_filled ? 2 : j < last ? 1 : 0;
    if (m == 1) cache_filled = true;
    modes.push_back(m);
  }
  return modes;
}

}  // namespace rtmini::bake
