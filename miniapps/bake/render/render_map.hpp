#pragma once
// The offline renderer of baked maps (`bake render`, issue 9): one camera ray per pixel sample,
// the closest hit on the baked mesh, and the colour the baker's MapReader reads there along
// the camera ray -- exactly what a mirror ray of the next bake iteration would see.
#include <cstdint>

#include "bake_config.hpp"
#include "baked_map.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/report/progress.hpp"
#include "rtmini/scene/camera.hpp"

namespace rtmini::bake {

struct RenderParams {
  int width = 640, height = 480;
  int spp = 1;  // 1: the pixel centre; more: stratified jittered samples, box-filtered
  Vec3f background{0.f, 0.f, 0.f};
  std::uint64_t seed = 1;
  Lookup lookup = Lookup::kGrid;
};

struct RenderResult {
  Image image;                     // linear RGB, top row first
  std::int64_t rays = 0;           // camera rays traced
  std::int64_t hits = 0;           // of which hit the mesh
  std::uint64_t verification = 0;  // order-independent hash of the pixel bits
};

// `progress` (may be null): pixels done; the caller finishes it.
RenderResult render_baked_map(const BakedMapDevice& map, const DeviceCamera& camera,
                              const RenderParams& params, ProgressLine* progress = nullptr);

}  // namespace rtmini::bake
