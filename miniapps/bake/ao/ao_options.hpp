#pragma once
// Every option of `bake --mode ao`: the OptiX Prime baking sample's options with
// its meanings and defaults (seed: optix-prime-ao-baking), plus the run contract.
#include <cstdint>
#include <string>

namespace rtmini::ao {

struct AoOptions {
  std::string input;         // .obj / .bs (flattened) or .toml (instances, blockers)
  std::string output;        // by extension: .bin .ply .obj .glb; empty = none
  int instances = 1;         // copies of every mesh (the sample's -i, for testing)
  int rays = 64;             // AO rays per sample point
  std::int64_t samples = 0;  // total sample points; 0 = min_samples_per_face per face
  int min_samples_per_face = 3;
  double ray_distance_scale = 0.01;  // ray origin offset = max scene extent * this
  double hit_distance_scale = 10.0;  // max hit distance = max scene extent * this
  bool ground_plane = true;
  int ground_axis = 1;  // 0..5 = +x +y +z -x -y -z
  double ground_scale = 100.0;
  double ground_offset = 0.03;
  bool least_squares = true;
  double regularization = 0.1;
  int passes = 1;                // kernel launches per batch; rays are split among them
  std::int64_t batch = 2000000;  // sample points resident on the device at once
  std::uint64_t seed = 1;
  std::string bvh = "auto";  // auto | lbvh | sah
  bool ply_ascii = false;
  std::string summary;  // --summary FILE.json
};

// Parses the full command line (argv[0] = program, `--mode ao` accepted anywhere).
// Returns false when --help or --version was printed (exit 0). InputError on bad usage.
bool parse_ao_options(int argc, char** argv, AoOptions& out);

}  // namespace rtmini::ao
