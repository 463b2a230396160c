#include "displace.hpp"

#include <cmath>

#include "rtmini/io/error.hpp"

namespace rtmini::sketch {
namespace {

// A point of a face: position and texture coordinate.
struct Corner {
  Vec3d p;
  double u, v;
};

Corner lerp(const Corner& a, const Corner& b, double t) {
  return {a.p + (b.p - a.p) * t, a.u + (b.u - a.u) * t, a.v + (b.v - a.v) * t};
}

// Builds the displaced grid of one face into `mesh`.
class FaceGrid {
 public:
  FaceGrid(Mesh& mesh, const Face& face, int material, const Image& height, double scale)
      : mesh_(mesh), face_(face), material_(material), height_(height), scale_(scale) {}

  void quad(const Corner c[4], const Vec3d& normal, int n) {
    std::vector<std::array<int, 2>> id((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double s = double(i) / n, t = double(j) / n;
        const bool border = i == 0 || j == 0 || i == n || j == n;
        id[j * (n + 1) + i] =
            vertex(lerp(lerp(c[0], c[1], s), lerp(c[3], c[2], s), t), normal, border);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto& a = id[j * (n + 1) + i];
        const auto& b = id[j * (n + 1) + i + 1];
        const auto& c2 = id[(j + 1) * (n + 1) + i + 1];
        const auto& d = id[(j + 1) * (n + 1) + i];
        triangle(a, b, c2);
        triangle(a, c2, d);
      }
  }

  void triangle_grid(const Corner c[3], const Vec3d& normal, int n) {
    std::vector<std::array<int, 2>> id((n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i) {
        const Corner p{
            c[0].p + (c[1].p - c[0].p) * (double(i) / n) + (c[2].p - c[0].p) * (double(j) / n),
            c[0].u + (c[1].u - c[0].u) * i / n + (c[2].u - c[0].u) * j / n,
            c[0].v + (c[1].v - c[0].v) * i / n + (c[2].v - c[0].v) * j / n};
        id[j * (n + 1) + i] = vertex(p, normal, i == 0 || j == 0 || i + j == n);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        triangle(id[j * (n + 1) + i], id[j * (n + 1) + i + 1], id[(j + 1) * (n + 1) + i]);
        if (i + j < n - 1)
          triangle(id[j * (n + 1) + i + 1], id[(j + 1) * (n + 1) + i + 1],
                   id[(j + 1) * (n + 1) + i]);
      }
  }

 private:
  // {vertex id, texture coordinate id} of a new displaced vertex; border vertices stay put.
  std::array<int, 2> vertex(const Corner& c, const Vec3d& normal, bool border) {
    const double h = border ? 1.0 : height_at(height_, c.u, c.v);
    mesh_.positions.push_back(c.p + normal * ((h - 1.0) * scale_));
    mesh_.texcoords.push_back({static_cast<float>(c.u), static_cast<float>(c.v)});
    return {static_cast<int>(mesh_.positions.size()) - 1,
            static_cast<int>(mesh_.texcoords.size()) - 1};
  }

  void triangle(const std::array<int, 2>& a, const std::array<int, 2>& b,
                const std::array<int, 2>& c) {
    Face f;
    f.count = 3;
    f.v = {a[0], b[0], c[0], -1};
    f.uv = {a[1], b[1], c[1], -1};
    f.material = material_;
    f.object = face_.object;
    mesh_.faces.push_back(f);
  }

  Mesh& mesh_;
  const Face& face_;
  int material_;
  const Image& height_;
  double scale_;
};

}  // namespace

DisplacementMode parse_displacement_mode(const std::string& name) {
  if (name == "parallax") return DisplacementMode::kParallax;
  if (name == "tessellate") return DisplacementMode::kTessellate;
  if (name == "off") return DisplacementMode::kOff;
  throw InputError("--displacement: must be parallax, tessellate or off (got '" + name + "')");
}

float height_at(const Image& image, double u, double v) {
  const double x = u * image.width - 0.5, y = (1.0 - v) * image.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const auto texel = [&](long i, long j) {
    i %= image.width;
    j %= image.height;
    if (i < 0) i += image.width;
    if (j < 0) j += image.height;
    return static_cast<double>(image.at(static_cast<int>(i), static_cast<int>(j), 0));
  };
  const long x0 = static_cast<long>(fx), y0 = static_cast<long>(fy);
  const double ax = x - fx, ay = y - fy;
  const double top = texel(x0, y0) * (1 - ax) + texel(x0 + 1, y0) * ax;
  const double bottom = texel(x0, y0 + 1) * (1 - ax) + texel(x0 + 1, y0 + 1) * ax;
  return static_cast<float>(top * (1 - ay) + bottom * ay);
}

std::size_t apply_displacement_mode(Mesh& mesh, const std::vector<MapImage>& images,
                                    DisplacementMode mode, int level) {
  if (mode == DisplacementMode::kParallax) return 0;
  // The displaced (or dropped) faces' material: the same without its height field.
  std::vector<int> flat_material(mesh.materials.size(), -1);
  for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
    if (mesh.materials[m].maps.displacement.empty()) continue;
    Material copy = mesh.materials[m];
    copy.maps.displacement.clear();
    copy.name += ".displaced";
    mesh.materials.push_back(copy);
    flat_material[m] = static_cast<int>(mesh.materials.size()) - 1;
  }
  std::size_t replaced = 0;
  const std::vector<Face> faces = mesh.faces;
  mesh.faces.clear();
  for (const Face& f : faces) {
    const bool displaced = f.material >= 0 && flat_material[f.material] >= 0 && f.uv[0] >= 0 &&
                           f.uv[1] >= 0 && f.uv[2] >= 0 && (f.count == 3 || f.uv[3] >= 0);
    if (!displaced) {
      mesh.faces.push_back(f);
      continue;
    }
    ++replaced;
    const Material& m = mesh.materials[f.material];
    const int flat = flat_material[f.material];
    if (mode == DisplacementMode::kOff) {
      Face g = f;
      g.material = flat;
      mesh.faces.push_back(g);
      continue;
    }
    const Image& height = images[find_map_image(images, m.maps.displacement, false)].image;
    Corner c[4];
    for (int k = 0; k < f.count; ++k)
      c[k] = {mesh.positions[f.v[k]], mesh.texcoords[f.uv[k]].u, mesh.texcoords[f.uv[k]].v};
    const Vec3d normal = normalize(cross(c[1].p - c[0].p, c[2].p - c[0].p));
    FaceGrid grid(mesh, f, flat, height, m.maps.displacement_scale);
    if (f.count == 4)
      grid.quad(c, normal, 1 << level);
    else
      grid.triangle_grid(c, normal, 1 << level);
  }
  return replaced;
}

}  // namespace rtmini::sketch
