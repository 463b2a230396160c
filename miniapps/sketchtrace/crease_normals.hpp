#pragma once
// Shading normals split at creases. Around each vertex the triangles fall into smoothing
// groups: two triangles that share an edge at the vertex join one group when the angle
// between their face normals is at most the crease angle (so `--crease-angle` is the
// face-to-face angle it claims to be). Each group gets the area-weighted mean of its face
// normals; a corner of a triangle uses its group's normal. A cube's 90 degree edges
// therefore stay flat at the default 60 degrees, a finely tessellated sphere stays smooth.
#include <array>
#include <vector>

#include "rtmini/geometry/vec.hpp"

namespace rtmini::sketch {

struct CornerNormals {
  std::vector<Vec3d> normals;                 // one per smoothing group; zero for degenerate faces
  std::vector<std::array<int, 3>> of_corner;  // normal id of each triangle corner
};

// `cos_crease` = cos(crease angle). Triangles with zero area join no group (their corners get
// a zero normal, which the shading replaces by the geometric one); so do faces wound the other
// way round than their neighbour (their normals point more than 90 degrees apart).
CornerNormals crease_split_normals(const std::vector<Vec3d>& positions,
                                   const std::vector<std::array<int, 3>>& triangles,
                                   double cos_crease);

}  // namespace rtmini::sketch
