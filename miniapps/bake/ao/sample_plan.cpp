#include "sample_plan.hpp"

#include <cmath>

namespace rtmini::ao {

SamplePlan plan_samples(const AoScene& scene, std::int64_t requested, int min_per_face) {
  SamplePlan plan;
  plan.receivers = scene.receivers();
  plan.tri_base.push_back(0);
  plan.vertex_base.push_back(0);
  for (int i : plan.receivers) {
    const AoInstance& inst = scene.instances[i];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    for (const auto& t : mesh.tris) {
      const Vec3d a = inst.xform.point(mesh.positions[t[0]]);
      const Vec3d b = inst.xform.point(mesh.positions[t[1]]);
      const Vec3d c = inst.xform.point(mesh.positions[t[2]]);
      plan.areas.push_back(0.5 * length(cross(b - a, c - a)));
    }
    plan.tri_base.push_back(plan.tri_base.back() + static_cast<std::int64_t>(mesh.tris.size()));
    plan.vertex_base.push_back(plan.vertex_base.back() +
                               static_cast<std::int64_t>(mesh.positions.size()));
  }
  const std::int64_t triangles = plan.total_triangles();
  const std::int64_t minimum = triangles * min_per_face;
  const std::int64_t extra = requested > minimum ? requested - minimum : 0;
  double total_area = 0.0;
  for (double a : plan.areas) total_area += a;
  plan.offsets.resize(static_cast<std::size_t>(triangles) + 1);
  plan.offsets[0] = 0;
  double running = 0.0;
  std::int64_t handed_out = 0;
  for (std::int64_t g = 0; g < triangles; ++g) {
    running += plan.areas[g];
    // The last triangle closes the sum exactly whatever the rounding of `running`.
    const std::int64_t upto =
        total_area > 0.0
            ? (g + 1 == triangles ? extra
                                  : static_cast<std::int64_t>(std::floor(
                                        static_cast<double>(extra) * (running / total_area))))
            : 0;
    const std::int64_t mine = std::min(upto, extra) - handed_out;
    const std::int64_t add = mine > 0 ? mine : 0;
    handed_out += add;
    plan.offsets[g + 1] = plan.offsets[g] + min_per_face + add;
  }
  return plan;
}

}  // namespace rtmini::ao
