#pragma once
// Every option of `bake --mode ao`: the OptiX Prime baking sample's options with
// its meanings and defaults (seed: optix-prime-ao-baking), plus the run contract.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace rtmini::ao {

struct AoOptions {
  std::string input;         // .obj / .bs (flattened) or .toml (instances, blockers)
  std::string output;        // by extension: .bin .ply .obj .glb; empty = none
  int instances = 1;         // copies of every mesh (the sample's -i, for testing)
  int rays = 64;             // AO rays per sample point
  std::int64_t samples = 0;  // total sample points; 0 = min_samples_per_face per face
  int min_samples_per_face = 3;
  // Extra ray origin offset = max scene extent * this, on top of offset_ray_origin's error bound.
  // 0 by default: the error bound alone keeps rays off their own triangle at any scale, and any
  // extra offset lifts the origin toward nearby occluders (the sample's 0.01 read a coaxial disk
  // at height 0.5 of radius 1 6 % too open).
  double ray_distance_scale = 0.0;
  double hit_distance_scale = 10.0;  // max hit distance = max scene extent * this
  bool ground_plane = true;
  int ground_axis = 1;  // 0..5 = +x +y +z -x -y -z
  double ground_scale = 100.0;
  double ground_offset = 0.03;
  bool least_squares = true;
  double regularization = 0.1;
  std::string fit = "auto";      // least-squares solve: auto | cholesky (host) | cg (device)
  int passes = 1;                // kernel launches per batch; rays are split among them
  std::int64_t batch = 2000000;  // sample points resident on the device at once
  std::uint64_t seed = 1;
  std::string bvh = "auto";  // auto | lbvh | ploc | sah
  bool ply_ascii = false;
  std::string summary;  // --summary FILE.json (the shared option group)
  std::string timings;  // --timings FILE.h5 (the shared option group)
  bool progress = false;
  std::int64_t max_memory = 0;  // --max-memory (report/memory_check.hpp)
};

// The `bake ao` command line, registered on `bake`'s `ao` subcommand or on rtmini-ao's app.
class AoCli {
 public:
  // Registers every AO option on `app`; values land in `out` (and in this object).
  void add_to(CLI::App& app, AoOptions& out);
  // After a successful parse: the options that need more than CLI11's checks. InputError.
  void finish(AoOptions& out) const;

 private:
  std::vector<double> ground_;
  bool no_ground_ = false, no_lsq_ = false;
  std::string mode_ = "ao";
};

}  // namespace rtmini::ao
