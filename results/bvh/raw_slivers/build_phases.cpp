#include <chrono>
#include <cstdio>
#include <ctime>
#include <algorithm>
#include "rtmini/bvh/build.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/device_mesh.hpp"
using namespace rtmini;
using Clock = std::chrono::steady_clock;
static double now() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }
static double cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }
int main(int argc, char** argv) {
  Kokkos::ScopeGuard g(argc, argv);
  {
  using Mem = Kokkos::HostSpace; using Exec = Kokkos::DefaultHostExecutionSpace;
  Mesh mesh = read_mesh(argv[1]);
  auto dm = upload_mesh(mesh, bvh::BuildQuality::kLbvh);
  int reps = argc > 2 ? atoi(argv[2]) : 10;
  std::vector<double> k1,k2,k3,k4, tot, tcpu, t1, t2, t3, t4;
  for (int r = 0; r < reps; ++r) {
    double a = now(), c0 = cpu();
    auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dm.tris);
    std::vector<Triangle> v(host.data(), host.data() + host.extent(0));
    double b = now(), cb = cpu();
    auto h = bvh::build_sah_host(v);
    double c = now(), cc = cpu();
    auto out = bvh::build<Exec, Mem>(Exec(), dm.tris, bvh::BuildQuality::kSah);
    double d = now(), cd = cpu();
    { Aabb bb; for (auto& t : v) { bb.expand(t.a); bb.expand(t.b); bb.expand(t.c);} auto r = bvh::presplit_triangles(v, bb, 1.0); }
    double e = now();
    double ce = cpu(); k1.push_back(cb-c0); k2.push_back(cc-cb); k3.push_back(cd-cc); k4.push_back(ce-cd); tot.push_back(e - a); tcpu.push_back(cpu() - c0); t1.push_back(b - a); t2.push_back(c - b); t3.push_back(d - c); t4.push_back(e - d);
  }
  auto med = [](std::vector<double> x) { std::sort(x.begin(), x.end()); return x[x.size() / 2] * 1e3; };
  std::printf("total %.2f ms (cpu %.2f): copy %.2f, sah_host %.2f, full build() %.2f, presplit %.2f\n", med(tot), med(tcpu), med(t1), med(t2), med(t3), med(t4)); std::printf("  cpu: copy %.2f, sah_host %.2f, full build() %.2f, presplit %.2f\n", med(k1), med(k2), med(k3), med(k4));
  }
}
