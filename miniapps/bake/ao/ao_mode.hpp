#pragma once
// `bake ao` (old spelling `bake --mode ao`): ambient-occlusion baking onto vertices (issue 8),
// from options already parsed by the caller (ao_options.hpp).
#include "ao_options.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini {
int run_ao_mode(rtmini::Communicator& comm, ao::AoOptions o);
}  // namespace rtmini
