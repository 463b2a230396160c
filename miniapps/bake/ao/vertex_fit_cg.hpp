#pragma once
// The least-squares vertex fit of vertex_mapping.hpp on the Kokkos device: the normal
// equations (weight * Laplacian + per-triangle sample blocks) assembled in CSR on the device
// and solved by Jacobi-preconditioned conjugate gradients, one system per group of identical
// receivers and one right-hand side per receiver, all receivers in the same kernels.
//
// Deterministic for any thread count: every sum has a fixed order (matrix rows and right-hand
// sides add their incident triangles in ascending order, dot products go through a fixed
// tree of kCgFanIn-wide chunks), and a receiver's iterations never see another receiver's
// numbers, so its values do not depend on which receivers share the batch.
#include <cstddef>
#include <vector>

#include "vertex_mapping.hpp"

namespace rtmini::ao {

// Stops a receiver's iterations once its preconditioned residual r^T D^-1 r has fallen by
// this factor (squared relative tolerance) from its start; chosen with a margin for AO values
// within 1e-5 of the sparse Cholesky solution (tests/unit/ao/least_squares_test.cpp).
constexpr double kCgRelativeResidual2 = 1e-24;
// A receiver not converged after this many iterations is reported as failed (fallback).
constexpr int kCgMaxIterations = 20000;
// Width of every node of the summation tree of the dot products.
constexpr int kCgFanIn = 32;

struct CgFit {
  std::vector<float> values;  // per output vertex; untouched where failed
  std::vector<char> failed;   // per receiver: breakdown or no convergence
};

// Solves the system of `groups` (receivers with identical matrices, as group_receivers in
// vertex_mapping.cpp; the first member's blocks define it) for every receiver. Times and the
// largest iteration count land in `stats`; `progress` (may be null) counts the
// kLeastSquaresSteps steps.
CgFit fit_least_squares_cg(const AoScene& scene, const SampleValues& samples, double weight,
                           const std::vector<std::vector<std::size_t>>& groups,
                           LeastSquaresStats& stats, ProgressLine* progress);

}  // namespace rtmini::ao
