// rtmini-bake-lookup-bench: the two viewpoint lookups (heap KD-tree, inverse spherical
// Fibonacci) against exhaustive search: queries per second and agreement, as a Markdown table.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Mem = Exec::memory_space;

KOKKOS_INLINE_FUNCTION Vec3 direction(int i) {
  const Rng rng(4242u, static_cast<std::uint64_t>(i), 0u);
  return uniform_sphere(Real(rng.uniform(0)), Real(rng.uniform(1)));
}

template <class F>
double seconds_per_query(int queries, F&& f) {
  double best = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    Kokkos::fence();
    const auto t0 = std::chrono::steady_clock::now();
    int sink = 0;
    Kokkos::parallel_reduce(
        "rtmini::bench::lookup", Kokkos::RangePolicy<Exec>(0, queries),
        KOKKOS_LAMBDA(int i, int& s) { s += f(i); }, sink);
    Kokkos::fence();
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (sink == -1) std::printf(" ");
    best = dt < best ? dt : best;
  }
  return best / queries;
}

void run(int n, int queries, int checked) {
  const auto pts = fibonacci_points<Mem>(n);
  const auto kd = build_fibonacci_kdtree<Mem>(n);
  const auto sf = build_fibonacci_inverse<Mem>(n);
  const Real r = fibonacci_radius(n);
  const double kd_near = seconds_per_query(
      queries, KOKKOS_LAMBDA(int i) { return kd.nearest(direction(i)); });
  const double sf_near = seconds_per_query(
      queries, KOKKOS_LAMBDA(int i) { return sf.nearest(direction(i)); });
  const double kd_nb = seconds_per_query(
      queries, KOKKOS_LAMBDA(int i) { return kd.neighbors(direction(i), r).count; });
  const double sf_nb = seconds_per_query(
      queries, KOKKOS_LAMBDA(int i) { return sf.neighbors(direction(i), r).count; });
  const double bf_near = seconds_per_query(
      checked, KOKKOS_LAMBDA(int i) { return brute_force_nearest(pts, direction(i)); });
  int kd_bad = 0, sf_bad = 0, kd_nb_bad = 0, sf_nb_bad = 0;
  double mean_count = 0;
  Kokkos::parallel_reduce(
      "rtmini::bench::lookup_agreement", Kokkos::RangePolicy<Exec>(0, checked),
      KOKKOS_LAMBDA(int i, int& a, int& b, int& c, int& d, double& m) {
        const Vec3 q = direction(i);
        const int ref = brute_force_nearest(pts, q);
        a += kd.nearest(q) != ref;
        b += sf.nearest(q) != ref;
        const ViewNeighbors nb = brute_force_neighbors(pts, q, r);
        const ViewNeighbors x = kd.neighbors(q, r), y = sf.neighbors(q, r);
        bool sx = x.count == nb.count, sy = y.count == nb.count;
        for (int k = 0; k < nb.count; ++k) {
          sx = sx && x.index[k] == nb.index[k];
          sy = sy && y.index[k] == nb.index[k];
        }
        c += !sx;
        d += !sy;
        m += nb.count;
      },
      kd_bad, sf_bad, kd_nb_bad, sf_nb_bad, mean_count);
  std::printf(
      "| %6d | %7.1f | %7.1f | %8.1f | %7.1f | %7.1f | %5.2f | %d/%d | %d/%d | %d/%d | %d/%d |\n",
      n, kd_near * 1e9, sf_near * 1e9, bf_near * 1e9, kd_nb * 1e9, sf_nb * 1e9,
      mean_count / checked, kd_bad, checked, sf_bad, checked, kd_nb_bad, checked, sf_nb_bad,
      checked);
}

}  // namespace
}  // namespace rtmini

namespace rtmini {
namespace {

int lookup_bench(Communicator& comm, int argc, char** argv) {
  CLI::App app{"rtmini-bake-lookup-bench: viewpoint lookup (kd-tree, spherical Fibonacci) timings",
               "rtmini-bake-lookup-bench"};
  CommonOptions common;
  add_common_options(app, common);
  int queries = 1000000;
  app.add_option("queries", queries, "random directions per lookup timing")
      ->check(CLI::PositiveNumber);
  if (const auto done = parse_command_line(app, argc, argv, common, comm.is_root())) return *done;
  RunReport report;
  report.app = "rtmini-bake-lookup-bench";
  report.parameters = {{"queries", queries}};
  std::printf("%s\n", build_banner().c_str());
  std::printf(
      "%d random directions per lookup timing (best of 3, ns per query, all threads); "
      "agreement with exhaustive search on 20000 of them\n\n",
      queries);
  std::printf(
      "| N | kd nearest | sf nearest | brute nearest | kd radius | sf radius | mean neighbours | "
      "kd nearest wrong | sf nearest wrong | kd radius set wrong | sf radius set wrong |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  report.timer.start("lookups");
  for (int n : {20, 100, 1000, 10000, 100000}) run(n, queries, 20000);
  const double seconds = report.timer.stop();
  // The table is the result; the summary's figure is the wall time of the whole sweep.
  report.fom_name = "sweep time";
  report.fom_unit = "s";
  report.fom_value = seconds;
  report.finish(comm, common.summary);
  return kExitOk;
}

}  // namespace
}  // namespace rtmini

int main(int argc, char** argv) {
  return rtmini::app_main("rtmini-bake-lookup-bench", argc, argv, rtmini::lookup_bench);
}
