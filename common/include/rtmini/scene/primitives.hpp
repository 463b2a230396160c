#pragma once
// Closed, watertight primitive meshes (shared vertices, consistent outward
// winding) appended to a Mesh: used for analytic spheres of the hand-drawn
// paper's scenes, test geometry and scene generators.
#include "rtmini/scene/mesh.hpp"

namespace rtmini {

// Icosahedron subdivided `level` times and projected onto the sphere:
// 20 * 4^level triangles.
void append_icosphere(Mesh& mesh, const Vec3d& center, double radius, int level, int material,
                      int object);

// Axis-aligned box as 6 quads with outward normals (inward when `inward`, for rooms and furnaces).
void append_box(Mesh& mesh, const Vec3d& lo, const Vec3d& hi, int material, int object,
                bool inward = false);

// A quad corner, corner + u, corner + u + v, corner + v (normal = u x v).
void append_quad(Mesh& mesh, const Vec3d& corner, const Vec3d& u, const Vec3d& v, int material,
                 int object);

// A grid of quads over the parallelogram (corner, u, v), nu x nv cells, shared vertices.
void append_grid(Mesh& mesh, const Vec3d& corner, const Vec3d& u, const Vec3d& v, int nu, int nv,
                 int material, int object);

// A flat fan of `count` triangles in the plane z = centre.z, all sharing the centre, their far
// edges on the arc of `radius` from angle 0 to `angle` (radians, from +x towards +y). Each is a
// sliver of aspect count / angle (radius over far edge): the BVH's worst case (issue 18).
void append_fan(Mesh& mesh, const Vec3d& center, double radius, double angle, int count,
                int material, int object);

}  // namespace rtmini
