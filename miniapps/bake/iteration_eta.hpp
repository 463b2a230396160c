#pragma once
// The remaining time of bake's iterate phase, from measured costs. A rank traces the same
// batches in every iteration, but their costs differ widely (a batch of view-dependent vertices
// traces N colours' rays, one of diffuse vertices a single colour's), and whole iterations
// differ by hit-cache mode (the base map, the iteration that fills the cache, the ones that
// reuse it). So the rest of the current iteration is the rest of the last iteration of the
// same mode, batch by batch, scaled by how fast this iteration has been so far (linear in
// batches while its mode is new: batches are cut to about equal work, colour entries are not
// a measure of it, since the gather rays go per vertex); each later iteration costs the last
// measured one of its mode (of any gather mode, for a gather mode not seen yet), or, failing
// that, this iteration's projected total. While the base map is all that is known of a run
// with gather iterations to come there is no estimate.
#include <cstdint>
#include <map>
#include <numeric>
#include <vector>

namespace rtmini::bake {

class IterationEta {
 public:
  void batch_done(double seconds) { current_.push_back(seconds); }
  void iteration_done(int mode) {
    last_of_mode_[mode] = current_;
    current_.clear();
  }
  // Seconds left: the current iteration (mode `mode`, `batches` batches on this rank) and the
  // iterations after it, whose modes are `upcoming`; negative when there is no estimate yet.
  double remaining(int mode, std::size_t batches, const std::vector<int>& upcoming) const {
    // A gather iteration still to come while only the base map has been measured (or the other
    // way round) has no fair reference: the base map (no gather rays, no mirror bounces) took
    // about half a gather iteration's time on cornell_big, and an ETA from it was 37 % low
    // (results/progress/). No estimate, rather than a wrong one, until one has run.
    for (const int m : upcoming)
      if (!reference(m) && (m == 0) != (mode == 0)) return -1.0;
    const double spent = sum(current_, 0, current_.size());
    const std::vector<double>* ref = reference(mode);
    double left = 0;
    if (ref && ref->size() > current_.size()) {
      const double ref_done = sum(*ref, 0, current_.size());
      const double ref_left = sum(*ref, current_.size(), ref->size());
      left = ref_done > 0 ? ref_left * spent / ref_done : ref_left;
    } else if (current_.size() >= 2) {
      // The first batch of an iteration also pays its setup (measured: ~15x a later batch on
      // cornell_big), so the rest is extrapolated from the batches after it.
      const double per_batch =
          sum(current_, 1, current_.size()) / static_cast<double>(current_.size() - 1);
      left = per_batch * static_cast<double>(batches - current_.size());
    } else if (current_.size() < batches) {
      return -1.0;  // only the setup-laden first batch is known: no honest estimate yet
    }
    const double this_iteration = spent + left;
    for (const int m : upcoming) {
      const std::vector<double>* r = reference(m);
      left += r ? sum(*r, 0, r->size()) : this_iteration;
    }
    return left;
  }

 private:
  static double sum(const std::vector<double>& v, std::size_t a, std::size_t b) {
    return std::accumulate(v.begin() + static_cast<std::ptrdiff_t>(a),
                           v.begin() + static_cast<std::ptrdiff_t>(b), 0.0);
  }
  // Only an iteration of the same mode is a fair reference: the base map's batches cost in a
  // different proportion (no gather rays, no mirror bounces) than the iterations after it. The
  // gather modes (fill, use, traced: chef.hpp's HitCacheMode) trace the same rays batch by
  // batch, so any of them stands in for another until that one has run: linear in batches instead
  // was 48 % low at the start of the first cache-using iteration (results/progress/).
  const std::vector<double>* reference(int mode) const {
    auto it = last_of_mode_.find(mode);
    for (auto other = last_of_mode_.begin();
         it == last_of_mode_.end() && mode != 0 && other != last_of_mode_.end(); ++other)
      if (other->first != 0) it = other;
    return it != last_of_mode_.end() ? &it->second : nullptr;
  }

  std::vector<double> current_;
  std::map<int, std::vector<double>> last_of_mode_;
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
