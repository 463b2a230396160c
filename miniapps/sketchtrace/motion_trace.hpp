#pragma once
// Scene queries that see moving objects (moving_objects.hpp says how and why): the kernels
// hold a MovingScene instead of a DeviceScene when the scene has moving objects (kMotion), and
// these overloads of light_sampling.hpp's scene_* functions take over by overload resolution.
#include "light_sampling.hpp"
#include "rtmini/bvh/traverse.hpp"

namespace rtmini::sketch {

// A DeviceScene whose kernels trace its moving objects too (same data, other overloads).
struct MovingScene : DeviceScene {
  MovingScene() = default;
  MovingScene(const DeviceScene& d) : DeviceScene(d) {}  // NOLINT: implicit on purpose
};

// One object's tree: the 8-wide SIMD layout where it was built (host memory), else binary.
template <bool kAnyHit, bool kStats>
KOKKOS_INLINE_FUNCTION bool traverse_object(const ObjectTree<MemSpace>& tree, const Ray& ray,
                                            Hit& hit, bvh::TraversalStats* stats) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible) {
    if (tree.motion.wide.extent(0) > 0)
      return bvh::detail::traverse_wide<ObjectTree<MemSpace>, kAnyHit, kStats>(tree, ray, hit,
                                                                               stats);
  }
  return bvh::detail::traverse<ObjectTree<MemSpace>, kAnyHit, kStats>(tree, ray, hit, stats);
}

// Closest hit of `ray` (at ray.time) among the moving objects, beyond nothing nearer than
// `best` (updated; global triangle ids).
template <bool kAnyHit>
KOKKOS_INLINE_FUNCTION bool trace_movers(const MovingScene& scene, const Ray& ray, Hit& best,
                                         TraceCounter& c) {
  const DeviceMotion<MemSpace>& motion = scene.motion;
  bool found = false;
  for (int m = 0; m < motion.count; ++m) {
    const MovingObject& o = motion.objects(m);
    if (o.num_prims == 0) continue;
    Ray local = ray;
    local.tmax = best.t;
    // The cull needs only the centre; the rotation (cos, sin) only objects that pass it.
    if (!may_hit_object(o, o.pivot + o.velocity * ray.time, local)) continue;
    local = pose_at(o, ray.time).ray_to_object(local);
    const ObjectTree<MemSpace> tree(motion, o);
    Hit h;
    h.t = local.tmax;
    bvh::TraversalStats st;
    const bool hit = c.stats ? traverse_object<kAnyHit, true>(tree, local, h, &st)
                             : traverse_object<kAnyHit, false>(tree, local, h, nullptr);
    c.tests += st.tests;
    c.nodes += st.nodes;
    if (!hit) continue;
    if (kAnyHit) return true;
    if (h.t < best.t || (h.t == best.t && h.prim < best.prim)) {
      best = h;
      found = true;
    }
  }
  return found;
}

KOKKOS_INLINE_FUNCTION Hit scene_closest(const MovingScene& scene, const Ray& ray,
                                         TraceCounter& c) {
  Hit best = trace_closest(scene.mesh.accel, ray, c);
  if (!best.valid()) best.t = ray.tmax;
  trace_movers<false>(scene, ray, best, c);
  return best;
}

KOKKOS_INLINE_FUNCTION bool movers_occlude(const MovingScene& scene, const Ray& ray,
                                           TraceCounter& c) {
  Hit h;
  h.t = ray.tmax;
  return trace_movers<true>(scene, ray, h, c);
}

KOKKOS_INLINE_FUNCTION bool scene_occluded(const MovingScene& scene, const Ray& ray,
                                           TraceCounter& c) {
  return trace_occluded(scene.mesh.accel, ray, c) || movers_occlude(scene, ray, c);
}

// A hit on a moving object is shaded in object space (its triangles and sphere centre are
// stored there), then the point and normals are moved to where the object is at ray.time.
KOKKOS_INLINE_FUNCTION Surface scene_surface(const MovingScene& scene, const Ray& ray,
                                             const Hit& hit, bool smooth) {
  const int m = scene.motion.mover_of_object(scene.mesh.tri_object(hit.prim));
  if (m < 0) return surface_at(scene, ray, hit, smooth);
  const RigidPose pose = pose_at(scene.motion.objects(m), ray.time);
  Surface s = surface_at(scene, pose.ray_to_object(ray), hit, smooth);
  s.p = pose.point_to_world(s.p);
  s.ng = normalize(pose.vector_to_world(s.ng));
  s.ns = normalize(pose.vector_to_world(s.ns));
  return s;
}

}  // namespace rtmini::sketch
