#include "moving_objects_host.hpp"

#include <algorithm>
#include <cmath>

#include "rtmini/bvh/build.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::sketch {
namespace {

using MemSpaceT = Kokkos::DefaultExecutionSpace::memory_space;

// Mover index of every mesh object, -1 for still ones.
std::vector<int> mover_of_objects(const HostScene& s) {
  std::vector<int> of(s.mesh.objects.size(), -1);
  for (std::size_t m = 0; m < s.movers.size(); ++m)
    for (int o = s.movers[m].first_object; o < s.movers[m].end_object; ++o)
      of[o] = static_cast<int>(m);
  return of;
}

template <class T, class View>
void append(std::vector<T>& out, const View& v) {
  out.insert(out.end(), v.data(), v.data() + v.extent(0));
}

}  // namespace

Vec3d objects_centre(const Mesh& mesh, int first, int end) {
  Bounds3d b;
  for (const Face& f : mesh.faces)
    if (f.object >= first && f.object < end)
      for (int k = 0; k < f.count; ++k) b.add(mesh.positions[f.v[k]]);
  return b.centre();
}

void add_mover(HostScene& s, int first, int end, const Vec3d& pivot, const ObjectMotion& motion,
               long line) {
  MoverDesc m;
  m.first_object = first;
  m.end_object = end;
  m.pivot = pivot;
  m.velocity = motion.velocity;
  m.axis = normalize(motion.spin_axis);
  m.spin_rad = motion.spin_deg * math::kPi / 180.0;
  m.line = line;
  s.movers.push_back(m);
}

void place_moving_objects_last(HostScene& s, const std::string& file) {
  const std::vector<int> mover = mover_of_objects(s);
  // Still faces first, then each mover's faces together: the still BVH is built over a prefix
  // of the triangles and each mover's tree over one contiguous range (upload_motion).
  std::stable_sort(s.mesh.faces.begin(), s.mesh.faces.end(),
                   [&](const Face& a, const Face& b) { return mover[a.object] < mover[b.object]; });
  std::vector<char> moved(s.mesh.positions.size(), 0);
  for (const Face& f : s.mesh.faces) {
    const int m = mover[f.object];
    if (m < 0) continue;
    if (f.material >= 0 && s.mesh.materials[f.material].is_emissive())
      throw InputError(file, s.movers[m].line,
                       "a moving object must not emit light (lights are sampled at rest)");
    for (int k = 0; k < f.count; ++k) {
      if (moved[f.v[k]]) continue;
      moved[f.v[k]] = 1;
      s.mesh.positions[f.v[k]] -= s.movers[m].pivot;
    }
  }
  for (const MoverDesc& m : s.movers)
    for (int o = m.first_object; o < m.end_object; ++o)
      if (s.objects[o].radius > Real(0))
        s.objects[o].center = Vec3(Vec3d(s.objects[o].center) - m.pivot);
}

DeviceMotion<MemSpaceT> upload_motion(const HostScene& s, const TriangleList& tl,
                                      std::size_t first_moving, Real& coordinate_bound) {
  const std::vector<int> mover = mover_of_objects(s);
  std::vector<MovingObject> objects;
  std::vector<bvh::BvhNode> nodes;
  std::vector<Triangle> tris;
  std::vector<int> prim;
  std::vector<bvh::WideNode> wide;
  std::vector<bvh::TriangleLanes> leaves;
  double bound = coordinate_bound;
  std::size_t t = first_moving;
  for (std::size_t m = 0; m < s.movers.size(); ++m) {
    const MoverDesc& d = s.movers[m];
    const std::size_t first = t;
    std::vector<Triangle> local;
    double radius = 0;
    for (; t < tl.vertices.size() && mover[s.mesh.faces[tl.face[t]].object] == int(m); ++t) {
      Vec3 v[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = Vec3(s.mesh.positions[tl.vertices[t][k]]);
        radius = std::max(radius, length(Vec3d(v[k])));
      }
      local.push_back({v[0], v[1], v[2]});
    }
    MovingObject o;
    o.pivot = Vec3(d.pivot);
    o.velocity = Vec3(d.velocity);
    o.axis = Vec3(d.axis);
    o.spin = Real(d.spin_rad);
    // A little more than the farthest vertex: the sphere test runs on a ray moved in Real.
    o.radius = Real(radius * (1 + 1e-3) + 1e-6);
    o.node_base = static_cast<std::uint32_t>(nodes.size());
    o.tri_base = static_cast<std::uint32_t>(tris.size());
    o.wide_base = static_cast<std::uint32_t>(wide.size());
    o.leaf_base = static_cast<std::uint32_t>(leaves.size());
    o.first_tri = static_cast<int>(first);
    o.num_prims = static_cast<int>(local.size());
    if (!local.empty()) {
      // Built in host memory by the still scene's SAH builder (no pre-splits: one reference
      // per triangle), which also gives the 8-wide layout the host traverses.
      const Kokkos::View<const Triangle*, Kokkos::HostSpace> view(local.data(), local.size());
      const bvh::Bvh<Kokkos::HostSpace> tree = bvh::build<Kokkos::DefaultHostExecutionSpace>(
          Kokkos::DefaultHostExecutionSpace(), view, bvh::BuildQuality::kSah,
          bvh::QuantizedWide::kNever, 0.0);
      append(nodes, tree.nodes);
      append(tris, tree.tris);
      append(prim, tree.prim);
      append(wide, tree.wide);
      const std::size_t leaf0 = leaves.size(), wide0 = wide.size() - tree.wide.extent(0);
      append(leaves, tree.leaves);
      bvh::offset_leaf_prims(wide.data() + wide0, tree.wide.extent(0), leaves.data() + leaf0,
                             static_cast<int>(first));
    }
    objects.push_back(o);
    // Everywhere the object reaches while rays sample times in [-max_abs_time, max_abs_time].
    bound = std::max(bound, length(d.pivot) + length(d.velocity) * s.max_abs_time + radius);
  }
  coordinate_bound = Real(bound);
  DeviceMotion<MemSpaceT> out;
  out.objects = compat::upload<MemSpaceT>("rtmini::sketch::moving_objects", objects);
  out.nodes = compat::upload<MemSpaceT>("rtmini::sketch::moving_nodes", nodes);
  out.tris = compat::upload<MemSpaceT>("rtmini::sketch::moving_tris", tris);
  out.prim = compat::upload<MemSpaceT>("rtmini::sketch::moving_prim", prim);
  // The wide layout only where the kernels can traverse it (traverse_object).
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpaceT>::accessible) {
    out.wide = compat::upload<MemSpaceT>("rtmini::sketch::moving_wide", wide);
    out.leaves = compat::upload<MemSpaceT>("rtmini::sketch::moving_leaves", leaves);
  }
  out.mover_of_object = compat::upload<MemSpaceT>("rtmini::sketch::mover_of_object", mover);
  out.count = static_cast<int>(objects.size());
  return out;
}

}  // namespace rtmini::sketch
