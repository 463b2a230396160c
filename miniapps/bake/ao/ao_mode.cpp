#include "ao_mode.hpp"

#include <cmath>
#include <cstdio>

#include "ao_options.hpp"
#include "ao_output.hpp"
#include "ao_trace.hpp"
#include "device_scene.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "rtmini/scene/recentre.hpp"
#include "vertex_mapping.hpp"

namespace rtmini {
namespace {

// The build --bvh names once auto is resolved (CLI checked the name).
bvh::BuildQuality build_quality_named(const std::string& name) {
  bvh::BuildQuality q = bvh::BuildQuality::kSah;
  bvh::parse_build_quality(name, q);
  return q;
}

// Order-independent hash of the per-vertex values quantised to 2^-16.
std::uint64_t ao_hash(const std::vector<float>& values) {
  std::uint64_t h = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const auto q =
        static_cast<std::int64_t>(std::llround(static_cast<double>(values[i]) * 65536.0));
    h += hash_term(i, static_cast<std::uint64_t>(q));
  }
  return h;
}

// The per-sample-point mean visibility (the AO value another tracer can be compared with) and
// its Monte-Carlo standard error: each point's k of R rays are binomial, so the mean of n points
// has variance sum p_i (1 - p_i) / (R n^2), estimated with p_i = 1 - k_i / R.
struct SampleMean {
  double mean = 0, std_error = 0;
};
SampleMean mean_visibility(const std::vector<std::uint16_t>& occluded, int rays) {
  SampleMean m;
  if (occluded.empty()) return m;
  double sum = 0, var = 0;
  for (const std::uint16_t k : occluded) {
    const double p = 1.0 - static_cast<double>(k) / rays;
    sum += p;
    var += p * (1.0 - p) / rays;
  }
  const double n = static_cast<double>(occluded.size());
  m.mean = sum / n;
  m.std_error = std::sqrt(var) / n;
  return m;
}

nlohmann::json parameters_json(const ao::AoOptions& o) {
  return {{"mode", "ao"},
          {"input", o.input},
          {"output", o.output},
          {"instances", o.instances},
          {"rays", o.rays},
          {"samples", o.samples},
          {"samples_per_face", o.min_samples_per_face},
          {"ray_distance_scale", o.ray_distance_scale},
          {"hit_distance_scale", o.hit_distance_scale},
          {"ground_plane", o.ground_plane},
          {"ground_axis", o.ground_axis},
          {"ground_scale", o.ground_scale},
          {"ground_offset", o.ground_offset},
          {"least_squares", o.least_squares},
          {"regularization_weight", o.regularization},
          {"fit", o.fit},
          {"passes", o.passes},
          {"batch", o.batch},
          {"seed", o.seed},
          {"bvh", o.bvh}};
}

// What the AO bake allocates after the scene is read (report/memory_check.hpp): one BVH per
// stored mesh and the sample plan on the device, a batch of rays in flight, this rank's
// occlusion counts; rank 0 also gathers every sample and maps them onto the vertices.
MemoryNeed ao_memory_need(const ao::SamplePlan& plan, std::int64_t stored_tris, std::int64_t batch,
                          std::int64_t total, const Communicator& comm) {
  const double samples = static_cast<double>(total);
  const double share = samples / comm.size() + 1;
  MemoryNeed need;
  need.views = device_mesh_bytes(static_cast<std::size_t>(stored_tris), 0) +
               static_cast<double>(plan.total_triangles()) * 52.0 +
               static_cast<double>(std::min(batch, total)) * (24.0 + 2.0) + share * 2.0;
  need.host = share * 2.0;
  if (comm.is_root()) need.host += samples * (2.0 + 8.0);
  return need;
}

}  // namespace

int run_ao_mode(Communicator& comm, ao::AoOptions o) {
  // auto: the device solves by CG where the host would factor (and copy both ways).
  const ao::FitMethod fit = ao::parse_fit_method(o.fit);
  o.fit = ao::fit_method_name(fit);
  ao::output_format(o.output);  // reject a bad extension before any work
  check_output_places({{o.output, 0}, {o.summary, 0}, {o.timings, 0}});
  const bool root = comm.is_root();
  RunReport report;
  report.app = "bake";
  report.parameters = parameters_json(o);

  report.timer.start("load");
  ao::AoScene world = ao::load_ao_scene(o.input);
  ao::replicate_instances(world, o.instances, o.ground_axis % 3);
  // Traced in a frame centred on the scene (outputs use `world`), refused where the precision
  // cannot hold it (geometry/offset.hpp).
  const ao::Bounds world_bounds = world.scene_bounds();
  Bounds3d placed;
  if (!world_bounds.empty()) {
    placed.add(world_bounds.lo);
    placed.add(world_bounds.hi);
  }
  check_representable(placed, placed.centre(), o.input);
  const ao::AoScene scene = ao::recentred(world, placed.centre());
  const ao::Bounds bounds = scene.receiver_bounds();
  // The scene scale of the AO seed: the maximum extent of the whole scene, blockers included
  // (a small receiver under a large blocker must reach it).
  const ao::Bounds all = scene.scene_bounds();
  const double extent = all.max_extent();
  report.timer.stop();
  const ao::GroundPlane ground = o.ground_plane
                                     ? ao::make_ground_plane(bounds.lo, bounds.hi, o.ground_axis,
                                                             o.ground_scale, o.ground_offset)
                                     : ao::GroundPlane{};

  report.timer.start("sample_plan");
  const ao::SamplePlan plan = ao::plan_samples(scene, o.samples, o.min_samples_per_face);
  report.timer.stop();
  const std::int64_t total = plan.total_samples();
  std::int64_t scene_tris = 0;
  for (const auto& inst : scene.instances)
    scene_tris += static_cast<std::int64_t>(scene.meshes[inst.mesh].tris.size());
  std::int64_t stored_tris = 0;
  for (const auto& m : scene.meshes) stored_tris += static_cast<std::int64_t>(m.tris.size());
  // auto: the least measured build plus trace time for these rays (build_quality.hpp): on the
  // device the LBVH's few milliseconds beat the host SAH build; on the host the SAH tree pays
  // from about 75 rays per triangle.
  if (o.bvh == "auto") {
    o.bvh = bvh::to_string(bvh::choose_build_quality(
        double(scene_tris), double(total) * o.rays,
        !Kokkos::SpaceAccessibility<Kokkos::HostSpace, ao::MemSpace>::accessible));
    report.parameters["bvh"] = o.bvh;
  }

  const MemoryPeak peak =
      require_memory(comm, ao_memory_need(plan, stored_tris, o.batch, total, comm), o.max_memory);
  const double peak_estimate = comm.max(peak.host + peak.device);
  if (root) {
    std::printf("%s\n", build_banner().c_str());
    std::printf("bake --mode ao: %s\n", o.input.c_str());
    std::printf(
        "  meshes %zu (stored triangles %lld), instances %zu (receivers %zu), instanced triangles "
        "%lld\n",
        scene.meshes.size(), static_cast<long long>(stored_tris), scene.instances.size(),
        plan.receivers.size(), static_cast<long long>(scene_tris));
    std::printf("  receiver vertices %lld, triangles %lld, scene scale (max extent) %.6g\n",
                static_cast<long long>(plan.total_vertices()),
                static_cast<long long>(plan.total_triangles()), extent);
    std::printf(
        "  samples %lld (min %d per face, requested %lld), rays per sample %d, total rays %lld\n",
        static_cast<long long>(total), o.min_samples_per_face, static_cast<long long>(o.samples),
        o.rays, static_cast<long long>(total) * o.rays);
    std::printf("  ray offset %.6g (scale %g), max hit distance %.6g (scale %g)\n",
                o.ray_distance_scale * extent, o.ray_distance_scale, o.hit_distance_scale * extent,
                o.hit_distance_scale);
    if (o.ground_plane)
      std::printf("  ground plane: axis %d scale %g offset %g (level %.6g)\n", o.ground_axis,
                  o.ground_scale, o.ground_offset, static_cast<double>(ground.level));
    else
      std::printf("  ground plane: off\n");
    std::printf(
        "  mapping: %s (regularization weight %g, fit %s), passes %d, batch %lld, seed %llu, "
        "bvh %s\n",
        o.least_squares ? "least squares" : "weighted average", o.regularization, o.fit.c_str(),
        o.passes, static_cast<long long>(o.batch), static_cast<unsigned long long>(o.seed),
        o.bvh.c_str());
    std::printf("  ranks %d, threads per rank %d, output %s\n", comm.size(), compat::concurrency(),
                o.output.empty() ? "(none)" : o.output.c_str());
    std::printf("  memory estimate (rank 0): %.1f MiB peak resident host, %.1f MiB device\n",
                peak.host / 1048576.0, peak.device / 1048576.0);
    std::fflush(stdout);
  }

  report.timer.start("build");
  const double build_start = report.timer.now();
  const ao::DeviceScene device(scene, build_quality_named(o.bvh), ground);
  const double bvh_built = report.timer.now();
  const ao::DeviceSamplePlan dplan = ao::upload_plan(device.meshes(), scene, plan);
  report.timer.stop();
  const double plan_upload_s = report.timer.now() - bvh_built;
  const double mesh_bvh_s = bvh_built - build_start;

  ao::TraceSettings ts;
  ts.rays = o.rays;
  ts.passes = o.passes;
  ts.batch = o.batch;
  ts.seed = o.seed;
  ts.offset = static_cast<Real>(o.ray_distance_scale * extent);
  ts.max_distance = static_cast<Real>(o.hit_distance_scale * extent);
  ts.coordinate_bound =
      static_cast<Real>(std::max(max_component(vabs(all.lo)), max_component(vabs(all.hi))));
  // Contiguous sample ranges per rank; the counts are integers, so the gathered
  // array (and everything after it) is identical for any rank count.
  const std::int64_t first = total * comm.rank() / comm.size();
  const std::int64_t last = total * (comm.rank() + 1) / comm.size();
  // Rank 0 shows its own share: ranks hold equal sample counts, so it speaks for all.
  ProgressLine trace_line("bake ao rays", "rays", o.progress && root);
  const std::vector<std::uint16_t> mine =
      ao::trace_samples(device.query(), dplan, ts, first, last, report.timer, &trace_line);

  report.timer.start("gather");
  const std::vector<std::uint16_t> occluded = comm.gatherv(mine, 0);
  report.timer.stop();
  const SampleMean mean_ao = root ? mean_visibility(occluded, o.rays) : SampleMean{};

  ao::AoResult result;
  result.scene = &world;
  result.plan = &plan;
  ao::LeastSquaresStats lsq;
  // Rank 0 maps, solves and writes; the others time the same (empty) phases so
  // every rank reduces the same phase list in RunReport::finish.
  ao::SampleValues values;
  // Steps, not an ETA: the mapping and the Cholesky fit's steps are single loops or library
  // calls that cannot report partial work. The CG fit's iterations draw their own line with an
  // ETA (ao::fit_least_squares_cg).
  const int mapping_steps = o.least_squares ? ao::kLeastSquaresSteps : 1;
  ProgressLine mapping_line("bake ao mapping", "steps", o.progress && root);
  mapping_line.update(0, mapping_steps, 0, mapping_steps);
  report.timer.start("mapping");
  if (root) {
    values = ao::make_sample_values(plan, o.seed, occluded, o.rays);
    if (!o.least_squares) result.values = ao::map_weighted_average(scene, values);
  }
  report.timer.stop();
  if (o.least_squares) {
    report.timer.start("solve");
    if (root)
      result.values =
          ao::map_least_squares(scene, values, o.regularization, &lsq, true, &mapping_line, fit);
    report.timer.stop();
  }
  mapping_line.finish(mapping_steps, mapping_steps);
  report.timer.start("write");
  if (root && !o.output.empty()) ao::write_ao_output(o.output, result, o.ply_ascii);
  report.timer.stop();

  // The sample's timing report, max over ranks.
  const char* names[] = {"load",   "sample_plan", "build", "samples", "rays",
                         "gather", "mapping",     "solve", "write"};
  double t[9];
  for (int i = 0; i < 9; ++i) t[i] = comm.max(report.timer.total(names[i]));
  const double total_rays = static_cast<double>(total) * o.rays;
  const double run_time = comm.max(report.timer.now());
  if (root) {
    std::printf("Load scene ...               %10.2f ms\n", 1e3 * t[0]);
    std::printf("Plan sample points ...       %10.2f ms\n", 1e3 * t[1]);
    std::printf("Build BVHs ...               %10.2f ms\n", 1e3 * t[2]);
    std::printf("    mesh BVHs ...                     %10.2f ms\n", 1e3 * mesh_bvh_s);
    std::printf("    upload receivers and plan ...     %10.2f ms\n", 1e3 * plan_upload_s);
    std::printf("Generate sample points ...   %10.2f ms\n", 1e3 * t[3]);
    std::printf("Compute AO (rays) ...        %10.2f ms  (%.4g Mrays/s)\n", 1e3 * t[4],
                t[4] > 0 ? total_rays / t[4] * 1e-6 : 0.0);
    std::printf("Gather to rank 0 ...         %10.2f ms\n", 1e3 * t[5]);
    std::printf("Map AO to vertices ...       %10.2f ms\n", 1e3 * (t[6] + t[7]));
    if (o.least_squares) {
      std::printf("    build mass matrices ...           %10.2f ms\n", 1e3 * lsq.assemble_s);
      std::printf("    build regularization matrices ... %10.2f ms\n", 1e3 * lsq.regularize_s);
      if (fit == ao::FitMethod::kCg) {
        std::printf(
            "    decompose matrices ...            %10.2f ms  (none: CG on %d matrix(es), %zu "
            "instances)\n",
            1e3 * lsq.factor_s, lsq.systems, plan.receivers.size());
        std::printf(
            "    solve linear systems ...          %10.2f ms  (CG, at most %d iterations)\n",
            1e3 * lsq.solve_s, lsq.cg_iterations);
      } else {
        std::printf(
            "    decompose matrices ...            %10.2f ms  (%d factorization(s), %zu "
            "instances)\n",
            1e3 * lsq.factor_s, lsq.factorizations, plan.receivers.size());
        std::printf("    solve linear systems ...          %10.2f ms\n", 1e3 * lsq.solve_s);
      }
      if (lsq.fallbacks > 0)
        std::printf("    %d singular system(s): weighted average used there\n", lsq.fallbacks);
    }
    std::printf("Write output ...             %10.2f ms\n", 1e3 * t[8]);
    std::printf("Mean AO over %lld sample points: %.6f +- %.6f (Monte-Carlo standard error)\n",
                static_cast<long long>(total), mean_ao.mean, mean_ao.std_error);
    std::printf("Whole bake (wall) ...        %10.2f ms\n", 1e3 * run_time);
    std::fflush(stdout);
  }

  report.scene = {{"input", o.input},
                  {"meshes", scene.meshes.size()},
                  {"instances", scene.instances.size()},
                  {"receivers", plan.receivers.size()},
                  {"stored_triangles", stored_tris},
                  {"instanced_triangles", scene_tris},
                  {"receiver_vertices", plan.total_vertices()},
                  {"samples", total},
                  {"rays", static_cast<std::int64_t>(total) * o.rays},
                  {"scene_scale", extent},
                  {"mean_ao", mean_ao.mean},
                  {"mean_ao_std_error", mean_ao.std_error}};
  if (o.least_squares)
    report.scene["least_squares"] = {{"fit", o.fit},
                                     {"assemble_s", lsq.assemble_s},
                                     {"regularize_s", lsq.regularize_s},
                                     {"factor_s", lsq.factor_s},
                                     {"solve_s", lsq.solve_s},
                                     {"matrices", lsq.systems},
                                     {"factorizations", lsq.factorizations},
                                     {"cg_iterations", lsq.cg_iterations},
                                     {"fallbacks", lsq.fallbacks}};
  report.scene["memory_estimate_bytes"] = peak_estimate;
  report.fom_name = "ao_rays_per_second";
  report.fom_unit = "rays/s";
  report.fom_value = t[4] > 0 ? total_rays / t[4] : 0.0;
  report.verification_hash = root ? ao_hash(result.values) : 0;
  // Phases only: the program has no dispatch loop of its own to record.
  if (!o.timings.empty())
    write_rank_timings(o.timings, comm, report.timer, RankTimings{},
                       {"bake", "", o.input, report.parameters.dump(), {}});
  report.finish(comm, o.summary);
  return kExitOk;
}

}  // namespace rtmini
