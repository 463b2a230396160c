// Latency of a 1-double all-reduce: blocking MPI_Allreduce vs the Communicator's
// MPI_Iallreduce + failure-polling wait (issue 17).
#include <chrono>
#include <cstdio>
#include "rtmini/parallel/communicator.hpp"
int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  {
    rtmini::Communicator comm;
    const int n = 20000;
    for (int rep = 0; rep < 5; ++rep) {
      double x = 1, s = 0;
      MPI_Barrier(MPI_COMM_WORLD);
      auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < n; ++i) MPI_Allreduce(&x, &s, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
      auto t1 = std::chrono::steady_clock::now();
      for (int i = 0; i < n; ++i) s = comm.max(x);
      auto t2 = std::chrono::steady_clock::now();
      if (comm.is_root())
        std::printf("rep %d: MPI_Allreduce %.2f us, Communicator::max %.2f us\n", rep,
                    std::chrono::duration<double, std::micro>(t1 - t0).count() / n,
                    std::chrono::duration<double, std::micro>(t2 - t1).count() / n);
    }
  }
  MPI_Finalize();
}
