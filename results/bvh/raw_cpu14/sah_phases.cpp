// Issue 22 (branch cpu14): where the whole SAH bvh::build's CPU time goes outside build_sah_host.
// Per build (each after a 20 ms sleep), CPU time (std::clock) and minor page faults of: the host
// build (build_sah_host), the upload of its three arrays into views (bvh::upload), the collapse
// into the 8-wide tree (collapse_to_wide) and its copy into the huge-page views; the medians over
// REPS builds. Built by hand as raw_cpu10/sah_build_cpu.cpp (its compile line; the bench's
// LINK_LIBRARIES from build/build.ninja).
// Usage: OMP_NUM_THREADS=T sah_phases MESH.obj [REPS]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <thread>
#include <vector>

#include "rtmini/bvh/build.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/device_mesh.hpp"
using namespace rtmini;
namespace {
long minor_faults() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}
double cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }
struct Phase {
  const char* name;
  std::vector<double> ms, faults;
};
template <class Fn>
auto timed(Phase& p, const Fn& fn) {
  const double c0 = cpu();
  const long f0 = minor_faults();
  auto r = fn();
  p.ms.push_back((cpu() - c0) * 1e3);
  p.faults.push_back(double(minor_faults() - f0));
  return r;
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace
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
  const int reps = argc > 2 ? atoi(argv[2]) : 20;
  using Mem = Kokkos::HostSpace;
  Phase host{"build_sah_host"}, up{"upload"}, collapse{"collapse_to_wide"}, views{"wide views"};
  for (int r = 0; r < reps; ++r) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const bvh::HostBvh h = timed(host, [&] { return bvh::build_sah_host(v); });
    bvh::Bvh<Mem> out = timed(up, [&] { return bvh::upload<Mem>(h, bvh::BuildQuality::kSah); });
    const bvh::WideBvh w = timed(
        collapse, [&] { return bvh::collapse_to_wide(h.nodes, h.tris.data(), h.prim.data()); });
    timed(views, [&] {
      out.wide = bvh::huge_page_view<bvh::WideNode, Mem>("wide", w.nodes.size());
      std::copy(w.nodes.begin(), w.nodes.end(), out.wide.data());
      out.leaves = bvh::huge_page_view<bvh::TriangleLanes, Mem>("leaves", w.leaves.size());
      std::copy(w.leaves.begin(), w.leaves.end(), out.leaves.data());
      return 0;
    });
  }
  std::printf("threads %d, %d builds: median CPU ms (minor faults)\n",
              Kokkos::DefaultHostExecutionSpace().concurrency(), reps);
  for (const Phase* p : {&host, &up, &collapse, &views})
    std::printf("  %-16s %6.2f ms (%5.0f faults)\n", p->name, median(p->ms), median(p->faults));
}
