// Whether pre-splitting applies to a mesh: prints triangles and references (0 = not applied).
#include <cstdio>
#include "rtmini/bvh/presplit.hpp"
#include "rtmini/io/obj_reader.hpp"
using namespace rtmini;
int main(int argc, char** argv) {
  Kokkos::ScopeGuard g(argc, argv);
  for (int a = 1; a < argc; ++a) {
    const Mesh m = read_mesh(argv[a]);
    const TriangleList tl = triangulate(m);
    std::vector<Triangle> v;
    Aabb box;
    for (auto& t : tl.vertices) {
      v.push_back({Vec3(m.positions[t[0]]), Vec3(m.positions[t[1]]), Vec3(m.positions[t[2]])});
      box.expand(v.back().a); box.expand(v.back().b); box.expand(v.back().c);
    }
    std::printf("%s: %zu triangles, pre-split references %zu\n", argv[a], v.size(), bvh::presplit_triangles(v, box, bvh::kDefaultSplitBudget).size());
  }
}
