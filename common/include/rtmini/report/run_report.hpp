#pragma once
// What every run reports (docs/architecture.md §6): phases (max over ranks), one
// figure of merit, a verification hash, the --summary JSON and the one-line
// summary that is always the last line on stdout.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "rtmini/io/summary_json.hpp"
#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/timer.hpp"

namespace rtmini {

struct RunReport {
  std::string app;
  nlohmann::json scene = nlohmann::json::object();
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json errors;  // filled when a reference was given
  PhaseTimer timer;
  std::string fom_name, fom_unit;
  double fom_value = 0;
  std::uint64_t verification_hash = 0;
  std::int64_t peak_memory_bytes = 0;

  // Collective: reduces phase times to their max over ranks, writes the JSON
  // summary on rank 0 when `summary_path` is not empty, and prints the final
  // one-line summary on rank 0. Returns the summary for callers that want it.
  RunSummary finish(const Communicator& comm, const std::string& summary_path);
};

// Resident set high-water mark of this process in bytes (Linux VmHWM), 0 if unknown.
std::int64_t peak_resident_bytes();

}  // namespace rtmini
