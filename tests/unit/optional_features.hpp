#pragma once
// Tests that need an optional library start with RTMINI_REQUIRE_<LIB>(): in a build without the
// library they are reported as skipped, with the reason, instead of being compiled out or failing.
#include <gtest/gtest.h>

#ifdef RTMINI_HAVE_PNG
#define RTMINI_REQUIRE_PNG() static_cast<void>(0)
#else
#define RTMINI_REQUIRE_PNG() \
  GTEST_SKIP() << "built without PNG support (RTMINI_ENABLE_PNG=OFF or libpng not found)"
#endif

#ifdef RTMINI_HAVE_EXR
#define RTMINI_REQUIRE_EXR() static_cast<void>(0)
#else
#define RTMINI_REQUIRE_EXR() \
  GTEST_SKIP() << "built without OpenEXR (RTMINI_ENABLE_EXR=OFF or OpenEXR not found)"
#endif

#ifdef RTMINI_HAVE_HDF5
#define RTMINI_REQUIRE_HDF5() static_cast<void>(0)
#else
#define RTMINI_REQUIRE_HDF5() \
  GTEST_SKIP() << "built without HDF5 (RTMINI_ENABLE_HDF5=OFF or HDF5 not found)"
#endif

#ifdef RTMINI_HAVE_GLTF
#define RTMINI_REQUIRE_GLTF() static_cast<void>(0)
#else
#define RTMINI_REQUIRE_GLTF()                                                                  \
  GTEST_SKIP() << "built without glTF support (RTMINI_ENABLE_GLTF=OFF or libtinygltf-dev not " \
                  "found)"
#endif
