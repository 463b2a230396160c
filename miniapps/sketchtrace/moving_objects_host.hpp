#pragma once
// Host side of object motion blur (moving_objects.hpp): declaring moving objects while a
// scene is built, putting their faces last in object space, and uploading their trees.
#include <string>

#include "moving_objects.hpp"
#include "render_scene.hpp"

namespace rtmini::sketch {

// The bounding-box centre of the vertices of objects [first, end) (a moving mesh's pivot).
Vec3d objects_centre(const Mesh& mesh, int first, int end);

// Declares objects [first, end) of s.mesh as one moving object turning about `pivot`
// (render frame).
void add_mover(HostScene& s, int first, int end, const Vec3d& pivot, const ObjectMotion& motion,
               long line);

// Moves the movers' faces after every still face (stable, in mover order) and their vertices
// and shading centres into object space (position - pivot). An emissive moving object is an
// InputError at its scene line: lights are sampled where they are at time 0.
void place_moving_objects_last(HostScene& s, const std::string& file);

// The movers' trees (built on the host, binned SAH) and tables in `MemorySpace`; triangles
// [first_moving, ...) of `tl` are theirs, in mover order. Raises `coordinate_bound` to cover
// every place a mover reaches within |t| <= s.max_abs_time.
DeviceMotion<Kokkos::DefaultExecutionSpace::memory_space> upload_motion(const HostScene& s,
                                                                        const TriangleList& tl,
                                                                        std::size_t first_moving,
                                                                        Real& coordinate_bound);

}  // namespace rtmini::sketch
