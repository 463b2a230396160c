#pragma once
// The shared outer layer of every executable: MPI + Kokkos lifetime and the
// exit-code contract (docs/architecture.md §6). Bad input -> one line on stderr and 2;
// resource/I-O failure -> 3. Input errors are detected identically on every
// rank (all ranks read and validate the same input), so all ranks exit 2
// together; any other failure on one rank aborts the whole job with 3.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "rtmini/io/error.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini {

template <class Body>
int app_main(const char* app, int argc, char** argv, Body&& body) {
  Environment env(argc, argv);
  Communicator comm;
  int code = kExitOk;
  try {
    code = body(comm, argc, argv);
  } catch (const InputError& e) {
    if (comm.is_root()) std::cerr << app << ": " << e.what() << "\n";
    code = kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << app << " (rank " << comm.rank() << "): " << e.what() << "\n";
#ifdef RTMINI_HAVE_MPI
    if (comm.size() > 1) MPI_Abort(comm.native(), kExitResource);
#endif
    code = kExitResource;
  }
  std::fflush(stdout);
  return code;
}

}  // namespace rtmini
