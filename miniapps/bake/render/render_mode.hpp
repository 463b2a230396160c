#pragma once
// `bake render MAP.bs ...`: the offline renderer of baked maps (issue 9). argv is the full
// command line (argv[1] == "render"); the mode parses the rest itself.
#include "rtmini/parallel/communicator.hpp"

namespace rtmini {
int run_render_mode(Communicator& comm, int argc, char** argv);
}  // namespace rtmini
