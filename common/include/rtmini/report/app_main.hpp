#pragma once
// The shared outer layer of every executable: MPI + Kokkos lifetime and the
// exit-code contract (docs/architecture.md §6). Bad input -> one line on stderr and 2;
// resource/I-O failure -> 3. Failures are collective (issue 17): a rank that
// fails tells every rank (Communicator::notify_failure); ranks waiting in a
// collective unwind with PeerFailure; then all ranks agree on the outcome and
// exit with the same code, rank 0 printing the one line (naming the failing
// rank when not every rank failed).
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "rtmini/io/error.hpp"
#include "rtmini/io/hdf5_file.hpp"
#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/stop_request.hpp"

namespace rtmini {

// How long a rank that knows of a failure waits for the others to agree
// before it aborts the job (a peer stuck outside any collective). Rank 0
// gives up first so that it is the one to print the line.
inline double agreement_patience(const Communicator& comm) { return comm.is_root() ? 10.0 : 20.0; }

template <class Body>
int app_main(const char* app, int argc, char** argv, Body&& body) {
  // Before MPI and Kokkos start (seconds on a large job): a SIGTERM/SIGUSR1/SIGINT in
  // start-up then stops the run cleanly at its first check instead of killing it.
  install_stop_handlers();
  quiet_hdf5_errors();  // HDF5 failures are our one line, never libhdf5's stack dump
  Environment env(argc, argv);
  Communicator comm;
  int code = kExitOk;
  bool failed = false;
  std::string message;
  try {
    code = body(comm, argc, argv);
  } catch (const PeerFailure&) {
    // Another rank failed first: the agreement below reports it.
  } catch (const InputError& e) {
    failed = true;
    code = kExitBadInput;
    message = e.what();
  } catch (const std::exception& e) {
    failed = true;
    code = kExitResource;
    message = e.what();
  }
  const Outcome outcome = comm.agree_outcome(code, failed, message, app, agreement_patience(comm));
  if (!outcome.line.empty()) std::cerr << outcome.line << std::endl;
  std::fflush(stdout);
  if (!outcome.agreed) env.abort(outcome.code);
  return outcome.code;
}

}  // namespace rtmini
