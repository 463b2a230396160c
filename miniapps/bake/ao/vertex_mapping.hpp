#pragma once
// From AO at sample points to AO at vertices (seed: optix-prime-ao-baking,
// "Map AO to vertices"): the area-and-barycentric weighted average, or the
// least-squares fit of Kavan, Bargteil, Sloan, "Least Squares Vertex Baking"
// (EGSR 2011) with a smoothness regulariser. Runs on the host in a fixed
// order, so the result does not depend on thread or rank count.
#include <cstdint>
#include <vector>

#include "ao_scene.hpp"
#include "rtmini/report/progress.hpp"
#include "sample_plan.hpp"

namespace rtmini::ao {

// Visibility (fraction of unoccluded rays, 1 = open) of every sample point.
struct SampleValues {
  const SamplePlan* plan = nullptr;
  std::uint64_t seed = 1;          // regenerates each point's barycentrics
  std::vector<double> visibility;  // one per sample point, global order
};

SampleValues make_sample_values(const SamplePlan& plan, std::uint64_t seed,
                                const std::vector<std::uint16_t>& occluded, int rays);

// One value per output vertex (SamplePlan::vertex_base order). Vertices that no
// sample reaches get 1 (open).
std::vector<float> map_weighted_average(const AoScene& scene, const SampleValues& samples);

struct LeastSquaresStats {
  double assemble_s = 0, regularize_s = 0, factor_s = 0, solve_s = 0;
  int fallbacks = 0;       // instances whose system was singular (weighted average used)
  int factorizations = 0;  // sparse Cholesky factorizations (one per group of identical systems)
};

// Minimises sum_s w_s (sum_k b_sk x_k - a_s)^2 + weight * sum_edges (x_i - x_j)^2 per
// receiver instance, w_s = sample area / mean triangle area of the instance (so
// `weight` is independent of scene scale and tessellation density), with Eigen's
// sparse Cholesky (SimplicialLDLT). weight = 0 is the pure fit. Instances of one
// mesh with the same per-triangle counts and relative areas have the same matrix:
// it is factored once and solved per instance (share_factorization = false
// factors every instance on its own, for verification). `progress` (may be null) counts the
// kLeastSquaresSteps steps below; the caller finishes it.
constexpr int kLeastSquaresSteps = 4;  // data blocks, patterns, factorizations, solves
std::vector<float> map_least_squares(const AoScene& scene, const SampleValues& samples,
                                     double weight, LeastSquaresStats* stats = nullptr,
                                     bool share_factorization = true,
                                     ProgressLine* progress = nullptr);

}  // namespace rtmini::ao
