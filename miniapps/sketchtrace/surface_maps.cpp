#include "surface_maps.hpp"

#include <algorithm>
#include <cmath>

#include "tangent_frame.hpp"

namespace rtmini::sketch {
namespace {

using DeviceSpace = Kokkos::DefaultExecutionSpace::memory_space;

// Input index range [first, last) that output texel i of `out` texels covers in `in`.
void covered(int i, int in, int out, int& first, int& last) {
  first = static_cast<int>(static_cast<long>(i) * in / out);
  last = static_cast<int>(static_cast<long>(i + 1) * in / out);
}

}  // namespace

std::vector<MapImage> load_map_images(const std::vector<Material>& materials) {
  std::vector<MapImage> images;
  const auto add = [&](const std::string& path, bool colour) {
    if (path.empty() || find_map_image(images, path, colour) >= 0) return;
    images.push_back({path, colour, colour ? read_png(path) : read_png_data(path)});
  };
  for (const Material& m : materials) {
    add(m.maps.diffuse, true);
    add(m.maps.specular, true);
    add(m.maps.normal, false);
    add(m.maps.bump, false);
    add(m.maps.displacement, false);
  }
  return images;
}

int find_map_image(const std::vector<MapImage>& images, const std::string& path, bool colour) {
  if (path.empty()) return -1;
  for (std::size_t i = 0; i < images.size(); ++i)
    if (images[i].path == path && images[i].colour == colour) return static_cast<int>(i);
  return -1;
}

Image downsample(const Image& image) {
  const int w = std::max(1, image.width / 2), h = std::max(1, image.height / 2);
  Image out(w, h, image.channels);
  for (int y = 0; y < h; ++y) {
    int y0, y1;
    covered(y, image.height, h, y0, y1);
    for (int x = 0; x < w; ++x) {
      int x0, x1;
      covered(x, image.width, w, x0, x1);
      const float inv = 1.f / static_cast<float>((y1 - y0) * (x1 - x0));
      for (int c = 0; c < image.channels; ++c) {
        float sum = 0.f;
        for (int yy = y0; yy < y1; ++yy)
          for (int xx = x0; xx < x1; ++xx) sum += image.at(xx, yy, c);
        out.at(x, y, c) = sum * inv;
      }
    }
  }
  return out;
}

int PackedTextures::add(const Image& image) {
  TextureDesc d;
  d.first_level = static_cast<int>(levels.size());
  d.levels = 0;
  Image level = image;
  for (;;) {
    TextureLevel l;
    l.offset = static_cast<int>(texels.size() / 3);
    l.width = level.width;
    l.height = level.height;
    levels.push_back(l);
    ++d.levels;
    // RGB(A) or grey: the first three channels, grey repeated.
    for (int y = 0; y < level.height; ++y)
      for (int x = 0; x < level.width; ++x)
        for (int c = 0; c < 3; ++c)
          texels.push_back(level.at(x, y, std::min(c, level.channels - 1)));
    if (level.width == 1 && level.height == 1) break;
    level = downsample(level);
  }
  textures.push_back(d);
  return static_cast<int>(textures.size()) - 1;
}

double map_image_bytes(const std::vector<MapImage>& images) {
  double texels = 0;
  for (const MapImage& m : images) texels += double(m.image.width) * m.image.height * 4.0 / 3.0;
  return texels * 3 * sizeof(float);
}

double surface_map_bytes(const Mesh& mesh, const std::vector<MapImage>& images) {
  bool any = false;
  for (const Material& m : mesh.materials) any = any || m.maps.any();
  if (!any) return 0;
  return map_image_bytes(images) + double(mesh.triangle_count()) * sizeof(TexturedTriangle) +
         double(mesh.materials.size()) * sizeof(MaterialMapIds);
}

std::vector<TexturedTriangle> textured_triangles(const std::vector<Vec3d>& positions,
                                                 const std::vector<std::array<int, 3>>& tris,
                                                 const std::vector<std::array<int, 3>>& uv_ids,
                                                 const std::vector<TexCoord>& texcoords,
                                                 const std::vector<std::array<int, 3>>& normal_ids,
                                                 const std::vector<Vec3>& normals) {
  const CornerTangents tangents =
      corner_tangents(positions, tris, uv_ids, texcoords, normal_ids, normals);
  std::vector<TexturedTriangle> out(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    if (uv_ids[t][0] < 0 || uv_ids[t][1] < 0 || uv_ids[t][2] < 0) continue;
    TexturedTriangle& r = out[t];
    r.has_uv = true;
    for (int k = 0; k < 3; ++k) {
      r.u[k] = Real(texcoords[uv_ids[t][k]].u);
      r.v[k] = Real(texcoords[uv_ids[t][k]].v);
      r.tangent[k] = tangents.tangent[t][k];
    }
    r.sign = Real(tangents.sign[t]);
    const Vec3d& a = positions[tris[t][0]];
    const double world = length(cross(positions[tris[t][1]] - a, positions[tris[t][2]] - a));
    const double uv = std::fabs(double(r.u[1] - r.u[0]) * (r.v[2] - r.v[0]) -
                                double(r.u[2] - r.u[0]) * (r.v[1] - r.v[0]));
    if (world > 0 && uv > 0) {
      r.lod_base = Real(0.5 * std::log2(uv / world));
      r.world_per_uv = Real(std::sqrt(world / uv));
    }
  }
  return out;
}

SurfaceMaps<DeviceSpace> upload_surface_maps(const Mesh& mesh, const std::vector<MapImage>& images,
                                             const std::vector<std::array<int, 3>>& tris,
                                             const std::vector<std::array<int, 3>>& uv_ids,
                                             const std::vector<std::array<int, 3>>& normal_ids,
                                             const std::vector<Vec3>& normals) {
  SurfaceMaps<DeviceSpace> d;
  for (const Material& m : mesh.materials)
    if (m.maps.any()) d.any = true;
  if (!d.any) return d;
  PackedTextures packed;
  std::vector<int> texture_of(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) texture_of[i] = packed.add(images[i].image);
  const auto id = [&](const std::string& path, bool colour) {
    const int i = find_map_image(images, path, colour);
    return i < 0 ? -1 : texture_of[i];
  };
  std::vector<MaterialMapIds> ids(mesh.materials.size());
  for (std::size_t m = 0; m < ids.size(); ++m) {
    const MaterialMaps& maps = mesh.materials[m].maps;
    ids[m].diffuse = id(maps.diffuse, true);
    ids[m].specular = id(maps.specular, true);
    ids[m].normal = id(maps.normal, false);
    ids[m].bump = id(maps.bump, false);
    ids[m].displacement = id(maps.displacement, false);
    ids[m].bump_scale = Real(maps.bump_scale);
    ids[m].displacement_scale = Real(maps.displacement_scale);
  }
  const std::vector<TexturedTriangle> records =
      textured_triangles(mesh.positions, tris, uv_ids, mesh.texcoords, normal_ids, normals);
  d.texels = compat::upload<DeviceSpace>("rtmini::sketch::texels", packed.texels);
  d.levels = compat::upload<DeviceSpace>("rtmini::sketch::texture_levels", packed.levels);
  d.textures = compat::upload<DeviceSpace>("rtmini::sketch::textures", packed.textures);
  d.materials = compat::upload<DeviceSpace>("rtmini::sketch::material_maps", ids);
  d.tris = compat::upload<DeviceSpace>("rtmini::sketch::textured_triangles", records);
  d.bytes = packed.texels.size() * sizeof(float) + packed.levels.size() * sizeof(TextureLevel) +
            packed.textures.size() * sizeof(TextureDesc) + ids.size() * sizeof(MaterialMapIds) +
            records.size() * sizeof(TexturedTriangle);
  return d;
}

}  // namespace rtmini::sketch
