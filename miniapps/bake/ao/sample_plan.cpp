#include "sample_plan.hpp"

#include <algorithm>
#include <cmath>

namespace rtmini::ao {
namespace {

double area_in_double(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  return 0.5 * length(cross(b - a, c - a));
}

// World area / object area when the linear part L is a similarity (L^T L = s^2 I),
// else 0. Snapped to 32 mantissa bits so rotations that are orthonormal only up
// to rounding give every instance of a mesh the same scale, bit for bit.
double similarity_area_scale(const AffineD& x) {
  double g[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      g[i][j] = x.m[0][i] * x.m[0][j] + x.m[1][i] * x.m[1][j] + x.m[2][i] * x.m[2][j];
  const double s2 = (g[0][0] + g[1][1] + g[2][2]) / 3.0;
  if (!(s2 > 0.0) || !std::isfinite(s2)) return 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::fabs(g[i][j] - (i == j ? s2 : 0.0)) > 1e-12 * s2) return 0.0;
  int e = 0;
  const double m = std::frexp(s2, &e);
  return std::ldexp(std::round(std::ldexp(m, 32)), e - 32);
}

// Hands `extra` points to n items in proportion to `weight`: item i gets
// out[i] = floor(E * C_i / W) - floor(E * C_{i-1} / W); the last item closes the
// sum exactly whatever the rounding of the running sum C.
void split_by_weight(const double* weight, std::size_t n, std::int64_t extra, std::int64_t* out) {
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) total += weight[i];
  double running = 0.0;
  std::int64_t handed_out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    running += weight[i];
    const std::int64_t upto =
        !(total > 0.0) ? 0
        : i + 1 == n
            ? extra
            : static_cast<std::int64_t>(std::floor(static_cast<double>(extra) * (running / total)));
    const std::int64_t mine = std::min(upto, extra) - handed_out;
    out[i] = mine > 0 ? mine : 0;
    handed_out += out[i];
  }
}

}  // namespace

SamplePlan plan_samples(const AoScene& scene, std::int64_t requested, int min_per_face) {
  SamplePlan plan;
  plan.receivers = scene.receivers();
  const std::size_t nr = plan.receivers.size();
  plan.tri_base.push_back(0);
  plan.vertex_base.push_back(0);
  std::size_t all_tris = 0;
  for (int i : plan.receivers) all_tris += scene.meshes[scene.instances[i].mesh].tris.size();
  plan.areas.reserve(all_tris);
  plan.relative_areas.reserve(all_tris);
  // Object-space areas once per stored mesh (only meshes that receive).
  std::vector<std::vector<double>> mesh_areas(scene.meshes.size());
  std::vector<double> scale(nr), receiver_area(nr, 0.0);
  for (std::size_t r = 0; r < nr; ++r) {
    const AoInstance& inst = scene.instances[plan.receivers[r]];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    plan.meshes.push_back(inst.mesh);
    scale[r] = similarity_area_scale(inst.xform);
    std::vector<double>& obj = mesh_areas[inst.mesh];
    if (scale[r] > 0.0 && obj.size() != mesh.tris.size()) {
      obj.clear();
      for (const auto& t : mesh.tris)
        obj.push_back(
            area_in_double(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
    }
    // Shape areas: object space for similarities (shared by instances), else world.
    const std::size_t first = plan.areas.size();
    for (std::size_t t = 0; t < mesh.tris.size(); ++t) {
      double world;
      if (scale[r] > 0.0) {
        world = obj[t] * scale[r];
        plan.relative_areas.push_back(obj[t]);
      } else {
        const auto& tri = mesh.tris[t];
        world = area_in_double(inst.xform.point(mesh.positions[tri[0]]),
                               inst.xform.point(mesh.positions[tri[1]]),
                               inst.xform.point(mesh.positions[tri[2]]));
        plan.relative_areas.push_back(world);
      }
      plan.areas.push_back(world);
      receiver_area[r] += world;
    }
    double shape_sum = 0.0;
    for (std::size_t g = first; g < plan.areas.size(); ++g) shape_sum += plan.relative_areas[g];
    const double mean = shape_sum / static_cast<double>(mesh.tris.size());
    for (std::size_t g = first; g < plan.areas.size(); ++g)
      plan.relative_areas[g] = mean > 0.0 ? plan.relative_areas[g] / mean : 0.0;
    plan.tri_base.push_back(plan.tri_base.back() + static_cast<std::int64_t>(mesh.tris.size()));
    plan.vertex_base.push_back(plan.vertex_base.back() +
                               static_cast<std::int64_t>(mesh.positions.size()));
  }
  const std::int64_t triangles = plan.total_triangles();
  const std::int64_t minimum = triangles * min_per_face;
  const std::int64_t extra = requested > minimum ? requested - minimum : 0;

  // Classes: receivers of one mesh under similarities of one area scale; any
  // other receiver is a class of its own. Members in scene order.
  std::vector<std::vector<std::size_t>> classes;
  std::vector<double> class_area;
  for (std::size_t r = 0; r < nr; ++r) {
    std::size_t c = 0;
    while (c < classes.size() && !(scale[r] > 0.0 && plan.meshes[classes[c][0]] == plan.meshes[r] &&
                                   scale[classes[c][0]] == scale[r]))
      ++c;
    if (c == classes.size()) {
      classes.emplace_back();
      class_area.push_back(0.0);
    }
    classes[c].push_back(r);
    class_area[c] += receiver_area[r];
  }
  std::vector<std::int64_t> class_extra(classes.size());
  split_by_weight(class_area.data(), classes.size(), extra, class_extra.data());
  // Per-triangle counts first (prefix-summed below); a member with the same share
  // as the previous member of its class copies that member's counts.
  plan.offsets.assign(static_cast<std::size_t>(triangles) + 1, 0);
  for (std::size_t c = 0; c < classes.size(); ++c) {
    const auto n = static_cast<std::int64_t>(classes[c].size());
    auto share = [&](std::int64_t k) {
      return class_extra[c] / n + (k < class_extra[c] % n ? 1 : 0);
    };
    for (std::int64_t k = 0; k < n; ++k) {
      const std::size_t r = classes[c][k];
      const std::int64_t mine = share(k);
      std::int64_t* counts = plan.offsets.data() + plan.tri_base[r] + 1;
      const std::int64_t nt = plan.tri_base[r + 1] - plan.tri_base[r];
      if (k > 0 && share(k - 1) == mine) {
        const std::int64_t* prev = plan.offsets.data() + plan.tri_base[classes[c][k - 1]] + 1;
        std::copy(prev, prev + nt, counts);
        continue;
      }
      split_by_weight(plan.relative_areas.data() + plan.tri_base[r], static_cast<std::size_t>(nt),
                      mine, counts);
      for (std::int64_t t = 0; t < nt; ++t) counts[t] += min_per_face;
    }
  }
  for (std::int64_t g = 0; g < triangles; ++g) plan.offsets[g + 1] += plan.offsets[g];
  return plan;
}

}  // namespace rtmini::ao
