#pragma once
// glTF 2.0 scenes (.gltf with external or data-URI buffers, .glb), read through Debian's
// tinygltf. Optional at build time (RTMINI_HAVE_GLTF): without it every function here throws
// InputError "built without glTF support".
//
// What is read, and what becomes of it:
//   - meshes: every primitive of mode TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN, indexed or
//     not, as triangles (Face::count 3); POINTS and LINES* primitives have no area and are
//     skipped. POSITION (float VEC3) is required; TEXCOORD_0 (float, or normalised unsigned
//     byte/short VEC2) fills Mesh::texcoords with v flipped (glTF's v grows downwards, the
//     Mesh's upwards as in OBJ). NORMAL is not read: both apps shade with geometric normals
//     and bake derives its own vertex normals, as for OBJ `vn`.
//   - materials: pbrMetallicRoughness.baseColorFactor (rgb) -> Material::diffuse,
//     emissiveFactor -> emissive, baseColorTexture -> maps.diffuse (the image's URI, percent-
//     decoded, resolved against the glTF file's folder). Metallic, roughness, alpha and the
//     other maps are not mapped. A primitive without a material gets material -1.
//   - the node hierarchy of the default scene (or scene 0): each node's matrix, or its
//     translation * rotation * scale, composed from the root down; every node with a mesh is
//     one instance of that mesh. A mesh referenced by several nodes is stored once.
//   - images embedded in the file (a bufferView of a .glb, or a data: URI) are refused when
//     textures are wanted (GltfTextures::kResolve): InputError naming the image and the
//     material. rtmini reads textures from image files only and writes no extracted copies.
//     Geometry-only readers (GltfTextures::kIgnore, bake --mode ao) do not look at images.
// A file that lists an extension in extensionsRequired (Draco, mesh quantisation, ...) is
// refused: its data would be misread. Malformed files (bad JSON, accessors outside their
// buffers, indices past the vertex count, node cycles) are InputError "file: reason".
#include <array>
#include <string>
#include <vector>

#include "rtmini/scene/mesh.hpp"

namespace rtmini {

// Row-major affine map p' = L p + t as 3 rows of (L | t), in double: object -> world.
using Affine3x4 = std::array<std::array<double, 4>, 3>;

inline Affine3x4 identity_affine() {
  return {{{1.0, 0.0, 0.0, 0.0}, {0.0, 1.0, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}}};
}
// a * b: apply b first, then a.
Affine3x4 compose_affine(const Affine3x4& a, const Affine3x4& b);
Vec3d apply_affine(const Affine3x4& a, const Vec3d& p);

struct GltfInstance {
  int mesh = 0;  // index into GltfScene::meshes
  Affine3x4 xform = identity_affine();
  std::string name;  // the node's name, or "node N"
};

struct GltfScene {
  std::string path;
  // One Mesh per glTF mesh, in object space. Each carries the file's whole material list, so
  // Face::material is the glTF material index (-1 = none).
  std::vector<Mesh> meshes;
  // same_geometry[m]: the first mesh whose primitives read the same accessors in the same
  // modes as mesh m (m itself if none). Writers such as bake --mode ao's .glb give each
  // instance its own glTF mesh (for its own colours) over shared geometry; readers that keep
  // instances store such meshes once.
  std::vector<int> same_geometry;
  std::vector<GltfInstance> instances;  // nodes with a mesh, depth-first in scene order
};

enum class GltfTextures {
  kResolve,  // base-colour textures become file paths; an embedded image is an InputError
  kIgnore,   // geometry only: images are not looked at (maps stay empty)
};

bool gltf_supported();  // false in a build without tinygltf

// Reads a .gltf or .glb (by extension). InputError "path: reason" on malformed input.
GltfScene read_gltf(const std::string& path, GltfTextures textures = GltfTextures::kResolve);

// Every instance's mesh in world space, appended into one Mesh: one object per instance (named
// after its node), the file's materials once, texture coordinates carried along.
Mesh flatten_gltf(const GltfScene& scene);

// The files a read of `path` opens: the glTF itself, its external buffers and (kResolve) its
// external images, for the restart signature (io/input_files.hpp).
std::vector<std::string> gltf_files(const std::string& path);

}  // namespace rtmini
