#include "vertex_fit_cg.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "device_scene.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::ao {
namespace cg_detail {

template <class T>
using DView = Kokkos::View<T*, MemSpace>;
using Policy = Kokkos::RangePolicy<ExecSpace, Kokkos::IndexType<std::int64_t>>;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Device work is asynchronous: a phase ends when the device is done with it.
double fenced_seconds_since(std::chrono::steady_clock::time_point t) {
  Kokkos::fence();
  return seconds_since(t);
}

void step_done(ProgressLine* progress, int done) {
  if (progress) progress->update(done, kLeastSquaresSteps, 0.0, kLeastSquaresSteps);
}

// The batch on the host. Rows come in two numberings: system rows (one block of vertices per
// system, i.e. per group of identical receivers: the matrix rows) and global rows (the output
// vertices of every receiver, SamplePlan::vertex_base order: the unknowns).
struct HostLayout {
  std::vector<std::int64_t> sys_vbase{0};  // system s owns system rows [sys_vbase[s], [s+1])
  std::vector<std::int64_t> sys_tbase{0};  // ... and system triangles [sys_tbase[s], [s+1])
  std::vector<std::int64_t> sys_blocks;    // plan triangle of its first member's first triangle
  std::vector<int> tris;                   // 3 mesh-local vertex ids per system triangle
  std::vector<int> tri_sys;                // system of each system triangle
  std::vector<int> row_sys;                // system of each system row
  std::vector<int> rcv_sys;                // per plan receiver: its system
  std::vector<int> row_rcv;                // per global row: its plan receiver
};

HostLayout make_layout(const AoScene& scene, const SamplePlan& plan,
                       const std::vector<std::vector<std::size_t>>& groups) {
  HostLayout h;
  h.rcv_sys.assign(plan.receivers.size(), 0);
  for (std::size_t s = 0; s < groups.size(); ++s) {
    const std::size_t first = groups[s][0];
    const AoMesh& mesh = scene.meshes[plan.meshes[first]];
    const std::int64_t nv = plan.vertex_base[first + 1] - plan.vertex_base[first];
    h.sys_blocks.push_back(plan.tri_base[first]);
    h.sys_vbase.push_back(h.sys_vbase.back() + nv);
    h.sys_tbase.push_back(h.sys_tbase.back() + static_cast<std::int64_t>(mesh.tris.size()));
    for (const auto& t : mesh.tris) h.tris.insert(h.tris.end(), t.begin(), t.end());
    h.tri_sys.insert(h.tri_sys.end(), mesh.tris.size(), static_cast<int>(s));
    h.row_sys.insert(h.row_sys.end(), static_cast<std::size_t>(nv), static_cast<int>(s));
    for (const std::size_t r : groups[s]) h.rcv_sys[r] = static_cast<int>(s);
  }
  h.row_rcv.resize(static_cast<std::size_t>(plan.total_vertices()));
  for (std::size_t r = 0; r < plan.receivers.size(); ++r)
    std::fill(h.row_rcv.begin() + plan.vertex_base[r], h.row_rcv.begin() + plan.vertex_base[r + 1],
              static_cast<int>(r));
  return h;
}

// Per plan triangle g: the symmetric block sum_s w_s b b^T (00 01 02 11 12 22) and
// sum_s w_s a_s b, 9 doubles, the same sums in the same order as the host path.
DView<double> triangle_blocks(const SampleValues& sv) {
  const SamplePlan& plan = *sv.plan;
  const std::int64_t nt = plan.total_triangles();
  std::vector<std::uint64_t> items(static_cast<std::size_t>(nt));
  for (std::size_t r = 0; r < plan.receivers.size(); ++r)
    for (std::int64_t g = plan.tri_base[r]; g < plan.tri_base[r + 1]; ++g)
      items[g] = plan.item(r, g);
  const auto item = compat::upload<MemSpace>("rtmini::bake::ao::cg_items", items);
  const auto offsets = compat::upload<MemSpace>("rtmini::bake::ao::cg_offsets", plan.offsets);
  const auto rel = compat::upload<MemSpace>("rtmini::bake::ao::cg_rel_areas", plan.relative_areas);
  const auto vis = compat::upload<MemSpace>("rtmini::bake::ao::cg_visibility", sv.visibility);
  DView<double> blocks("rtmini::bake::ao::cg_blocks", static_cast<std::size_t>(nt) * 9);
  const std::uint64_t seed = sv.seed;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_blocks", Policy(0, nt), KOKKOS_LAMBDA(std::int64_t g) {
        double m[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        const std::int64_t count = offsets(g + 1) - offsets(g);
        if (count > 0 && rel(g) > 0.0) {
          const double w = rel(g) / static_cast<double>(count);
          for (std::int64_t s = offsets(g); s < offsets(g + 1); ++s) {
            Real u, v;
            sample_barycentrics(seed, item(g), s - offsets(g), u, v);
            const double du = u, dv = v;
            const double b0 = 1.0 - du - dv, b1 = du, b2 = dv, a = vis(s);
            m[0] += w * b0 * b0;
            m[1] += w * b0 * b1;
            m[2] += w * b0 * b2;
            m[3] += w * b1 * b1;
            m[4] += w * b1 * b2;
            m[5] += w * b2 * b2;
            m[6] += w * a * b0;
            m[7] += w * a * b1;
            m[8] += w * a * b2;
          }
        }
        for (int k = 0; k < 9; ++k) blocks(9 * g + k) = m[k];
      });
  return blocks;
}

// Exclusive prefix sum of `counts` (n + 1 entries, the last is the total).
DView<std::int64_t> exclusive_offsets(const char* label, const DView<std::int64_t>& counts) {
  const std::int64_t n = static_cast<std::int64_t>(counts.extent(0));
  DView<std::int64_t> out(std::string(label), static_cast<std::size_t>(n) + 1);
  Kokkos::parallel_scan(
      label, Policy(0, n), KOKKOS_LAMBDA(std::int64_t i, std::int64_t & sum, bool final) {
        if (final) out(i) = sum;
        sum += counts(i);
        if (final && i == n - 1) out(n) = sum;
      });
  return out;
}

KOKKOS_INLINE_FUNCTION void insertion_sort(const DView<std::int64_t>& a, std::int64_t lo,
                                           std::int64_t hi) {
  for (std::int64_t i = lo + 1; i < hi; ++i) {
    const std::int64_t key = a(i);
    std::int64_t j = i;
    for (; j > lo && a(j - 1) > key; --j) a(j) = a(j - 1);
    a(j) = key;
  }
}

KOKKOS_INLINE_FUNCTION void insertion_sort(const DView<int>& a, std::int64_t lo, std::int64_t hi) {
  for (std::int64_t i = lo + 1; i < hi; ++i) {
    const int key = a(i);
    std::int64_t j = i;
    for (; j > lo && a(j - 1) > key; --j) a(j) = a(j - 1);
    a(j) = key;
  }
}

// The sparsity pattern and values of every system, and the per-row data the solve needs.
struct DeviceSystems {
  DView<std::int64_t> sys_vbase, sys_tbase, sys_blocks;
  DView<int> tris, tri_sys, row_sys;
  DView<std::int64_t> inc_ptr, inc;  // per system row: its triangles (system ids), ascending
  DView<std::int64_t> row_ptr;       // per system row: its entries in cols/vals
  DView<int> cols;                   // mesh-local column, ascending within a row
  DView<double> vals, inv_diag;
  DView<char> touched;  // per system row: reached by a sample
};

// Whether vertex u already appeared at an earlier corner (entry e, corner c) of the
// triangles incident to one row (entries [p0, e], corners before c in entry e).
KOKKOS_INLINE_FUNCTION bool seen_before(const DView<int>& tris, const DView<std::int64_t>& inc,
                                        std::int64_t p0, std::int64_t e, int c, int u) {
  for (std::int64_t e2 = p0; e2 <= e; ++e2) {
    const std::int64_t t = inc(e2);
    const int corners = e2 == e ? c : 3;
    for (int c2 = 0; c2 < corners; ++c2)
      if (tris(3 * t + c2) == u) return true;
  }
  return false;
}

// Per system row: the triangles touching its vertex, ascending (the fixed order of every sum).
void build_incidence(DeviceSystems& d) {
  const std::int64_t nrows = static_cast<std::int64_t>(d.row_sys.extent(0));
  const std::int64_t ntris = static_cast<std::int64_t>(d.tri_sys.extent(0));
  DView<std::int64_t> count("rtmini::bake::ao::cg_incidence_count",
                            static_cast<std::size_t>(nrows));
  const auto tris = d.tris;
  const auto tri_sys = d.tri_sys;
  const auto sys_vbase = d.sys_vbase;
  // A triangle with a repeated vertex counts once for it.
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_incidence_count", Policy(0, ntris), KOKKOS_LAMBDA(std::int64_t t) {
        const std::int64_t base = sys_vbase(tri_sys(t));
        const int a = tris(3 * t), b = tris(3 * t + 1), c = tris(3 * t + 2);
        Kokkos::atomic_add(&count(base + a), std::int64_t(1));
        if (b != a) Kokkos::atomic_add(&count(base + b), std::int64_t(1));
        if (c != a && c != b) Kokkos::atomic_add(&count(base + c), std::int64_t(1));
      });
  d.inc_ptr = exclusive_offsets("rtmini::bake::ao::cg_incidence_ptr", count);
  std::int64_t total = 0;
  Kokkos::deep_copy(total, Kokkos::subview(d.inc_ptr, nrows));
  d.inc = DView<std::int64_t>("rtmini::bake::ao::cg_incidence", static_cast<std::size_t>(total));
  const auto inc_ptr = d.inc_ptr;
  const auto inc = d.inc;
  Kokkos::deep_copy(count, 0);  // now the fill cursor per row
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_incidence_fill", Policy(0, ntris), KOKKOS_LAMBDA(std::int64_t t) {
        const std::int64_t base = sys_vbase(tri_sys(t));
        const int a = tris(3 * t), b = tris(3 * t + 1), c = tris(3 * t + 2);
        inc(inc_ptr(base + a) + Kokkos::atomic_fetch_add(&count(base + a), std::int64_t(1))) = t;
        if (b != a)
          inc(inc_ptr(base + b) + Kokkos::atomic_fetch_add(&count(base + b), std::int64_t(1))) = t;
        if (c != a && c != b)
          inc(inc_ptr(base + c) + Kokkos::atomic_fetch_add(&count(base + c), std::int64_t(1))) = t;
      });
  // The atomics left each row's list in arrival order: sorted, every thread count agrees.
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_incidence_sort", Policy(0, nrows),
      KOKKOS_LAMBDA(std::int64_t i) { insertion_sort(inc, inc_ptr(i), inc_ptr(i + 1)); });
}

// Row v of a system holds v and every vertex sharing a triangle with it (the pattern of the
// host path: the diagonal plus both directions of every edge), columns ascending.
void build_pattern(DeviceSystems& d) {
  const std::int64_t nrows = static_cast<std::int64_t>(d.row_sys.extent(0));
  const auto tris = d.tris;
  const auto row_sys = d.row_sys;
  const auto sys_vbase = d.sys_vbase;
  const auto inc_ptr = d.inc_ptr;
  const auto inc = d.inc;
  DView<std::int64_t> count("rtmini::bake::ao::cg_row_count", static_cast<std::size_t>(nrows));
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_row_count", Policy(0, nrows), KOKKOS_LAMBDA(std::int64_t i) {
        const int v = static_cast<int>(i - sys_vbase(row_sys(i)));
        std::int64_t n = 1;
        for (std::int64_t e = inc_ptr(i); e < inc_ptr(i + 1); ++e)
          for (int c = 0; c < 3; ++c) {
            const int u = tris(3 * inc(e) + c);
            if (u != v && !seen_before(tris, inc, inc_ptr(i), e, c, u)) ++n;
          }
        count(i) = n;
      });
  d.row_ptr = exclusive_offsets("rtmini::bake::ao::cg_row_ptr", count);
  std::int64_t nnz = 0;
  Kokkos::deep_copy(nnz, Kokkos::subview(d.row_ptr, nrows));
  d.cols = DView<int>("rtmini::bake::ao::cg_cols", static_cast<std::size_t>(nnz));
  const auto row_ptr = d.row_ptr;
  const auto cols = d.cols;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_row_fill", Policy(0, nrows), KOKKOS_LAMBDA(std::int64_t i) {
        const int v = static_cast<int>(i - sys_vbase(row_sys(i)));
        std::int64_t k = row_ptr(i);
        cols(k++) = v;
        for (std::int64_t e = inc_ptr(i); e < inc_ptr(i + 1); ++e)
          for (int c = 0; c < 3; ++c) {
            const int u = tris(3 * inc(e) + c);
            if (u != v && !seen_before(tris, inc, inc_ptr(i), e, c, u)) cols(k++) = u;
          }
        insertion_sort(cols, row_ptr(i), row_ptr(i + 1));
      });
}

// Entry of column `col` in the sorted columns [lo, hi) (present by construction).
KOKKOS_INLINE_FUNCTION std::int64_t find_column(const DView<int>& cols, std::int64_t lo,
                                                std::int64_t hi, int col) {
  while (hi - lo > 1) {
    const std::int64_t mid = lo + (hi - lo) / 2;
    if (cols(mid) <= col)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// Index of entry (a, b) of a symmetric 3x3 block stored as 00 01 02 11 12 22.
KOKKOS_INLINE_FUNCTION int packed_symmetric(int a, int b) {
  const int i = a < b ? a : b, j = a < b ? b : a;
  return 3 * i - i * (i - 1) / 2 + (j - i);
}

// A = weight * Laplacian + the first member's blocks (+1 on the diagonal of rows no sample
// reaches), each entry summed in the host path's order: the Laplacian, then the triangles
// ascending, corners row-major. Also the Jacobi preconditioner and the touched rows.
void assemble_values(DeviceSystems& d, const DView<double>& blocks, double weight) {
  const std::int64_t nrows = static_cast<std::int64_t>(d.row_sys.extent(0));
  d.vals = DView<double>("rtmini::bake::ao::cg_vals", d.cols.extent(0));
  d.inv_diag = DView<double>("rtmini::bake::ao::cg_inv_diag", static_cast<std::size_t>(nrows));
  d.touched = DView<char>("rtmini::bake::ao::cg_touched", static_cast<std::size_t>(nrows));
  const auto tris = d.tris;
  const auto row_sys = d.row_sys;
  const auto sys_vbase = d.sys_vbase;
  const auto sys_tbase = d.sys_tbase;
  const auto sys_blocks = d.sys_blocks;
  const auto inc_ptr = d.inc_ptr;
  const auto inc = d.inc;
  const auto row_ptr = d.row_ptr;
  const auto cols = d.cols;
  const auto vals = d.vals;
  const auto inv_diag = d.inv_diag;
  const auto touched = d.touched;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_assemble", Policy(0, nrows), KOKKOS_LAMBDA(std::int64_t i) {
        const int s = row_sys(i);
        const int v = static_cast<int>(i - sys_vbase(s));
        const std::int64_t lo = row_ptr(i), hi = row_ptr(i + 1);
        const std::int64_t diag = find_column(cols, lo, hi, v);
        for (std::int64_t k = lo; k < hi; ++k) vals(k) = -1.0 * weight;
        vals(diag) = static_cast<double>(hi - lo - 1) * weight;  // the vertex degree
        bool reached = false;
        for (std::int64_t e = inc_ptr(i); e < inc_ptr(i + 1); ++e) {
          const std::int64_t t = inc(e);
          const double* m = &blocks(9 * (sys_blocks(s) + t - sys_tbase(s)));
          if (m[0] + m[3] + m[5] <= 0.0) continue;
          reached = true;
          for (int a = 0; a < 3; ++a) {
            if (tris(3 * t + a) != v) continue;
            for (int b = 0; b < 3; ++b)
              vals(find_column(cols, lo, hi, tris(3 * t + b))) += m[packed_symmetric(a, b)];
          }
        }
        if (!reached) vals(diag) += 1.0;  // no data: pulled weakly towards open (1)
        touched(i) = reached ? 1 : 0;
        inv_diag(i) = 1.0 / vals(diag);
      });
}

// The right-hand side of every receiver, over global rows: its own blocks' sum w a b, in the
// host path's order (triangles ascending), +1 where no sample reaches.
DView<double> assemble_rhs(const DeviceSystems& d, const DView<double>& blocks,
                           const DView<int>& row_rcv, const DView<int>& rcv_sys,
                           const DView<std::int64_t>& rcv_vbase,
                           const DView<std::int64_t>& rcv_tbase) {
  const std::int64_t n = static_cast<std::int64_t>(row_rcv.extent(0));
  DView<double> rhs("rtmini::bake::ao::cg_rhs", static_cast<std::size_t>(n));
  const auto tris = d.tris;
  const auto sys_vbase = d.sys_vbase;
  const auto sys_tbase = d.sys_tbase;
  const auto inc_ptr = d.inc_ptr;
  const auto inc = d.inc;
  const auto touched = d.touched;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_rhs", Policy(0, n), KOKKOS_LAMBDA(std::int64_t gi) {
        const int r = row_rcv(gi);
        const int s = rcv_sys(r);
        const int v = static_cast<int>(gi - rcv_vbase(r));
        const std::int64_t i = sys_vbase(s) + v;
        double sum = 0.0;
        for (std::int64_t e = inc_ptr(i); e < inc_ptr(i + 1); ++e) {
          const std::int64_t t = inc(e);
          const std::int64_t g = rcv_tbase(r) + t - sys_tbase(s);
          for (int a = 0; a < 3; ++a)
            if (tris(3 * t + a) == v) sum += blocks(9 * g + 6 + a);
        }
        if (!touched(i)) sum += 1.0;
        rhs(gi) = sum;
      });
  return rhs;
}

// A fixed summation tree over segments (receivers) of the global rows: level 0 sums chunks of
// kCgFanIn consecutive rows of one segment, each further level kCgFanIn consecutive sums of
// the level below, until one value per segment is left. The same tree for any thread count.
struct SumTree {
  std::vector<DView<std::int64_t>> starts;  // per level: chunk c sums inputs [c], [c + 1])
  std::vector<DView<double>> sums;          // per level: one per chunk
};

SumTree make_sum_tree(const std::vector<std::int64_t>& segment_lengths) {
  SumTree tree;
  std::vector<std::int64_t> lengths = segment_lengths;
  do {
    std::vector<std::int64_t> starts{0}, next;
    for (const std::int64_t n : lengths) {
      const std::int64_t first = starts.back();
      const std::int64_t chunks = std::max<std::int64_t>(1, (n + kCgFanIn - 1) / kCgFanIn);
      for (std::int64_t c = 1; c <= chunks; ++c)
        starts.push_back(std::min(first + c * kCgFanIn, first + n));
      next.push_back(chunks);
    }
    tree.starts.push_back(compat::upload<MemSpace>("rtmini::bake::ao::cg_tree_starts", starts));
    tree.sums.emplace_back("rtmini::bake::ao::cg_tree_sums", starts.size() - 1);
    lengths = next;
  } while (*std::max_element(lengths.begin(), lengths.end()) > 1);
  return tree;
}

// Per segment: a . b over its rows, returned as the tree's last level.
DView<double> tree_dot(const SumTree& tree, const DView<double>& a, const DView<double>& b) {
  {
    const auto starts = tree.starts[0];
    const auto out = tree.sums[0];
    Kokkos::parallel_for(
        "rtmini::bake::ao::cg_dot", Policy(0, static_cast<std::int64_t>(out.extent(0))),
        KOKKOS_LAMBDA(std::int64_t c) {
          double sum = 0.0;
          for (std::int64_t i = starts(c); i < starts(c + 1); ++i) sum += a(i) * b(i);
          out(c) = sum;
        });
  }
  for (std::size_t level = 1; level < tree.sums.size(); ++level) {
    const auto starts = tree.starts[level];
    const auto in = tree.sums[level - 1];
    const auto out = tree.sums[level];
    Kokkos::parallel_for(
        "rtmini::bake::ao::cg_dot_level", Policy(0, static_cast<std::int64_t>(out.extent(0))),
        KOKKOS_LAMBDA(std::int64_t c) {
          double sum = 0.0;
          for (std::int64_t i = starts(c); i < starts(c + 1); ++i) sum += in(i);
          out(c) = sum;
        });
  }
  return tree.sums.back();
}

enum CgState : int { kActive = 0, kConverged = 1, kFailed = 2 };

// Per receiver: the scalars of its own CG recurrence and where it stands.
struct CgScalars {
  DView<double> rz, rz0, alpha, beta;
  DView<int> state, iterations;
  CgScalars() = default;
  explicit CgScalars(std::size_t n)
      : rz("rtmini::bake::ao::cg_rz", n),
        rz0("rtmini::bake::ao::cg_rz0", n),
        alpha("rtmini::bake::ao::cg_alpha", n),
        beta("rtmini::bake::ao::cg_beta", n),
        state("rtmini::bake::ao::cg_state", n),
        iterations("rtmini::bake::ao::cg_iterations", n) {}
};

// The Jacobi-preconditioned CG of every receiver at once, x0 = 0. Each kernel skips rows of
// receivers that have stopped, so a receiver's iterates are its own.
struct CgSolver {
  DeviceSystems sys;
  DView<int> row_rcv, rcv_sys;
  DView<std::int64_t> rcv_vbase, row_sysrow;  // per global row: its system row
  SumTree tree;
  CgScalars sc;
  DView<double> x, r, z, p, q;
  std::int64_t n = 0;
  int receivers = 0;
};

void cg_start(CgSolver& cg, const DView<double>& rhs) {
  const auto row_sysrow = cg.row_sysrow;
  const auto inv_diag = cg.sys.inv_diag;
  const auto x = cg.x, r = cg.r, z = cg.z, p = cg.p;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_start", Policy(0, cg.n), KOKKOS_LAMBDA(std::int64_t gi) {
        x(gi) = 0.0;
        r(gi) = rhs(gi);
        z(gi) = inv_diag(row_sysrow(gi)) * rhs(gi);
        p(gi) = z(gi);
      });
  const auto rz = tree_dot(cg.tree, r, z);
  const CgScalars sc = cg.sc;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_start_scalars", Policy(0, cg.receivers), KOKKOS_LAMBDA(std::int64_t k) {
        sc.rz(k) = rz(k);
        sc.rz0(k) = rz(k);
        sc.iterations(k) = 0;
        // b = 0 has the solution x = 0; a negative or non-finite start means no SPD system.
        sc.state(k) =
            rz(k) == 0.0 ? kConverged : (rz(k) > 0.0 && math::isfinite(rz(k)) ? kActive : kFailed);
      });
}

// One CG step of every active receiver: q = A p, alpha, x, r, z, beta, p.
void cg_step(CgSolver& cg, double tolerance2, int max_iterations) {
  const auto row_rcv = cg.row_rcv;
  const auto rcv_vbase = cg.rcv_vbase;
  const auto row_sysrow = cg.row_sysrow;
  const auto row_ptr = cg.sys.row_ptr;
  const auto cols = cg.sys.cols;
  const auto vals = cg.sys.vals;
  const auto inv_diag = cg.sys.inv_diag;
  const auto x = cg.x, r = cg.r, z = cg.z, p = cg.p, q = cg.q;
  const CgScalars sc = cg.sc;
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_spmv", Policy(0, cg.n), KOKKOS_LAMBDA(std::int64_t gi) {
        const int k = row_rcv(gi);
        if (sc.state(k) != kActive) return;
        const std::int64_t i = row_sysrow(gi), base = rcv_vbase(k);
        double sum = 0.0;
        for (std::int64_t e = row_ptr(i); e < row_ptr(i + 1); ++e)
          sum += vals(e) * p(base + cols(e));
        q(gi) = sum;
      });
  const auto pq = tree_dot(cg.tree, p, q);
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_alpha", Policy(0, cg.receivers), KOKKOS_LAMBDA(std::int64_t k) {
        if (sc.state(k) != kActive) return;
        if (!(pq(k) > 0.0) || !math::isfinite(pq(k)))
          sc.state(k) = kFailed;  // A not positive definite along p (singular system)
        else
          sc.alpha(k) = sc.rz(k) / pq(k);
      });
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_update", Policy(0, cg.n), KOKKOS_LAMBDA(std::int64_t gi) {
        const int k = row_rcv(gi);
        if (sc.state(k) != kActive) return;
        const double a = sc.alpha(k);
        x(gi) += a * p(gi);
        r(gi) -= a * q(gi);
        z(gi) = inv_diag(row_sysrow(gi)) * r(gi);
      });
  const auto rz = tree_dot(cg.tree, r, z);
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_beta", Policy(0, cg.receivers), KOKKOS_LAMBDA(std::int64_t k) {
        if (sc.state(k) != kActive) return;
        const int it = ++sc.iterations(k);
        if (!math::isfinite(rz(k)) || rz(k) < 0.0)
          sc.state(k) = kFailed;
        else if (rz(k) <= tolerance2 * sc.rz0(k))
          sc.state(k) = kConverged;
        else if (it >= max_iterations)
          sc.state(k) = kFailed;
        else {
          sc.beta(k) = rz(k) / sc.rz(k);
          sc.rz(k) = rz(k);
        }
      });
  Kokkos::parallel_for(
      "rtmini::bake::ao::cg_direction", Policy(0, cg.n), KOKKOS_LAMBDA(std::int64_t gi) {
        const int k = row_rcv(gi);
        if (sc.state(k) != kActive) return;
        p(gi) = z(gi) + sc.beta(k) * p(gi);
      });
}

int count_active(const CgSolver& cg) {
  const auto state = cg.sc.state;
  int active = 0;
  Kokkos::parallel_reduce(
      "rtmini::bake::ao::cg_active", Policy(0, cg.receivers),
      KOKKOS_LAMBDA(std::int64_t k, int& n) { n += state(k) == kActive ? 1 : 0; }, active);
  return active;
}

// Orders of magnitude the residual of the slowest active receiver has fallen since its start:
// 0.5 log10(rz0 / rz), rz the preconditioned squared norm CG tracks. Receivers that stopped
// are done and do not count; with none active the solve is complete.
double residual_digits(const CgSolver& cg, double goal_digits) {
  const CgScalars sc = cg.sc;
  double worst = 0.0;  // the largest rz / rz0 over active receivers
  Kokkos::parallel_reduce(
      "rtmini::bake::ao::cg_worst_residual", Policy(0, cg.receivers),
      KOKKOS_LAMBDA(std::int64_t k, double& w) {
        if (sc.state(k) == kActive && sc.rz0(k) > 0.0) w = math::fmax(w, sc.rz(k) / sc.rz0(k));
      },
      Kokkos::Max<double>(worst));
  if (!(worst > 0.0)) return goal_digits;
  return std::clamp(0.5 * std::log10(1.0 / worst), 0.0, goal_digits);
}

}  // namespace cg_detail

CgFit fit_least_squares_cg(const AoScene& scene, const SampleValues& sv, double weight,
                           const std::vector<std::vector<std::size_t>>& groups,
                           LeastSquaresStats& st, ProgressLine* progress) {
  using namespace cg_detail;
  using Clock = std::chrono::steady_clock;
  const SamplePlan& plan = *sv.plan;
  const std::size_t nr = plan.receivers.size();
  CgFit fit;
  fit.values.assign(static_cast<std::size_t>(plan.total_vertices()), 1.0f);
  fit.failed.assign(nr, 0);
  if (plan.total_vertices() == 0) {
    for (int step = 1; step <= kLeastSquaresSteps; ++step) step_done(progress, step);
    return fit;
  }

  // Data term: one block per plan triangle.
  auto t0 = Clock::now();
  const DView<double> blocks = triangle_blocks(sv);
  st.assemble_s += fenced_seconds_since(t0);
  step_done(progress, 1);

  // Patterns: the triangles of every vertex, then its row.
  t0 = Clock::now();
  const HostLayout h = make_layout(scene, plan, groups);
  CgSolver cg{};
  cg.sys.sys_vbase = compat::upload<MemSpace>("rtmini::bake::ao::cg_sys_vbase", h.sys_vbase);
  cg.sys.sys_tbase = compat::upload<MemSpace>("rtmini::bake::ao::cg_sys_tbase", h.sys_tbase);
  cg.sys.sys_blocks = compat::upload<MemSpace>("rtmini::bake::ao::cg_sys_blocks", h.sys_blocks);
  cg.sys.tris = compat::upload<MemSpace>("rtmini::bake::ao::cg_tris", h.tris);
  cg.sys.tri_sys = compat::upload<MemSpace>("rtmini::bake::ao::cg_tri_sys", h.tri_sys);
  cg.sys.row_sys = compat::upload<MemSpace>("rtmini::bake::ao::cg_row_sys", h.row_sys);
  build_incidence(cg.sys);
  build_pattern(cg.sys);
  st.regularize_s += fenced_seconds_since(t0);
  step_done(progress, 2);

  // Values, preconditioner and right-hand sides.
  t0 = Clock::now();
  assemble_values(cg.sys, blocks, weight);
  cg.n = plan.total_vertices();
  cg.receivers = static_cast<int>(nr);
  cg.row_rcv = compat::upload<MemSpace>("rtmini::bake::ao::cg_row_rcv", h.row_rcv);
  cg.rcv_sys = compat::upload<MemSpace>("rtmini::bake::ao::cg_rcv_sys", h.rcv_sys);
  cg.rcv_vbase = compat::upload<MemSpace>("rtmini::bake::ao::cg_rcv_vbase", plan.vertex_base);
  const auto rcv_tbase = compat::upload<MemSpace>("rtmini::bake::ao::cg_rcv_tbase", plan.tri_base);
  {
    std::vector<std::int64_t> sysrow(static_cast<std::size_t>(cg.n));
    for (std::size_t r = 0; r < nr; ++r)
      for (std::int64_t gi = plan.vertex_base[r]; gi < plan.vertex_base[r + 1]; ++gi)
        sysrow[gi] = h.sys_vbase[h.rcv_sys[r]] + gi - plan.vertex_base[r];
    cg.row_sysrow = compat::upload<MemSpace>("rtmini::bake::ao::cg_row_sysrow", sysrow);
  }
  const DView<double> rhs =
      assemble_rhs(cg.sys, blocks, cg.row_rcv, cg.rcv_sys, cg.rcv_vbase, rcv_tbase);
  st.assemble_s += fenced_seconds_since(t0);
  step_done(progress, 3);

  // The solves.
  t0 = Clock::now();
  std::vector<std::int64_t> lengths(nr);
  for (std::size_t r = 0; r < nr; ++r) lengths[r] = plan.vertex_base[r + 1] - plan.vertex_base[r];
  cg.tree = make_sum_tree(lengths);
  cg.sc = CgScalars(nr);
  cg.x = DView<double>("rtmini::bake::ao::cg_x", cg.n);
  cg.r = DView<double>("rtmini::bake::ao::cg_r", cg.n);
  cg.z = DView<double>("rtmini::bake::ao::cg_z", cg.n);
  cg.p = DView<double>("rtmini::bake::ao::cg_p", cg.n);
  cg.q = DView<double>("rtmini::bake::ao::cg_q", cg.n);
  cg_start(cg, rhs);
  // Checking for the end costs a device round trip: only every few steps (stopped receivers
  // do not move, so this changes no value).
  constexpr int kCheckEvery = 8;
  // The solve's own progress line, in orders of magnitude of residual reduction: CG converges
  // about linearly in log(residual), so the digits gained so far measure the work done and the
  // ETA is the digits still to gain at the rate so far (the slowest receiver's; the others stop
  // earlier). Steps 1-3 above are single loops; this is the only part with many iterations.
  const double goal_digits = -0.5 * std::log10(kCgRelativeResidual2);
  ProgressLine solve_line("bake ao solve", "digits", progress && progress->enabled());
  for (int it = 0; it < kCgMaxIterations; it += kCheckEvery) {
    if (count_active(cg) == 0) break;
    if (solve_line.due()) {
      const double digits = residual_digits(cg, goal_digits);
      solve_line.update(digits, goal_digits);
    }
    for (int k = 0; k < kCheckEvery; ++k) cg_step(cg, kCgRelativeResidual2, kCgMaxIterations);
  }
  solve_line.finish(goal_digits, goal_digits);
  std::vector<double> x;
  std::vector<int> state, iterations;
  compat::download(cg.x, x);
  compat::download(cg.sc.state, state);
  compat::download(cg.sc.iterations, iterations);
  st.solve_s += seconds_since(t0);
  step_done(progress, 4);
  for (std::size_t r = 0; r < nr; ++r) {
    st.cg_iterations = std::max(st.cg_iterations, iterations[r]);
    if (state[r] != kConverged) {
      fit.failed[r] = 1;
      continue;
    }
    for (std::int64_t gi = plan.vertex_base[r]; gi < plan.vertex_base[r + 1]; ++gi)
      fit.values[gi] = static_cast<float>(x[gi]);
  }
  return fit;
}

}  // namespace rtmini::ao
