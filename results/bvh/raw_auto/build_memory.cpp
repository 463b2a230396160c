#include <cstdio>
#include <cstdlib>
#include <ctime>
#include "rtmini/bvh/build.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/device_mesh.hpp"
using namespace rtmini;
int main(int argc, char** argv) {
  Kokkos::ScopeGuard g(argc, argv);
  {
    using Mem = Kokkos::HostSpace; using Exec = Kokkos::DefaultHostExecutionSpace;
    Mesh mesh = read_mesh(argv[1]);
    auto dm = upload_mesh(mesh, bvh::BuildQuality::kLbvh);
    dm.accel = {};
    double budget = bvh::kDefaultSplitBudget;
    if (argc > 2) bvh::parse_split_budget(argv[2], budget);
    const double c0 = double(std::clock()) / CLOCKS_PER_SEC;
    auto out = bvh::build<Exec, Mem>(Exec(), dm.tris, bvh::BuildQuality::kSah);
    const double c1 = double(std::clock()) / CLOCKS_PER_SEC;
    std::printf("references %d, build CPU %.1f s\n", out.num_prims, c1 - c0);
  }
}
