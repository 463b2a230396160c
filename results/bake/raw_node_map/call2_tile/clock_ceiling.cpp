// Compute-only ceiling of a 16-core host: one FP-bound loop (no memory traffic) timed alone and
// as 16 concurrent copies, one per core. Its per-copy time ratio is what the host's clocks allow
// any 16-way run against one core, before memory enters.
#include <chrono>
#include <cstdio>
int main() {
  const auto t0 = std::chrono::steady_clock::now();
  double a[8] = {1, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7};
  for (long i = 0; i < 400000000L; ++i)
    for (int k = 0; k < 8; ++k) a[k] = a[k] * 0.9999999 + 1e-7;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double sum = 0;
  for (double x : a) sum += x;
  std::printf("%.4f %g\n", s, sum);
}
