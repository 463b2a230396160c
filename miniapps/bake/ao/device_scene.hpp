#pragma once
// The AO scene on the device as a two-level structure: one BVH per stored mesh
// (object space) and a top-level list of instances with world boxes and
// world->object transforms; rays are moved into each instance's space and
// traced against the shared mesh BVH (one copy per mesh, as the sample does).
#include <cstdint>
#include <vector>

#include "affine.hpp"
#include "ao_scene.hpp"
#include "ground_plane.hpp"
#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/traverse.hpp"

namespace rtmini::ao {

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;

// A mesh BVH seen through raw device pointers, shaped like bvh::Bvh for the
// templated traversal (nodes, wide, leaves, tris, prim, num_prims, memory_space), so a
// table of them can live in one View and be indexed per instance in a kernel.
struct BvhRef {
  using memory_space = MemSpace;
  template <class T>
  struct Array {
    const T* data = nullptr;
    std::size_t size = 0;
    KOKKOS_INLINE_FUNCTION const T& operator()(std::uint32_t i) const { return data[i]; }
    KOKKOS_INLINE_FUNCTION std::size_t extent(int) const { return size; }
  };
  Array<bvh::BvhNode> nodes;
  Array<bvh::WideNode> wide;
  Array<bvh::TriangleLanes> leaves;
  Array<Triangle> tris;
  Array<int> prim;
  int num_prims = 0;
};

struct DeviceInstance {
  Affine to_object;
  Vec3 lo, hi;  // world box
  int mesh = 0;
  int identity = 0;  // skip the transform
};

// Everything a kernel needs to answer "is this segment blocked?" (copyable by value).
struct OcclusionQuery {
  Kokkos::View<const BvhRef*, MemSpace> meshes;
  Kokkos::View<const DeviceInstance*, MemSpace> instances;
  GroundPlane ground;
  int num_instances = 0;

  KOKKOS_INLINE_FUNCTION bool occluded(const Ray& ray) const {
    if (ground.hit(ray)) return true;
    const RaySlab slab(ray.org, ray.dir);
    for (int i = 0; i < num_instances; ++i) {
      const DeviceInstance& inst = instances(i);
      Real tenter;
      if (!slab_test(slab, inst.lo, inst.hi, ray.tmin, ray.tmax, tenter)) continue;
      if (inst.identity) {
        if (bvh::any_hit(meshes(inst.mesh), ray)) return true;
      } else {
        // The direction is not renormalised, so t means the same in both spaces.
        Ray local = ray;
        local.org = inst.to_object.point(ray.org);
        local.dir = inst.to_object.vector(ray.dir);
        if (bvh::any_hit(meshes(inst.mesh), local)) return true;
      }
    }
    return false;
  }
};

// The stored meshes on the device as the host holds them: object-space positions in double
// and corner indices, every mesh's concatenated (mesh m's vertices from vertex_base[m], its
// triangles from tri_base[m]). Only these cross to the device: the BVHs' float triangles and
// the receivers' world triangles (ao_trace.hpp's upload_plan) are formed from them there.
struct StoredMeshes {
  Kokkos::View<Vec3d*, MemSpace> positions;
  Kokkos::View<int*, MemSpace> corners;  // 3 per triangle, indices into the mesh's positions
  std::vector<std::int64_t> vertex_base, tri_base;  // per stored mesh, one past the last at the end
};
StoredMeshes upload_meshes(const AoScene& scene);

// Owns the device BVHs, instance table and stored meshes; query() is the kernel-side view.
class DeviceScene {
 public:
  DeviceScene(const AoScene& scene, bvh::BuildQuality quality, const GroundPlane& ground);
  const OcclusionQuery& query() const { return query_; }
  const StoredMeshes& meshes() const { return meshes_; }
  std::size_t bytes() const { return bytes_; }

 private:
  StoredMeshes meshes_;
  std::vector<bvh::Bvh<MemSpace>> bvhs_;
  OcclusionQuery query_;
  std::size_t bytes_ = 0;
};

}  // namespace rtmini::ao
