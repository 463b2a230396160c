#pragma once
// Tests are written once against TestExecSpace and compiled once per enabled
// Kokkos backend (the build defines RTMINI_TEST_EXECSPACE).
#include "rtmini/geometry/triangle.hpp"
#include "rtmini/kokkos_compat.hpp"
#include "rtmini/scene/mesh.hpp"

#ifndef RTMINI_TEST_EXECSPACE
#define RTMINI_TEST_EXECSPACE Kokkos::DefaultExecutionSpace
#endif

namespace rtmini::test {
using TestExecSpace = RTMINI_TEST_EXECSPACE;
using TestMemSpace = TestExecSpace::memory_space;
// Directory of the public test meshes (inputs/meshes, bundled with their provenance).
const char* scenes_dir();

// The mesh's triangles in the test space's memory (one copy for every test that traces them).
inline Kokkos::View<Triangle*, TestMemSpace> upload_triangles(const Mesh& mesh) {
  const TriangleList tl = triangulate(mesh);
  Kokkos::View<Triangle*, TestMemSpace> tris("tris", tl.vertices.size());
  auto h = Kokkos::create_mirror_view(tris);
  for (std::size_t t = 0; t < tl.vertices.size(); ++t)
    h(t) = {Vec3(mesh.positions[tl.vertices[t][0]]), Vec3(mesh.positions[tl.vertices[t][1]]),
            Vec3(mesh.positions[tl.vertices[t][2]])};
  Kokkos::deep_copy(tris, h);
  return tris;
}

// A test scene scaled by `scale` and moved `offset` away from the origin: the numerical
// extremes (tiny, huge, far) that watertightness and the box tests must survive.
struct Placement {
  const char* name;
  double scale;
  double offset;
};
}  // namespace rtmini::test
