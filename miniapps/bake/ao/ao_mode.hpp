#pragma once
// `bake --mode ao`: ambient-occlusion baking onto vertices (issue 8). argv is
// the full command line; the mode parses it itself.
#include "rtmini/parallel/communicator.hpp"

namespace rtmini {
int run_ao_mode(rtmini::Communicator& comm, int argc, char** argv);
}  // namespace rtmini
