#pragma once
#include <string>

namespace rtmini {
const char* version_string();
const char* git_hash();
// One line: "rtmini 0.1.0 (git abc123) Kokkos 3.4.1 OpenMP, MPI: Open MPI v4.1.4, 2 threads".
std::string build_banner();
}  // namespace rtmini
