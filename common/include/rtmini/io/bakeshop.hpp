#pragma once
// Bake Shop (.bs) maps, the baking seed's format made strict (docs/architecture.md §5):
//
//   # hemisphere                optional first line: a hemisphere map (ViewpointColors)
//   x y z                       vertex, followed by zero or more viewpoint lines
//   | dx dy dz r g b            camera-ray direction into the vertex, linear RGB colour
//   <blank line>
//   : dr dg db  sr sg sb  er eg eb   material: diffuse, reflective, emissive
//   <blank line>
//   a b c d m  |  a b c m       quad or triangle, 0-based vertex indices, material (-1 = none)
//   !
//
// Each section is zero or more lines; exactly one blank line separates them, so an
// empty materials section reads "...\n\n\n<faces>". Number formatting (writer):
// std::to_chars shortest round-trip form, locale-independent -- double for positions,
// float for directions and colours -- so write -> read -> write is byte-identical and
// read values equal the written ones exactly. Lines are variable length: an MPI writer
// places each rank's formatted block at the exclusive prefix sum of the block sizes.
#include <cstddef>
#include <string>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini {

// The first line of a hemisphere map's text form (older files have none: full-sphere maps).
inline constexpr const char* kBakeshopHemisphereLine = "# hemisphere\n";

// Reads a .bs file. Viewpoint lines go to Mesh::viewpoints (empty when the file
// has none). One object (named after the file stem); materials have no names.
// Malformed input: InputError "file:line: reason".
Mesh read_bakeshop(const std::string& path);

// One vertex line followed by its n viewpoint lines ("| dx dy dz r g b").
std::string format_bakeshop_vertex(const Vec3d& p, const Vec3f* dirs, const Vec3f* colors,
                                   std::size_t n);
// Same, for a vertex whose colour is view-independent: n lines with the same colour.
std::string format_bakeshop_vertex_uniform(const Vec3d& p, const Vec3f* dirs, std::size_t n,
                                           const Vec3f& color);
// The materials section (one ": ..." line per material, no separators).
std::string format_bakeshop_materials(const Mesh& mesh);
// The faces section (one line per face, no separators, no "!").
std::string format_bakeshop_faces(const Mesh& mesh);
// The complete text of a mesh: vertices (+viewpoints), blank, materials, blank, faces, "!".
std::string format_bakeshop(const Mesh& mesh);

// Writes format_bakeshop(mesh) atomically (temporary file + rename); IoError on failure.
void write_bakeshop(const std::string& path, const Mesh& mesh);

}  // namespace rtmini
