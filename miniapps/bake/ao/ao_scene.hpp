#pragma once
// The AO scene on the host: meshes stored once, instances (mesh + transform)
// that either receive samples or only block rays (the sample's "blockers").
#include <array>
#include <string>
#include <vector>

#include "affine.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::ao {

struct AoMesh {
  std::string name;
  std::vector<Vec3d> positions;          // object space
  std::vector<std::array<int, 3>> tris;  // triangulated faces (scene/mesh.hpp order)
};

struct AoInstance {
  int mesh = 0;
  AffineD xform;  // object -> world
  bool blocker = false;
};

struct Bounds {
  Vec3d lo{1e300}, hi{-1e300};
  void expand(const Vec3d& p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  double max_extent() const { return max_component(hi - lo); }
};

struct AoScene {
  std::vector<AoMesh> meshes;
  std::vector<AoInstance> instances;

  std::vector<int> receivers() const;  // instance ids that receive samples, in order
  Bounds receiver_bounds() const;      // world bounds of the receivers (sets the scene scale)
  Bounds instance_bounds(int instance) const;
  Bounds scene_bounds() const;  // world bounds of every instance, blockers included
};

AoMesh make_ao_mesh(const Mesh& mesh, const std::string& name);

// The same scene in the tracing frame (geometry/offset.hpp): each mesh's object space centred
// on its own bounds and the world centred on `world_origin`, composed into the instance
// transforms, all in double. Object-space BVHs and world rays then round relative to the
// scene's size, not its distance from the origin. Outputs keep the original scene.
AoScene recentred(const AoScene& scene, const Vec3d& world_origin);

// .obj/.bs: one mesh, one identity instance (the sample's OBJ loader flattens).
// .gltf/.glb: every node with a mesh is an instance (its world transform); a glTF mesh used
// by several nodes (or meshes over the same accessors) is stored once.
// .toml: io/scene_file.hpp layout; [[meshes]] naming the same file share one
// stored mesh; a [[meshes]] glTF entry adds all its node instances, the entry's transform
// applied after the nodes' own; [settings] blockers = [i, ...] marks [[meshes]] entries (0-based)
// as blockers; [[spheres]] become icosphere receivers. InputError on bad input.
AoScene load_ao_scene(const std::string& path);

// The sample's --instances n: every instance gets n-1 extra copies laid out on a
// grid across the two axes perpendicular to up_axis (0..2), 1.25 x the scene extent apart.
void replicate_instances(AoScene& scene, int copies, int up_axis);

}  // namespace rtmini::ao
