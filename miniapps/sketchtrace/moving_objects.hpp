#pragma once
// Object motion blur: rigid objects that translate (velocity) and spin (about an axis through
// their centre) over the shutter, each ray seeing the scene at its own instant (Ray::time).
//
// Acceleration is two-level. The still geometry keeps the ordinary BVH (so a scene without
// moving objects traces exactly as before). Each moving object gets its own BVH built once
// over its triangles in object space (centred on its pivot); a ray is moved into that space
// by the inverse of the object's motion at the ray's time and traverses the object's tree
// unchanged. Why not a motion BVH with time-interpolated node bounds: (1) rotation is exact
// here, while lerped boxes are not conservative for turning vertices (they need a sagitta
// margin that grows with angle squared) and moving triangles to the ray's time costs three
// vertex transforms per test instead of one ray transform per object; (2) the static tree,
// its builders and its SIMD/GPU layouts stay untouched; (3) the object trees reuse the
// binary traversal (bvh/traverse.hpp) as is. The price: the top level is a list, tested
// object by object (a bounding-sphere test at the ray's instant first), which suits scenes
// with a few moving objects (results/accuracy/model.md gives the measured cost); many
// moving objects would want a BVH over their swept bounds as the top level.
#include <cstdint>

#include "rtmini/bvh/bvh.hpp"
#include "rtmini/geometry/ray.hpp"

namespace rtmini::sketch {

// One moving object in the render frame: at time t its object-space point x is at
// pivot + velocity t + R(axis, spin t) x. Its triangles are the global triangles
// [first_tri, first_tri + num_prims) (stored in object space), its tree the nodes and
// leaf triangles from node_base / tri_base (binary layout) and wide_base / leaf_base (8-wide
// host layout) of DeviceMotion's tables.
struct MovingObject {
  Vec3 pivot, velocity, axis;  // axis: unit
  Real spin = 0;               // radians per unit time
  Real radius = 0;             // bounds every object-space vertex: |x| <= radius
  std::uint32_t node_base = 0, tri_base = 0, wide_base = 0, leaf_base = 0;
  int num_prims = 0, first_tri = 0;
};

// The rigid motion of one object at one instant.
struct RigidPose {
  Vec3 offset;  // pivot + velocity t
  Vec3 axis;
  Real cos_a = 1, sin_a = 0;

  // Rodrigues' formula; sign -1 turns the other way (the inverse rotation).
  KOKKOS_INLINE_FUNCTION Vec3 rotate(const Vec3& x, Real sign) const {
    return x * cos_a + cross(axis, x) * (sign * sin_a) + axis * (dot(axis, x) * (Real(1) - cos_a));
  }
  KOKKOS_INLINE_FUNCTION Vec3 point_to_world(const Vec3& x) const {
    return offset + rotate(x, Real(1));
  }
  KOKKOS_INLINE_FUNCTION Vec3 vector_to_world(const Vec3& v) const { return rotate(v, Real(1)); }
  // The ray in object space; rotation keeps lengths, so its t values are the world ray's.
  KOKKOS_INLINE_FUNCTION Ray ray_to_object(const Ray& r) const {
    Ray o = r;
    o.org = rotate(r.org - offset, Real(-1));
    o.dir = rotate(r.dir, Real(-1));
    return o;
  }
};

KOKKOS_INLINE_FUNCTION RigidPose pose_at(const MovingObject& m, Real time) {
  RigidPose p;
  p.offset = m.pivot + m.velocity * time;
  p.axis = m.axis;
  if (m.spin != Real(0)) {
    const Real a = m.spin * time;
    p.cos_a = math::cos(a);
    p.sin_a = math::sin(a);
  }
  return p;
}

// Whether the ray's segment [tmin, tmax] can reach the object's bounding sphere at the
// ray's instant (a cheap cull before the ray is moved into object space).
KOKKOS_INLINE_FUNCTION bool may_hit_object(const MovingObject& m, const Vec3& centre,
                                           const Ray& r) {
  const Vec3 oc = r.org - centre;
  const Real half_b = dot(oc, r.dir);
  const Real c = dot(oc, oc) - m.radius * m.radius;
  const Real disc = half_b * half_b - dot(r.dir, r.dir) * c;
  if (disc < Real(0)) return false;
  // Generous on the segment ends: the BVH decides exactly.
  const Real s = math::sqrt(disc), a = dot(r.dir, r.dir);
  return (-half_b + s) >= r.tmin * a * Real(0.999) && (-half_b - s) <= r.tmax * a * Real(1.001);
}

template <class MemorySpace>
struct DeviceMotion {
  Kokkos::View<MovingObject*, MemorySpace> objects;
  Kokkos::View<bvh::BvhNode*, MemorySpace> nodes;  // every object's tree, one after another
  Kokkos::View<Triangle*, MemorySpace> tris;       // their leaf triangles, in leaf order
  Kokkos::View<int*, MemorySpace> prim;            // leaf slot -> object-local triangle
  // The same trees in the 8-wide SIMD layout (bvh.hpp), host memory only; the leaves' prim
  // lanes hold global triangle ids.
  Kokkos::View<bvh::WideNode*, MemorySpace> wide;
  Kokkos::View<bvh::TriangleLanes*, MemorySpace> leaves;
  Kokkos::View<int*, MemorySpace> mover_of_object;  // mesh object -> moving object, -1 = still
  int count = 0;
};

// One object's tree seen through DeviceMotion's shared tables, in the shape
// bvh::detail::traverse and traverse_wide read (num_prims, nodes(i), tris(i), prim(i),
// wide(i), leaves(i)); prim reports the global triangle id.
template <class MemorySpace>
struct ObjectTree {
  const DeviceMotion<MemorySpace>& motion;
  const MovingObject& object;
  int num_prims;
  KOKKOS_INLINE_FUNCTION ObjectTree(const DeviceMotion<MemorySpace>& m, const MovingObject& o)
      : motion(m), object(o), num_prims(o.num_prims) {}
  KOKKOS_INLINE_FUNCTION const bvh::BvhNode& nodes(std::uint32_t i) const {
    return motion.nodes(object.node_base + i);
  }
  KOKKOS_INLINE_FUNCTION const Triangle& tris(std::uint32_t i) const {
    return motion.tris(object.tri_base + i);
  }
  KOKKOS_INLINE_FUNCTION int prim(std::uint32_t i) const {
    return object.first_tri + motion.prim(object.tri_base + i);
  }
  KOKKOS_INLINE_FUNCTION const bvh::WideNode& wide(std::uint32_t i) const {
    return motion.wide(object.wide_base + i);
  }
  KOKKOS_INLINE_FUNCTION const bvh::TriangleLanes& leaves(std::uint32_t i) const {
    return motion.leaves(object.leaf_base + i);
  }
};

}  // namespace rtmini::sketch
