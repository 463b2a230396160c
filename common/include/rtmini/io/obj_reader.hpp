#pragma once
// Wavefront OBJ/MTL input (through Debian's tinyobjloader) and the mesh-file
// dispatcher used by the apps and the scene loader.
#include <cstddef>
#include <string>
#include <vector>

#include "rtmini/scene/mesh.hpp"

namespace rtmini {

// Reads an OBJ and its MTL libraries. Triangles and quads are kept as they are;
// polygons with more vertices are fan-triangulated. Each `o`/`g` name becomes one
// entry of Mesh::objects (repeated names share an id; unnamed faces go to "default").
// MTL Kd/Ks/Ke/Ns/Ni/d fill Material; `vt` and `f v/vt[/vn]` fill Mesh::texcoords and
// Face::uv; map_Kd, map_Ks, norm, map_bump/bump and disp (PNG only, paths resolved against the
// OBJ's folder, `-bm` kept as the map's scale) fill Material::maps. A light pre-scan validates
// field counts, numbers, finiteness and index ranges first, so errors carry "file:line: reason"; an
// undefined `usemtl` name, or a missing MTL file in an OBJ that uses materials, is an InputError
// too (an OBJ without `usemtl` loads without its missing library). Large files are scanned in
// pieces of whole lines, one thread each (the same Mesh and errors).
Mesh read_obj(const std::string& path);

namespace detail {
// read_obj with pieces of about piece_bytes, at most max_pieces (tests compare piece sizes).
Mesh read_obj(const std::string& path, std::size_t piece_bytes, std::size_t max_pieces);
}  // namespace detail

// Dispatches on the extension (case-insensitive): .obj -> read_obj, .bs -> read_bakeshop,
// .gltf/.glb -> read_gltf flattened into world space (io/gltf_reader.hpp).
Mesh read_mesh(const std::string& path);

// True for ".gltf" and ".glb" (an extension as lower_extension returns it).
bool is_gltf_extension(const std::string& ext);

// The files read_mesh(path) reads: the mesh itself and, for an OBJ, the material libraries it
// names that exist and the image maps those name, for a glTF its external buffers and images
// (io/input_files.hpp hashes them for the restart signature).
std::vector<std::string> mesh_files(const std::string& path);

}  // namespace rtmini
