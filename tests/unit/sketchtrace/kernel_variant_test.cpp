// The render kernel instantiation picked for a scene's features (renderer.cpp): always one of
// the scene's shape that compiles in every light path the scene needs, a lean one where it
// exists.
#include <gtest/gtest.h>

#include "renderer.hpp"

namespace rtmini::sketch::test {
namespace {

// Every shape Renderer can ask for: textures force secondary rays and lights, moving objects
// the general shape with motion.
constexpr unsigned kShapes[] = {0u,
                                1u,
                                2u,
                                3u,
                                4u,
                                5u,
                                6u,
                                7u,
                                kTextures | kSecondary | kLights,
                                kTextures | kSecondary | kLights | kCameraSampling,
                                kSecondary | kLights | kCameraSampling | kMotion,
                                kSecondary | kLights | kCameraSampling | kMotion | kTextures};

TEST(KernelVariant, SameShapeAndEveryLightPathNeeded) {
  for (unsigned shape : kShapes) {
    for (unsigned paths = 0; paths <= kEveryLightPath; paths += kGlossy) {
      unsigned wanted = shape;
      if (shape & kLights) wanted |= paths;
      if (!(shape & kSecondary)) wanted &= ~kGlossy;
      const unsigned v = kernel_variant(wanted);
      EXPECT_EQ(v & kShapeFeatures, shape) << feature_names(wanted);
      EXPECT_EQ(v & wanted, wanted) << feature_names(wanted) << " ran " << feature_names(v);
    }
  }
}

TEST(KernelVariant, LeanWhereCompiled) {
  // The bundled scenes' cases (one quad light each).
  for (unsigned lean :
       {unsigned(kLights), kSecondary | kLights | kShafts, kSecondary | kLights | kGlossy,
        kSecondary | kLights | kCameraSampling | kGlossy})
    EXPECT_EQ(kernel_variant(lean), lean) << feature_names(lean);
  // A light path no lean instantiation holds: the general one of the shape.
  EXPECT_EQ(kernel_variant(kSecondary | kLights | kMeshLights),
            kSecondary | kLights | kEveryLightPath);
  EXPECT_EQ(kernel_variant(kLights | kPointLights), kLights | kEveryLightPath);
  // No lights: nothing about light paths compiled in.
  EXPECT_EQ(kernel_variant(kSecondary), kSecondary);
}

}  // namespace
}  // namespace rtmini::sketch::test
