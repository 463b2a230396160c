#pragma once
// Tests are written once against TestExecSpace and compiled once per enabled
// Kokkos backend (the build defines RTMINI_TEST_EXECSPACE).
#include "rtmini/kokkos_compat.hpp"

#ifndef RTMINI_TEST_EXECSPACE
#define RTMINI_TEST_EXECSPACE Kokkos::DefaultExecutionSpace
#endif

namespace rtmini::test {
using TestExecSpace = RTMINI_TEST_EXECSPACE;
using TestMemSpace = TestExecSpace::memory_space;
// Directory of the public test meshes (inputs/meshes, bundled with their provenance).
const char* scenes_dir();
}  // namespace rtmini::test
