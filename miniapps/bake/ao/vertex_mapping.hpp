#pragma once
// From AO at sample points to AO at vertices (seed: optix-prime-ao-baking,
// "Map AO to vertices"): the area-and-barycentric weighted average, or the
// least-squares fit of Kavan, Bargteil, Sloan, "Least Squares Vertex Baking"
// (EGSR 2011) with a smoothness regulariser. Runs on the host in a fixed
// order, so the result does not depend on thread or rank count.
#include <cstdint>
#include <string>
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
  int systems = 0;         // distinct matrices (groups of identical systems), either method
  int cg_iterations = 0;   // most CG iterations of any instance (0 for Cholesky)
};

// How the normal equations are solved: Eigen's sparse Cholesky on the host (the reference, and
// the default), or Jacobi-preconditioned CG on the Kokkos device (vertex_fit_cg.hpp; agrees
// with Cholesky to ~1e-7 but not bit for bit, so its AO hashes are its own).
enum class FitMethod { kCholesky, kCg };
// "cholesky" | "cg" | "auto": CG where the default memory space is not the host's (a GPU),
// Cholesky otherwise. InputError on anything else.
FitMethod parse_fit_method(const std::string& name);
const char* fit_method_name(FitMethod method);

// Minimises sum_s w_s (sum_k b_sk x_k - a_s)^2 + weight * sum_edges (x_i - x_j)^2 per
// receiver instance, w_s = sample area / mean triangle area of the instance (so
// `weight` is independent of scene scale and tessellation density), with Eigen's
// sparse Cholesky (SimplicialLDLT) or device CG (`method`). weight = 0 is the pure fit.
// Instances of one mesh with the same per-triangle counts and relative areas have the same
// matrix: it is factored (CG: assembled) once and solved per instance (share_factorization =
// false gives every instance its own, for verification). `progress` (may be null) counts the
// kLeastSquaresSteps steps below; the caller finishes it.
constexpr int kLeastSquaresSteps = 4;  // data blocks, patterns, factorizations/values, solves
std::vector<float> map_least_squares(const AoScene& scene, const SampleValues& samples,
                                     double weight, LeastSquaresStats* stats = nullptr,
                                     bool share_factorization = true,
                                     ProgressLine* progress = nullptr,
                                     FitMethod method = FitMethod::kCholesky);

}  // namespace rtmini::ao
