#include <chrono>
#include <cstdio>
#include <cstdlib>
#include "rtmini/bvh/build.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/device_mesh.hpp"
using namespace rtmini;
int main(int argc, char** argv) {
  Kokkos::ScopeGuard g(argc, argv);
  {
    Mesh mesh = read_mesh(argv[1]);
    auto dm = upload_mesh(mesh, bvh::BuildQuality::kLbvh);
    double budget = argc > 2 ? atof(argv[2]) : bvh::kDefaultSplitBudget;
    auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dm.tris);
    std::vector<Triangle> v(host.data(), host.data() + host.extent(0));
    Aabb bb; for (auto& t : v) { bb.expand(t.a); bb.expand(t.b); bb.expand(t.c); }
    auto t0 = std::chrono::steady_clock::now();
    auto r = bvh::presplit_triangles(v, bb, budget);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double area = 0; for (auto& x : r) area += x.box.surface_area();
    std::printf("refs %zu area %.6g presplit %.1f ms\n", r.size(), area, s * 1e3);
  }
}
