// How long an idle libgomp worker spin-waits after a parallel region (results/bvh/README.md,
// issue 22 build row): one empty 2-thread region, then the main thread sleeps; the process CPU
// time counted during the sleep is the worker's spin. Build and run:
//   g++ -O2 -fopenmp spin_wait.cpp -o spin_wait && OMP_PROC_BIND=false ./spin_wait
#include <chrono>
#include <cstdio>
#include <ctime>
#include <initializer_list>
#include <thread>

int main() {
  volatile int sink = 0;
  for (int ms : {1, 2, 5, 10, 20, 50, 100, 200}) {
#pragma omp parallel num_threads(2)
    { sink = sink + 1; }
    const std::clock_t c0 = std::clock();
    std::this_thread::sleep_for(std::chrono::milliseconds(ms));
    std::printf("sleep %3d ms after the region: process CPU %.2f ms\n", ms,
                double(std::clock() - c0) / CLOCKS_PER_SEC * 1e3);
  }
}
