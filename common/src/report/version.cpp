#include "rtmini/report/version.hpp"

#include <sstream>

#include "rtmini/config.hpp"
#include "rtmini/kokkos_compat.hpp"
#ifdef RTMINI_HAVE_MPI
#include <mpi.h>
#endif

namespace rtmini {

namespace {
// The widest x86 SIMD level this translation unit was compiled for (RTMINI_HOST_ARCH).
const char* host_simd() {
#if defined(__AVX512F__)
  return "avx512";
#elif defined(__AVX2__)
  return "avx2";
#elif defined(__AVX__)
  return "avx";
#elif defined(__SSE4_2__)
  return "sse4.2";
#elif defined(__x86_64__)
  return "sse2";
#else
  return "default";
#endif
}
}  // namespace

std::string build_banner() {
  std::ostringstream os;
  os << "rtmini " << version_string() << " (git " << git_hash() << ") Kokkos "
     << KOKKOS_VERSION / 10000 << "." << KOKKOS_VERSION / 100 % 100 << "." << KOKKOS_VERSION % 100
     << " " << compat::backend_name() << ", host SIMD " << host_simd() << ", precision "
     << (sizeof(Real) == 4 ? "float" : "double");
#ifdef RTMINI_HAVE_MPI
  // Allowed before MPI_Init (MPI-3), so the banner can print before any communicator exists.
  // Open MPI's string runs over several lines (repository, release date): keep its first part.
  char lib[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  MPI_Get_library_version(lib, &len);
  std::string s(lib, static_cast<std::size_t>(len));
  os << ", MPI: " << s.substr(0, s.find_first_of(",\n"));
#else
  os << ", MPI: none (one-rank stand-in)";
#endif
  return os.str();
}

}  // namespace rtmini
