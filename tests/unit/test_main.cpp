// GoogleTest main shared by the unit executables: Kokkos is initialised once,
// and invalid floating-point operations trap so a NaN fails loudly.
#include <fenv.h>
#include <gtest/gtest.h>

#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/common_options.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  rtmini::Environment env(argc, argv);
  rtmini::start_kokkos(rtmini::CommonOptions{});
#if defined(__GLIBC__) && !defined(RTMINI_NO_FPE_TRAP)
  feenableexcept(FE_INVALID);
#endif
  return RUN_ALL_TESTS();
}
