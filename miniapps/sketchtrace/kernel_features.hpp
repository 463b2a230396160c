#pragma once
// The scene features a render kernel instantiation compiles in (renderer.cpp picks the
// instantiation once per render, on the host). A feature compiled out costs nothing per ray:
// no branch, no registers, no code; a feature compiled in is still checked at run time, so
// an instantiation with more features renders the same image, only slower.
namespace rtmini::sketch {

enum FeatureBits : unsigned {
  // The shape of a path: continuation rays, light sampling, lens/time samples, image maps
  // (surface_detail.hpp, looked up at ray-cone LODs), moving objects (motion_trace.hpp; every
  // path then sees one instant, the camera sample's time).
  kSecondary = 1u,
  kLights = 2u,
  kCameraSampling = 4u,
  kTextures = 8u,
  kMotion = 16u,
  // What light sampling needs (light_sampling.hpp): light sampled through glossy Phong lobes
  // and the MIS weights of the emission glossy continuations find (some material is glossy),
  // shaft culling (at least kShaftMinSamples shadow rays per light), emissive meshes, point
  // lights. Quad lights are always compiled in.
  kGlossy = 32u,
  kShafts = 64u,
  kMeshLights = 128u,
  kPointLights = 256u
};

// The shape bits: a render runs an instantiation with exactly its scene's shape.
inline constexpr unsigned kShapeFeatures =
    kSecondary | kLights | kCameraSampling | kTextures | kMotion;
// Every light-sampling path: the instantiations a scene of any lights can run.
inline constexpr unsigned kEveryLightPath = kGlossy | kShafts | kMeshLights | kPointLights;

}  // namespace rtmini::sketch
