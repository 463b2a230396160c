#include "rtmini/report/version.hpp"

#include <sstream>

#include "rtmini/config.hpp"
#include "rtmini/kokkos_compat.hpp"
#ifdef RTMINI_HAVE_MPI
#include <mpi.h>
#endif

namespace rtmini {

std::string build_banner() {
  std::ostringstream os;
  os << "rtmini " << version_string() << " (git " << git_hash() << ") Kokkos "
     << KOKKOS_VERSION / 10000 << "." << KOKKOS_VERSION / 100 % 100 << "." << KOKKOS_VERSION % 100
     << " " << compat::backend_name() << ", precision " << (sizeof(Real) == 4 ? "float" : "double");
#ifdef RTMINI_HAVE_MPI
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
