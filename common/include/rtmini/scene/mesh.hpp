#pragma once
// Host-side polygon mesh shared by both apps: triangles and quads, materials,
// object ids (OBJ groups), and optional per-vertex viewpoint colours (a baked
// Bake Shop map). Device copies are made from this by scene/device_mesh.hpp.
#include <array>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"

namespace rtmini {

// A texture coordinate (OBJ `vt`, glTF TEXCOORD_0); v grows upwards as in OBJ.
struct TexCoord {
  float u = 0.f, v = 0.f;
};

// Image maps of a material (MTL map_Kd, map_Ks, norm, map_bump/bump, disp; glTF
// baseColorTexture): paths resolved against the scene file's folder, empty = none.
// A scene without maps renders with the constant-material kernels.
struct MaterialMaps {
  std::string diffuse, specular, normal, bump, displacement;
  // MTL `-bm` of map_bump (height scale of the bump map) and of disp (the height, in the
  // mesh's units, of a white texel of the height field); 1 when not given.
  float bump_scale = 1.f, displacement_scale = 1.f;
  bool any() const {
    return !diffuse.empty() || !specular.empty() || !normal.empty() || !bump.empty() ||
           !displacement.empty();
  }
};

// Phong-style material of the seed papers: Kd diffuse, Ks mirror reflectance,
// Ke emission, Ns glossiness exponent, Ni index of refraction, d opacity.
struct Material {
  std::string name;
  Vec3f diffuse{0.8f, 0.8f, 0.8f};
  Vec3f reflective{0.f, 0.f, 0.f};
  Vec3f emissive{0.f, 0.f, 0.f};
  float shininess = 0.f;  // Ns; 0 (or >= kMirrorShininess) means a perfect mirror
  float ior = 1.f;        // Ni
  float opacity = 1.f;    // d; < 1 makes the surface refractive
  MaterialMaps maps;
  bool is_emissive() const { return emissive.x > 0.f || emissive.y > 0.f || emissive.z > 0.f; }
  bool is_reflective() const {
    return reflective.x > 0.f || reflective.y > 0.f || reflective.z > 0.f;
  }
};

// A polygon: 3 or 4 vertex indices (0-based), optional texture-coordinate
// indices (into Mesh::texcoords, -1 = none), a material index (-1 = none), and
// the object (OBJ group / mesh instance) it belongs to.
struct Face {
  std::array<int, 4> v{-1, -1, -1, -1};
  std::array<int, 4> uv{-1, -1, -1, -1};
  int count = 3;
  int material = -1;
  int object = 0;
};

// Per-vertex list of (camera-ray direction into the vertex, linear RGB colour),
// stored flat: vertex i owns entries [offsets[i], offsets[i+1]).
struct ViewpointColors {
  std::vector<std::size_t> offsets;  // size = vertices + 1, or empty when absent
  std::vector<Vec3f> dirs;
  std::vector<Vec3f> colors;
  // A hemisphere map (bake --directions hemisphere): each vertex's directions are in its own
  // frame (z = front, away from the surface) and cover the front half of the sphere only; a
  // viewpoint behind is read as its mirror image in front (miniapps/bake/map_reader.hpp).
  bool hemisphere = false;
  bool empty() const { return dirs.empty(); }
};

struct Mesh {
  std::vector<Vec3d> positions;
  std::vector<Face> faces;
  std::vector<TexCoord> texcoords;  // empty when no face has texture coordinates
  std::vector<Material> materials;
  std::vector<std::string> objects;  // names; Face::object indexes this
  ViewpointColors viewpoints;        // only for baked .bs maps

  std::size_t triangle_count() const {
    std::size_t n = 0;
    for (const Face& f : faces) n += f.count == 4 ? 2 : 1;
    return n;
  }
};

// Triangles of a mesh in a fixed order: face by face, a quad (a,b,c,d) as
// (a,b,c) then (a,c,d). Each triangle remembers its face (the quad id).
struct TriangleList {
  std::vector<std::array<int, 3>> vertices;
  std::vector<int> face;
};

inline TriangleList triangulate(const Mesh& mesh) {
  TriangleList out;
  out.vertices.reserve(mesh.triangle_count());
  out.face.reserve(mesh.triangle_count());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Face& face = mesh.faces[f];
    out.vertices.push_back({face.v[0], face.v[1], face.v[2]});
    out.face.push_back(static_cast<int>(f));
    if (face.count == 4) {
      out.vertices.push_back({face.v[0], face.v[2], face.v[3]});
      out.face.push_back(static_cast<int>(f));
    }
  }
  return out;
}

}  // namespace rtmini
