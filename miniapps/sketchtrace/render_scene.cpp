#include "render_scene.hpp"

#include <algorithm>
#include <cmath>

#include "displace.hpp"
#include "moving_objects_host.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/scene/camera.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini::sketch {
namespace {

int add_object(HostScene& s, const std::string& name, ObjectShading shading, bool quad_light) {
  s.mesh.objects.push_back(name);
  s.objects.push_back(shading);
  s.object_is_quad_light.push_back(quad_light ? 1 : 0);
  return static_cast<int>(s.mesh.objects.size()) - 1;
}

int add_material(Mesh& mesh, const Material& m) {
  mesh.materials.push_back(m);
  return static_cast<int>(mesh.materials.size()) - 1;
}

void bounds_of(const Mesh& mesh, Vec3d& lo, Vec3d& hi) {
  lo = Vec3d(1e300);
  hi = Vec3d(-1e300);
  for (const Vec3d& p : mesh.positions) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  if (mesh.positions.empty()) lo = hi = Vec3d(0.0);
}

// World-space bounds of the meshes, spheres and lights of a scene file.
Bounds3d placed_bounds(const Mesh& mesh, const SceneDescription& desc) {
  Bounds3d b = bounds_of(mesh.positions);
  for (const SphereDesc& sp : desc.spheres) {
    b.add(sp.center - Vec3d(sp.radius));
    b.add(sp.center + Vec3d(sp.radius));
  }
  for (const LightDesc& l : desc.lights) {
    if (l.type == LightType::kQuad) {
      b.add(l.corner);
      b.add(l.corner + l.edge_u + l.edge_v);
    } else if (l.type == LightType::kPoint) {
      b.add(l.position);
    } else {
      b.add(l.center - Vec3d(l.radius));
      b.add(l.center + Vec3d(l.radius));
    }
  }
  return b;
}

}  // namespace

CameraDesc to_render_frame(const CameraDesc& camera, const Vec3d& origin) {
  CameraDesc c = camera;
  c.position -= origin;
  c.look_at -= origin;
  return c;
}

void add_quad_light(HostScene& s, const Vec3d& corner, const Vec3d& u, const Vec3d& v,
                    const Vec3f& emission) {
  Material m;
  m.name = "light";
  m.diffuse = Vec3f(0.f);
  m.emissive = emission;
  const int mat = add_material(s.mesh, m);
  const int obj =
      add_object(s, "quad_light" + std::to_string(s.quads.size()), {Vec3(0), Real(0)}, true);
  append_quad(s.mesh, corner, u, v, mat, obj);
  const Vec3d n = cross(u, v);
  s.quads.push_back(
      {Vec3(corner), Vec3(u), Vec3(v), Vec3(normalize(n)), Real(length(n)), Vec3(emission)});
}

int add_sphere(HostScene& s, const Vec3d& center, double radius, int level,
               const Material& material, const std::string& name) {
  const int mat = add_material(s.mesh, material);
  const int obj = add_object(s, name, {Vec3(center), Real(radius)}, false);
  const std::size_t first_face = s.mesh.faces.size();
  append_icosphere(s.mesh, center, radius, level, mat, obj);
  // The closed icosphere holds the ball around its centre out to its nearest face plane (a
  // plane's distance bounds its triangle's from below) and lies within its farthest vertex's
  // distance; the margins cover the float triangles.
  double inner = radius, outer = 0;
  for (std::size_t f = first_face; f < s.mesh.faces.size(); ++f) {
    const Face& face = s.mesh.faces[f];
    const Vec3d& a = s.mesh.positions[face.v[0]];
    const Vec3d n =
        normalize(cross(s.mesh.positions[face.v[1]] - a, s.mesh.positions[face.v[2]] - a));
    inner = std::min(inner, std::fabs(dot(n, a - center)));
    for (int k = 0; k < face.count; ++k)
      outer = std::max(outer, length(s.mesh.positions[face.v[k]] - center));
  }
  s.solid_balls.push_back({Vec3(center), Real(inner * (1 - 1e-4)), Real(outer * (1 + 1e-4))});
  return obj;
}

int add_mesh_object(HostScene& s, const std::string& name) {
  return add_object(s, name, {Vec3(0), Real(0)}, false);
}

int add_scene_material(HostScene& s, const Material& material) {
  return add_material(s.mesh, material);
}

HostScene build_scene(const std::string& input, const SceneDescription* desc,
                      RenderSettings& settings) {
  HostScene s;
  s.name = input;
  std::vector<int> first_object;  // of each [[meshes]] entry
  s.mesh = desc ? load_scene_meshes(*desc, &first_object) : read_mesh(input);
  if (s.mesh.objects.empty()) s.mesh.objects.push_back("default");
  for (const Face& f : s.mesh.faces)
    while (f.object >= static_cast<int>(s.mesh.objects.size()))
      s.mesh.objects.push_back("object" + std::to_string(s.mesh.objects.size()));
  s.objects.assign(s.mesh.objects.size(), ObjectShading{Vec3(0), Real(0)});
  s.object_is_quad_light.assign(s.mesh.objects.size(), 0);
  // Faces without a material get the default grey Lambertian.
  int fallback = -1;
  for (Face& f : s.mesh.faces) {
    if (f.material >= 0) continue;
    if (fallback < 0) fallback = add_material(s.mesh, Material{});
    f.material = fallback;
  }
  // The render frame: the bounding-box centre of everything placed goes to the origin, in
  // double, before any coordinate is rounded to Real (geometry/offset.hpp says why).
  const Bounds3d placed = desc ? placed_bounds(s.mesh, *desc) : bounds_of(s.mesh.positions);
  s.origin = placed.centre();
  check_representable(placed, s.origin, input);
  for (Vec3d& p : s.mesh.positions) p -= s.origin;
  const int level = settings.sphere_subdivisions;
  if (desc) {
    const int mesh_objects = static_cast<int>(s.mesh.objects.size());
    for (std::size_t i = 0; i < desc->meshes.size(); ++i) {
      const MeshDesc& m = desc->meshes[i];
      if (!m.motion.moves()) continue;
      const int end = i + 1 < first_object.size() ? first_object[i + 1] : mesh_objects;
      add_mover(s, first_object[i], end, objects_centre(s.mesh, first_object[i], end), m.motion,
                m.line);
    }
    for (std::size_t i = 0; i < desc->spheres.size(); ++i) {
      const SphereDesc& sp = desc->spheres[i];
      const int obj = add_sphere(s, sp.center - s.origin, sp.radius, level, sp.material,
                                 "sphere" + std::to_string(i));
      if (!sp.motion.moves()) continue;
      s.solid_balls.pop_back();  // a moving ball is not where the shadow shortcut would look
      add_mover(s, obj, obj + 1, sp.center - s.origin, sp.motion, sp.line);
    }
    for (const LightDesc& l : desc->lights) {
      if (l.type == LightType::kQuad) {
        add_quad_light(s, l.corner - s.origin, l.edge_u, l.edge_v, l.emission);
      } else if (l.type == LightType::kPoint) {
        s.points.push_back({Vec3(l.position - s.origin), Vec3(l.intensity)});
      } else {
        Material m;
        m.name = "sphere_light";
        m.diffuse = Vec3f(0.f);
        m.emissive = l.emission;
        add_sphere(s, l.center - s.origin, l.radius, level, m, "sphere_light");
      }
    }
  }
  Vec3d lo, hi;
  bounds_of(s.mesh, lo, hi);
  if (!desc) {
    // A bare mesh: a square light of the bounds' size one radius above the top,
    // bright enough that the irradiance at the centre is about pi (white shades to ~Kd).
    const double r = std::max(0.5 * length(hi - lo), 1e-6);
    const Vec3d c = (lo + hi) * 0.5;
    const double height = hi.y + r;
    const double d = height - c.y;
    const double emission = math::kPi * d * d / (r * r);
    add_quad_light(s, Vec3d(c.x - 0.5 * r, height, c.z + 0.5 * r), Vec3d(r, 0, 0), Vec3d(0, 0, -r),
                   Vec3f(static_cast<float>(emission)));
    if (settings.ambient.x == 0.f && settings.ambient.y == 0.f && settings.ambient.z == 0.f)
      settings.ambient = Vec3f(0.05f);
  }
  // The camera stays in world coordinates (the CLI may still move it); see to_render_frame.
  if (!settings.has_camera)
    settings.camera = frame_bounds(lo + s.origin, hi + s.origin, settings.camera.fov_deg);
  if (s.mesh.faces.empty()) throw InputError(input, 0, "the scene has no geometry");
  if (!s.movers.empty()) {
    s.max_abs_time =
        std::max(std::fabs(settings.camera.shutter_open), std::fabs(settings.camera.shutter_close));
    place_moving_objects_last(s, input);
  }
  s.map_images = load_map_images(s.mesh.materials);
  apply_displacement_mode(s.mesh, s.map_images, parse_displacement_mode(settings.displacement),
                          settings.displacement_level);
  return s;
}

}  // namespace rtmini::sketch
