#include "ao_options.hpp"

#include <CLI/CLI.hpp>
#include <vector>

#include "rtmini/io/error.hpp"

namespace rtmini::ao {

void AoCli::add_to(CLI::App& app, AoOptions& o) {
  app.add_option("input,-f,--file", o.input,
                 "mesh (.obj, .bs: flattened), glTF (.gltf, .glb: node instances) or scene "
                 "(.toml: instances, blockers)")
      ->required();
  app.add_option("-o,--outfile,--output", o.output,
                 "per-vertex AO: .bin (sample layout), .ply, .obj, .glb");
  app.add_option("--mode", mode_, "must be ao (the old spelling of `bake ao`)")
      ->check(CLI::IsMember({"ao"}));
  app.add_option("-i,--instances", o.instances,
                 "copies of every mesh (procedural transforms, for testing)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("-r,--rays", o.rays, "rays per sample point")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("-s,--samples", o.samples,
                 "total sample points (0: samples_per_face per face; extra by area)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("-t,--samples_per_face,--samples-per-face", o.min_samples_per_face,
                 "minimum sample points per face")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("-d,--ray_distance_scale,--ray-distance-scale", o.ray_distance_scale,
                 "ray origin offset = max scene extent * s")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("-m,--hit_distance_scale,--hit-distance-scale", o.hit_distance_scale,
                 "max hit distance = max scene extent * s")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("-g,--ground_setup,--ground-setup", ground_,
                 "ground plane: axis (0..5 = +x +y +z -x -y -z) scale offset [1 100 0.03]")
      ->expected(3);
  app.add_flag("--no_ground_plane,--no-ground-plane", no_ground_,
               "disable the virtual ground plane");
  app.add_option("-w,--regularization_weight,--regularization", o.regularization,
                 "least-squares regularization weight")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--fit", o.fit,
                 "least-squares solve: cholesky (host sparse Cholesky), cg (preconditioned CG on "
                 "the device), or auto (cg on a GPU, cholesky on the host)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "cholesky", "cg"}));
  app.add_flag("--no_least_squares,--no-least-squares", no_lsq_,
               "area/barycentric weighted average instead");
  app.add_option("--passes", o.passes, "kernel launches per batch (rays are split among them)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--batch", o.batch, "sample points per batch on the device")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "random seed")->capture_default_str();
  app.add_option("--bvh", o.bvh,
                 "BVH build: lbvh, ploc, sah, or auto (the least measured build plus trace time "
                 "for the run's rays)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "lbvh", "ploc", "sah"}));
  app.add_flag("--ply-ascii", o.ply_ascii, "ASCII PLY instead of binary little endian");
  app.add_flag("--no_viewer,--no-viewer", "accepted for compatibility (there is no viewer)");
}

void AoCli::finish(AoOptions& o) const {
  const std::vector<double>& ground = ground_;
  o.ground_plane = !no_ground_;
  o.least_squares = !no_lsq_;
  if (!ground.empty()) {
    const double axis = ground[0];
    // Range first: converting 1e300 (or NaN) to int is undefined (found by fuzz_ao_options).
    if (!(axis >= 0 && axis <= 5) || axis != static_cast<int>(axis))
      throw InputError("bad usage: --ground_setup axis must be an integer 0..5");
    if (!(ground[1] > 0) || !(ground[2] >= 0))
      throw InputError("bad usage: --ground_setup needs scale > 0 and offset >= 0");
    o.ground_axis = static_cast<int>(axis);
    o.ground_scale = ground[1];
    o.ground_offset = ground[2];
  }
  if (o.rays > 65535) throw InputError("bad usage: --rays must be at most 65535");
  if (o.passes > o.rays) throw InputError("bad usage: --passes must not exceed --rays");
}

}  // namespace rtmini::ao
