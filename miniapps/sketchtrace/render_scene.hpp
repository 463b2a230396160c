#pragma once
// The host-side scene sketchtrace renders: one triangle/quad mesh holding meshes,
// tessellated spheres and the visible geometry of area lights, plus the light
// lists and the per-object table that gives tessellated spheres their analytic
// normal. Built from a TOML scene or from a bare OBJ/.bs mesh (default camera
// framing its bounds, default quad light above it).
#include <string>
#include <vector>

#include "render_settings.hpp"
#include "rtmini/scene/mesh.hpp"
#include "rtmini/scene/recentre.hpp"
#include "surface_maps.hpp"

namespace rtmini::sketch {

// A parallelogram emitter corner + s u + t v, emitting `emission` (radiance) from
// both sides; its geometry is also in the mesh so it is seen directly.
struct QuadLight {
  Vec3 corner, u, v, normal;
  Real area;
  Vec3 emission;
};

struct PointLight {
  Vec3 position;
  Vec3 intensity;  // radiant intensity: irradiance = intensity cos / r^2
};

// Emissive triangles of one object (emissive mesh faces, sphere lights), sampled
// by area: triangles [first, first + count) of the emissive-triangle table.
struct MeshLight {
  int first, count;
  Real area;
};

// radius > 0: the object is a tessellated sphere shaded with the analytic normal.
struct ObjectShading {
  Vec3 center;
  Real radius;
};

// A generated sphere's closed triangle mesh lies between two concentric spheres: it holds
// the ball of radius `inner` and is held by the ball of radius `outer`. A shadow segment with
// both ends outside `outer` that enters `inner` crosses the triangles: it is blocked, and no
// traversal is needed to know it.
struct SolidBall {
  Vec3 center;
  Real inner, outer;
};

// Mesh objects [first_object, end_object) moving together (moving_objects.hpp): at time t an
// object-space point x (= its time-0 position - pivot) is at pivot + velocity t +
// R(axis, spin_rad t) x. `line`: the scene-file entry, for errors.
struct MoverDesc {
  int first_object = 0, end_object = 0;
  Vec3d pivot, velocity, axis;
  double spin_rad = 0;  // per unit time
  long line = 0;
};

struct HostScene {
  std::string name;
  Mesh mesh;
  std::vector<QuadLight> quads;
  std::vector<PointLight> points;
  std::vector<ObjectShading> objects;      // one per mesh object
  std::vector<char> object_is_quad_light;  // excluded from the mesh-light list
  std::vector<SolidBall> solid_balls;      // one per generated still sphere
  std::vector<MapImage> map_images;        // the materials' image maps, decoded once
  // Moving objects: their faces come last in the mesh (in this order) and their vertices are
  // in object space (place_moving_objects_last, moving_objects_host.hpp).
  std::vector<MoverDesc> movers;
  double max_abs_time = 0;  // the largest |shutter time|, to bound where movers can be
  // Everything above is in the render frame: world position = frame position + origin
  // (the bounding-box centre of the scene file's geometry and lights; geometry/offset.hpp).
  Vec3d origin{0.0};
};

// Device bytes of the scene's image maps and texture records (surface_maps.hpp).
inline double texture_bytes(const HostScene& s) { return surface_map_bytes(s.mesh, s.map_images); }

// A world-space camera in the render frame of a scene whose frame sits at `origin`.
CameraDesc to_render_frame(const CameraDesc& camera, const Vec3d& origin);

// Building blocks for generators and tests (build_scene uses them too). Each adds
// a new object; the quad light is also visible geometry.
void add_quad_light(HostScene& s, const Vec3d& corner, const Vec3d& u, const Vec3d& v,
                    const Vec3f& emission);
int add_sphere(HostScene& s, const Vec3d& center, double radius, int level,
               const Material& material, const std::string& name);
int add_mesh_object(HostScene& s, const std::string& name);
int add_scene_material(HostScene& s, const Material& material);

// Builds the scene from a parsed TOML description, or (desc == nullptr) from the
// mesh file `input` alone. Spheres use settings.sphere_subdivisions. Without a
// [camera], settings.camera becomes a default framing of the scene bounds; a bare
// mesh also gets a default quad light above it and a small ambient term.
HostScene build_scene(const std::string& input, const SceneDescription* desc,
                      RenderSettings& settings);

}  // namespace rtmini::sketch
