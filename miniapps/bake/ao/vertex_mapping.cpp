#include "vertex_mapping.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <map>
#include <utility>

#include "rtmini/io/error.hpp"
#include "vertex_fit_cg.hpp"

namespace rtmini::ao {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Step `done` of the least-squares solve is complete. The steps are single parallel loops of
// unlike cost, so they are counted but give no ETA (zero measured cost: "ETA ?").
void step_done(ProgressLine* progress, int done) {
  if (progress) progress->update(done, kLeastSquaresSteps, 0.0, kLeastSquaresSteps);
}

// Calls fn(b0, b1, b2, a) for every sample of global triangle g of receiver r:
// barycentric weights of its three vertices and the sample's visibility.
template <class Fn>
void for_each_sample(const SampleValues& sv, std::size_t r, std::int64_t g, Fn&& fn) {
  const SamplePlan& plan = *sv.plan;
  const std::uint64_t item = plan.item(r, g);
  for (std::int64_t s = plan.offsets[g]; s < plan.offsets[g + 1]; ++s) {
    Real u, v;
    sample_barycentrics(sv.seed, item, s - plan.offsets[g], u, v);
    const double du = u, dv = v;
    fn(1.0 - du - dv, du, dv, sv.visibility[s]);
  }
}

// Unique undirected edges (i < j) of a mesh, sorted.
std::vector<std::pair<int, int>> mesh_edges(const AoMesh& mesh) {
  std::vector<std::pair<int, int>> edges;
  edges.reserve(mesh.tris.size() * 3);
  for (const auto& t : mesh.tris) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace

SampleValues make_sample_values(const SamplePlan& plan, std::uint64_t seed,
                                const std::vector<std::uint16_t>& occluded, int rays) {
  SampleValues sv;
  sv.plan = &plan;
  sv.seed = seed;
  sv.visibility.resize(occluded.size());
  for (std::size_t i = 0; i < occluded.size(); ++i)
    sv.visibility[i] = 1.0 - static_cast<double>(occluded[i]) / rays;
  return sv;
}

std::vector<float> map_weighted_average(const AoScene& scene, const SampleValues& sv) {
  const SamplePlan& plan = *sv.plan;
  std::vector<double> sum(plan.total_vertices(), 0.0), weight(plan.total_vertices(), 0.0);
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoMesh& mesh = scene.meshes[scene.instances[plan.receivers[r]].mesh];
    const std::int64_t vbase = plan.vertex_base[r];
    for (std::int64_t g = plan.tri_base[r]; g < plan.tri_base[r + 1]; ++g) {
      const std::int64_t count = plan.offsets[g + 1] - plan.offsets[g];
      if (count == 0) continue;
      const double da = plan.areas[g] / static_cast<double>(count);
      const auto& tri = mesh.tris[g - plan.tri_base[r]];
      for_each_sample(sv, r, g, [&](double b0, double b1, double b2, double a) {
        const double b[3] = {b0, b1, b2};
        for (int k = 0; k < 3; ++k) {
          sum[vbase + tri[k]] += b[k] * da * a;
          weight[vbase + tri[k]] += b[k] * da;
        }
      });
    }
  }
  std::vector<float> out(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i)
    out[i] = weight[i] > 0.0 ? static_cast<float>(sum[i] / weight[i]) : 1.0f;
  return out;
}

namespace {

// Sparsity pattern shared by every instance of a stored mesh: the diagonal plus
// both directions of every edge, compressed column storage (symmetric), with
// the unweighted graph Laplacian as values and, per triangle, the 9 value slots
// of its 3x3 block, so assembly is a scatter instead of a triplet sort.
struct MeshPattern {
  Eigen::SparseMatrix<double> laplacian;
  std::vector<int> slots;  // 9 per triangle, row-major (i, j)
};

MeshPattern make_pattern(const AoMesh& mesh) {
  const int nv = static_cast<int>(mesh.positions.size());
  // Column v holds its neighbours j < v, then v, then its neighbours j > v: both
  // directions of every unique edge, written straight into compressed storage (no
  // triplet sort). mesh_edges is sorted by (i, j), which keeps every column sorted.
  const auto edges = mesh_edges(mesh);
  std::vector<int> outer(static_cast<std::size_t>(nv) + 1, 0);
  for (const auto& e : edges) {
    ++outer[e.first + 1];
    ++outer[e.second + 1];
  }
  for (int v = 0; v < nv; ++v) outer[v + 1] += outer[v] + 1;  // + the diagonal
  std::vector<int> inner(static_cast<std::size_t>(outer[nv]));
  std::vector<double> values(inner.size(), 0.0);
  // Rows j < v of column v come from edges (j, v): collect them per column first.
  std::vector<int> below_count(nv, 0);
  for (const auto& e : edges) ++below_count[e.second];
  std::vector<int> below_start(static_cast<std::size_t>(nv) + 1, 0);
  for (int v = 0; v < nv; ++v) below_start[v + 1] = below_start[v] + below_count[v];
  std::vector<int> below_rows(edges.size());
  {
    std::vector<int> at(below_start.begin(), below_start.end() - 1);
    for (const auto& e : edges) below_rows[at[e.second]++] = e.first;
  }
  std::size_t e = 0;  // edges (v, j > v) are contiguous and ascending for each v
  for (int v = 0; v < nv; ++v) {
    int k = outer[v];
    for (int q = below_start[v]; q < below_start[v + 1]; ++q) {
      inner[k] = below_rows[q];
      values[k++] = -1.0;
    }
    const int diag = k++;
    inner[diag] = v;
    int degree = below_start[v + 1] - below_start[v];
    for (; e < edges.size() && edges[e].first == v; ++e) {
      inner[k] = edges[e].second;
      values[k++] = -1.0;
      ++degree;
    }
    values[diag] = degree;
  }
  MeshPattern p;
  p.laplacian.resize(nv, nv);
  p.laplacian.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), p.laplacian.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), p.laplacian.innerIndexPtr());
  std::copy(values.begin(), values.end(), p.laplacian.valuePtr());
  const int* in = p.laplacian.innerIndexPtr();
  p.slots.resize(mesh.tris.size() * 9);
  for (std::size_t t = 0; t < mesh.tris.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const int row = mesh.tris[t][i], col = mesh.tris[t][j];
        const int* found = std::lower_bound(in + outer[col], in + outer[col + 1], row);
        p.slots[t * 9 + i * 3 + j] = static_cast<int>(found - in);
      }
    }
  }
  return p;
}

// Per triangle: the symmetric block sum_s w_s b b^T (6 values) and sum_s w_s a_s b (3).
struct TriangleBlock {
  double m[6];  // 00 01 02 11 12 22
  double f[3];
};

// Receivers with the same system matrix: same stored mesh, per-triangle sample
// counts and relative areas, hence (barycentrics keyed by mesh triangle) the same
// mass blocks. Groups in scene order, members in scene order; without sharing
// every receiver is a group of its own.
std::vector<std::vector<std::size_t>> group_receivers(const SamplePlan& plan, bool share) {
  auto same_system = [&](std::size_t q, std::size_t r) {
    if (plan.meshes[q] != plan.meshes[r]) return false;
    const std::int64_t gq = plan.tri_base[q], gr = plan.tri_base[r];
    for (std::int64_t t = 0; t < plan.tri_base[q + 1] - gq; ++t)
      if (plan.sample_count(gq + t) != plan.sample_count(gr + t) ||
          plan.relative_areas[gq + t] != plan.relative_areas[gr + t])
        return false;
    return true;
  };
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    std::size_t c = 0;
    while (share && c < groups.size() && !same_system(groups[c][0], r)) ++c;
    if (!share || c == groups.size()) groups.emplace_back();
    groups[share ? c : groups.size() - 1].push_back(r);
  }
  return groups;
}

// One factored system: A = weight * Laplacian + mass blocks (+1 on the diagonal of
// vertices no sample reaches), from the group's first member.
struct GroupSystem {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  std::vector<char> touched;  // per vertex: reached by a sample
  bool ok = false;
  double factor_s = 0;
};

void factor_group(const AoMesh& mesh, const MeshPattern& pat, const TriangleBlock* blocks,
                  double weight, GroupSystem& sys) {
  const int nv = static_cast<int>(mesh.positions.size());
  Eigen::SparseMatrix<double> a = pat.laplacian * weight;
  double* val = a.valuePtr();
  sys.touched.assign(nv, 0);
  static constexpr int kSym[9] = {0, 1, 2, 1, 3, 4, 2, 4, 5};
  for (std::size_t t = 0; t < mesh.tris.size(); ++t) {
    const TriangleBlock& b = blocks[t];
    if (b.m[0] + b.m[3] + b.m[5] <= 0.0) continue;
    const int* slot = &pat.slots[t * 9];
    for (int k = 0; k < 9; ++k) val[slot[k]] += b.m[kSym[k]];
    for (int i = 0; i < 3; ++i) sys.touched[mesh.tris[t][i]] = 1;
  }
  // Vertices without data are pulled weakly towards open (1).
  for (int v = 0; v < nv; ++v)
    if (!sys.touched[v]) a.coeffRef(v, v) += 1.0;
  const auto c0 = std::chrono::steady_clock::now();
  sys.solver.compute(a);
  sys.factor_s = seconds_since(c0);
  sys.ok = sys.solver.info() == Eigen::Success;
}

// The Eigen path: per-vertex values (1 where no system) and per-receiver failure flags.
std::vector<float> fit_cholesky(const AoScene& scene, const SampleValues& sv, double weight,
                                const std::vector<std::vector<std::size_t>>& groups,
                                LeastSquaresStats& st, ProgressLine* progress,
                                std::vector<char>& failed) {
  using Clock = std::chrono::steady_clock;
  using HostSpace = Kokkos::DefaultHostExecutionSpace;
  using DynamicHostPolicy = Kokkos::RangePolicy<HostSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
  const SamplePlan& plan = *sv.plan;
  const std::size_t nr = plan.receivers.size();
  std::vector<float> out(plan.total_vertices(), 1.0f);

  // Data term, one independent block per triangle (any thread count gives the same
  // sums), w_s = relative area / count.
  auto t0 = Clock::now();
  std::vector<TriangleBlock> blocks(static_cast<std::size_t>(plan.total_triangles()));
  std::vector<int> owner(blocks.size());
  for (std::size_t r = 0; r < nr; ++r)
    std::fill(owner.begin() + plan.tri_base[r], owner.begin() + plan.tri_base[r + 1],
              static_cast<int>(r));
  Kokkos::parallel_for(
      "rtmini::bake::ao::lsq_blocks", Kokkos::RangePolicy<HostSpace>(0, plan.total_triangles()),
      [&](std::int64_t g) {
        TriangleBlock& b = blocks[g];
        for (double& x : b.m) x = 0.0;
        for (double& x : b.f) x = 0.0;
        const std::int64_t count = plan.sample_count(g);
        if (count == 0 || plan.relative_areas[g] <= 0.0) return;
        const double w = plan.relative_areas[g] / static_cast<double>(count);
        for_each_sample(sv, owner[g], g, [&](double b0, double b1, double b2, double a) {
          b.m[0] += w * b0 * b0;
          b.m[1] += w * b0 * b1;
          b.m[2] += w * b0 * b2;
          b.m[3] += w * b1 * b1;
          b.m[4] += w * b1 * b2;
          b.m[5] += w * b2 * b2;
          b.f[0] += w * a * b0;
          b.f[1] += w * a * b1;
          b.f[2] += w * a * b2;
        });
      });
  st.assemble_s += seconds_since(t0);
  step_done(progress, 1);

  // Patterns once per stored mesh.
  t0 = Clock::now();
  std::map<int, MeshPattern> patterns;
  for (std::size_t r = 0; r < nr; ++r) {
    const int mesh_id = plan.meshes[r];
    if (!patterns.count(mesh_id)) patterns.emplace(mesh_id, make_pattern(scene.meshes[mesh_id]));
  }
  st.regularize_s += seconds_since(t0);
  step_done(progress, 2);

  // One sparse Cholesky per group of identical systems, groups in parallel (the
  // sample factors per mesh), then one solve per receiver, receivers in parallel.
  const std::size_t ng = groups.size();
  std::vector<GroupSystem> systems(ng);
  std::vector<int> group_of(nr, 0);
  for (std::size_t c = 0; c < ng; ++c)
    for (std::size_t r : groups[c]) group_of[r] = static_cast<int>(c);
  Kokkos::parallel_for("rtmini::bake::ao::lsq_factor",
                       DynamicHostPolicy(0, static_cast<std::int64_t>(ng)), [&](std::int64_t c) {
                         const std::size_t r = groups[c][0];
                         const AoMesh& mesh = scene.meshes[plan.meshes[r]];
                         if (mesh.positions.empty()) return;
                         factor_group(mesh, patterns.at(plan.meshes[r]),
                                      blocks.data() + plan.tri_base[r], weight, systems[c]);
                       });
  step_done(progress, 3);
  failed.assign(nr, 0);
  std::vector<double> solve_s(nr, 0.0);
  Kokkos::parallel_for("rtmini::bake::ao::lsq_solve",
                       DynamicHostPolicy(0, static_cast<std::int64_t>(nr)), [&](std::int64_t r) {
                         const AoMesh& mesh = scene.meshes[plan.meshes[r]];
                         const int nv = static_cast<int>(mesh.positions.size());
                         if (nv == 0) return;
                         const GroupSystem& sys = systems[group_of[r]];
                         if (!sys.ok) {
                           failed[r] = 1;
                           return;
                         }
                         const auto c0 = Clock::now();
                         Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv);
                         const std::int64_t g0 = plan.tri_base[r];
                         for (std::size_t t = 0; t < mesh.tris.size(); ++t) {
                           const TriangleBlock& b = blocks[g0 + static_cast<std::int64_t>(t)];
                           for (int i = 0; i < 3; ++i) rhs[mesh.tris[t][i]] += b.f[i];
                         }
                         for (int v = 0; v < nv; ++v)
                           if (!sys.touched[v]) rhs[v] += 1.0;
                         const Eigen::VectorXd x = sys.solver.solve(rhs);
                         solve_s[r] = seconds_since(c0);
                         if (!x.allFinite()) {
                           failed[r] = 1;
                           return;
                         }
                         for (int v = 0; v < nv; ++v)
                           out[plan.vertex_base[r] + v] = static_cast<float>(x[v]);
                       });
  for (const GroupSystem& sys : systems) st.factor_s += sys.factor_s;
  st.factorizations += static_cast<int>(ng);
  for (std::size_t r = 0; r < nr; ++r) st.solve_s += solve_s[r];
  return out;
}

}  // namespace

FitMethod parse_fit_method(const std::string& name) {
  if (name == "cholesky") return FitMethod::kCholesky;
  if (name == "cg") return FitMethod::kCg;
  if (name == "auto")
    return Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                      Kokkos::DefaultExecutionSpace::memory_space>::accessible
               ? FitMethod::kCholesky
               : FitMethod::kCg;
  throw InputError("bad usage: --fit must be auto, cholesky or cg, not '" + name + "'");
}

const char* fit_method_name(FitMethod method) {
  return method == FitMethod::kCg ? "cg" : "cholesky";
}

std::vector<float> map_least_squares(const AoScene& scene, const SampleValues& sv, double weight,
                                     LeastSquaresStats* stats, bool share_factorization,
                                     ProgressLine* progress, FitMethod method) {
  const SamplePlan& plan = *sv.plan;
  LeastSquaresStats local;
  LeastSquaresStats& st = stats ? *stats : local;
  const std::size_t nr = plan.receivers.size();
  const auto groups = group_receivers(plan, share_factorization);
  st.systems += static_cast<int>(groups.size());
  std::vector<char> failed;
  std::vector<float> out;
  if (method == FitMethod::kCg) {
    CgFit fit = fit_least_squares_cg(scene, sv, weight, groups, st, progress);
    out = std::move(fit.values);
    failed = std::move(fit.failed);
  } else {
    out = fit_cholesky(scene, sv, weight, groups, st, progress, failed);
  }
  std::vector<float> fallback;  // weighted average where a system was singular
  for (std::size_t r = 0; r < nr; ++r) {
    if (!failed[r]) continue;
    ++st.fallbacks;
    if (fallback.empty()) fallback = map_weighted_average(scene, sv);
    std::copy(fallback.begin() + plan.vertex_base[r], fallback.begin() + plan.vertex_base[r + 1],
              out.begin() + plan.vertex_base[r]);
  }
  return out;
}

}  // namespace rtmini::ao
