// The host thread count rtmini asks Kokkos for (report/common_options.hpp): Kokkos' OpenMP
// backend writes past a fixed array of 512 per-thread records beyond that, so explicit requests
// above the limit are bad input and the node's own count is capped.
#include <gtest/gtest.h>

#include <string>

#include "rtmini/io/error.hpp"
#include "rtmini/report/common_options.hpp"

namespace rtmini {
namespace {

constexpr int kLimit = 512;

int request(int option, const char* kokkos, const char* omp, int available, bool* capped) {
  return host_thread_request(option, kokkos, omp, available, kLimit, capped);
}

TEST(HostThreadRequest, WithinTheLimitEveryRequestPassesThrough) {
  bool capped = true;
  EXPECT_EQ(request(8, nullptr, "600", 2, &capped), 8);  // --threads wins over the environment
  EXPECT_FALSE(capped);
  EXPECT_EQ(request(0, "16", nullptr, 2000, &capped), 0);  // Kokkos reads its own variable
  EXPECT_EQ(request(0, nullptr, "512,4", 2000, &capped), 0);
  EXPECT_EQ(request(0, nullptr, nullptr, 512, &capped), 0);
  EXPECT_FALSE(capped);
}

TEST(HostThreadRequest, AnExplicitRequestAboveTheLimitIsBadInput) {
  bool capped = false;
  EXPECT_THROW(request(513, nullptr, nullptr, 2, &capped), InputError);
  EXPECT_THROW(request(0, "1024", nullptr, 2, &capped), InputError);
  EXPECT_THROW(request(0, nullptr, "600", 2, &capped), InputError);
  try {
    request(0, nullptr, "600,2", 2, &capped);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("OMP_NUM_THREADS=600,2"), std::string::npos) << e.what();
  }
}

TEST(HostThreadRequest, TheNodesOwnCountIsCappedAtTheLimit) {
  bool capped = false;
  EXPECT_EQ(request(0, nullptr, nullptr, 768, &capped), kLimit);
  EXPECT_TRUE(capped);
  EXPECT_EQ(request(0, nullptr, "0", 768, &capped), kLimit);  // "0" requests nothing
  EXPECT_TRUE(capped);
}

}  // namespace
}  // namespace rtmini
