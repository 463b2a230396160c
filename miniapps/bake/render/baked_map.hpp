#pragma once
// A baked ray-trace map ready to render: the mesh and each vertex's colours in the baker's
// device layout (bake_scene.hpp): N colours in Fibonacci order for a view-dependent vertex,
// one colour for a vertex whose N colours are all equal (the baker writes a view-independent
// vertex as N copies of one colour), so MapReader reads it exactly as the Chef does.
#include <cstdint>
#include <string>
#include <vector>

#include "bake_scene.hpp"
#include "map_reader.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::bake {

struct BakedMapHost {
  Mesh mesh;                               // geometry and materials (viewpoints moved out)
  int viewpoints = 0;                      // N of the bake
  std::vector<std::int64_t> color_offset;  // vertices + 1 entries
  std::vector<Vec3f> colors;
  std::int64_t view_dependent_vertices = 0;
  // A hemisphere map: N/2 colours per view-dependent vertex, in the frame of the bake's vertex
  // normal (recomputed from the mesh by prepare_bake_scene: the same bits as the bake's).
  bool hemisphere = false;
  std::vector<Vec3> normal;  // per vertex, hemisphere maps only
};

// Reads a baked .bs (text) or .bsb (binary) map and checks that it is one: every vertex of a
// face has the same number N of viewpoints, in the baker's Fibonacci order. InputError
// "file:line: reason" (text) or "file: vertex V: reason" (binary) otherwise.
BakedMapHost read_baked_map(const std::string& path);

// The same checks and layout for a mesh already in memory; `text_lines`: report the .bs line
// numbers of vertices and viewpoints.
BakedMapHost make_baked_map(Mesh mesh, const std::string& path, bool text_lines);

struct BakedMapDevice {
  DeviceMesh<MemSpace> mesh;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<Vec3f*, MemSpace> colors;
  int viewpoints = 0;        // N of the sphere (the lookup's point set)
  HemisphereMap hemisphere;  // off for a full-sphere map
};

BakedMapDevice upload_baked_map(const BakedMapHost& map, bvh::BuildQuality quality);

}  // namespace rtmini::bake
