#pragma once
// Host side of the image maps: the decoded images of a scene's materials (read once
// per distinct file and use: colour maps sRGB-decoded, data maps as stored), their
// mip chains packed into one texel array, the per-triangle texture records, and the
// upload into SurfaceMaps (textures.hpp).
#include <array>
#include <string>
#include <vector>

#include "rtmini/io/image.hpp"
#include "rtmini/scene/mesh.hpp"
#include "textures.hpp"

namespace rtmini::sketch {

// One decoded map: the file and whether it holds colour (map_Kd, map_Ks: sRGB-decoded).
struct MapImage {
  std::string path;
  bool colour = true;
  Image image;
};

// Every distinct (file, colour) pair the materials name, decoded (read_png/read_png_data;
// the OBJ reader already checked each one at its MTL line).
std::vector<MapImage> load_map_images(const std::vector<Material>& materials);
// Index into `images` of a material's map, -1 for an empty path.
int find_map_image(const std::vector<MapImage>& images, const std::string& path, bool colour);

// The next mip level, half the size rounded down (at least 1): each texel the mean of the
// block of texels it covers, 2 x 2, or 3 wide (high) at the end of an odd-sized row (column).
Image downsample(const Image& image);

// Mip chains packed for the device: 3 floats per texel, levels finest first down to 1 x 1.
struct PackedTextures {
  std::vector<float> texels;
  std::vector<TextureLevel> levels;
  std::vector<TextureDesc> textures;
  int add(const Image& image);  // returns the texture id
};

// Device bytes of the packed mip chains of `images` (about 4/3 of level 0).
double map_image_bytes(const std::vector<MapImage>& images);
// What upload_surface_maps will allocate for a mesh with `triangles` triangles: the mip
// chains and, when any material has a map, one texture record per triangle.
double surface_map_bytes(const Mesh& mesh, const std::vector<MapImage>& images);

// Per-triangle texture records of a triangle list (uv ids per corner, -1 none): coordinates,
// lod_base and world_per_uv, tangents from tangent_frame.hpp.
std::vector<TexturedTriangle> textured_triangles(const std::vector<Vec3d>& positions,
                                                 const std::vector<std::array<int, 3>>& tris,
                                                 const std::vector<std::array<int, 3>>& uv_ids,
                                                 const std::vector<TexCoord>& texcoords,
                                                 const std::vector<std::array<int, 3>>& normal_ids,
                                                 const std::vector<Vec3>& normals);

// Everything above, uploaded. `maps.any` is false (and nothing is allocated) when no
// material has a map. `uv_ids` as for textured_triangles.
SurfaceMaps<Kokkos::DefaultExecutionSpace::memory_space> upload_surface_maps(
    const Mesh& mesh, const std::vector<MapImage>& images,
    const std::vector<std::array<int, 3>>& tris, const std::vector<std::array<int, 3>>& uv_ids,
    const std::vector<std::array<int, 3>>& normal_ids, const std::vector<Vec3>& normals);

}  // namespace rtmini::sketch
