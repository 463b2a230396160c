// Issue 22 (branch cpu10): the CPU time of build_sah_host (default) or of the whole bvh::build
// (argument "full") per build, median and first quartile over REPS builds, each after a 20 ms
// sleep so no earlier work's spin is charged. Built by hand like raw_slivers/build_phases.cpp:
// g++ -O3 -DNDEBUG -march=native -ffp-contract=off -fopenmp -std=c++17 -Icommon/include
// -isystem .deps/kokkos/include sah_build_cpu.cpp -o sah_build_cpu + the bench's link line
// (build/build.ninja, LINK_LIBRARIES of rtmini-bvh-bench).
// Usage: OMP_NUM_THREADS=T sah_build_cpu MESH.obj [REPS] [full]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "rtmini/bvh/build.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/device_mesh.hpp"
using namespace rtmini;
static void ru(double& sys, long& flt) {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  sys = u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
  flt = u.ru_minflt;
}
static double cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }
int main(int argc, char** argv) {
  Kokkos::ScopeGuard g(argc, argv);
  Mesh mesh = read_mesh(argv[1]);
  std::vector<Triangle> v;
  const TriangleList tl = triangulate(mesh);
  for (const auto& t : tl.vertices) {
    auto p = [&](int i) {
      const Vec3d& q = mesh.positions[i];
      return Vec3(Real(q.x), Real(q.y), Real(q.z));
    };
    v.push_back({p(t[0]), p(t[1]), p(t[2])});
  }
  int reps = argc > 2 ? atoi(argv[2]) : 20;
  std::vector<double> c, sy, fl;
  const bool full = argc > 3 && std::string(argv[3]) == "full";
  auto dm = upload_mesh(mesh, bvh::BuildQuality::kLbvh);
  using Mem = Kokkos::HostSpace;
  using Exec = Kokkos::DefaultHostExecutionSpace;
  for (int r = 0; r < reps; ++r) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    double c0 = cpu();
    double s0;
    long f0;
    ru(s0, f0);
    if (full) {
      const auto b = bvh::build<Exec, Mem>(Exec(), dm.tris, bvh::BuildQuality::kSah);
      Kokkos::fence();
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      c.push_back(cpu() - c0);
      {
        double s1;
        long f1;
        ru(s1, f1);
        sy.push_back(s1 - s0);
        fl.push_back(double(f1 - f0));
      }
      continue;
    }
    {
      auto h = bvh::build_sah_host(v);
      if (h.nodes.empty()) return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    c.push_back(cpu() - c0);
    {
      double s1;
      long f1;
      ru(s1, f1);
      sy.push_back(s1 - s0);
      fl.push_back(double(f1 - f0));
    }
  }
  std::sort(sy.begin(), sy.end());
  std::sort(fl.begin(), fl.end());
  std::printf("sys median %.2f ms, minor faults median %.0f\n", sy[sy.size() / 2] * 1e3,
              fl[fl.size() / 2]);
  std::sort(c.begin(), c.end());
  std::printf("threads %d: %s CPU median %.2f ms, q1 %.2f\n",
              Kokkos::DefaultHostExecutionSpace().concurrency(),
              full ? "build()" : "build_sah_host", c[c.size() / 2] * 1e3, c[c.size() / 4] * 1e3);
}
