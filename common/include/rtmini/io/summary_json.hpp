#pragma once
// The run summary (--summary FILE.json, docs/architecture.md §6). Top-level keys in a
// fixed order: app, version, git_hash, backend, ranks, threads, scene, parameters,
// phases {name: seconds, max over ranks, in run order}, figure_of_merit {name, value, unit}
// (docs/architecture.md §6), verification_hash, peak_memory_bytes, errors (only when not null).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace rtmini {

struct RunSummary {
  std::string app, version, git_hash, backend;
  int ranks = 1;
  int threads = 1;
  nlohmann::json scene = nlohmann::json::object();
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json errors;                               // null = no reference given
  std::vector<std::pair<std::string, double>> phases;  // max over ranks
  std::string fom_name, fom_unit;
  double fom_value = 0.0;
  std::string verification_hash;
  std::int64_t peak_memory_bytes = 0;
};

// The summary as JSON text (2-space indent, trailing newline).
std::string format_summary_json(const RunSummary& summary);
// Writes format_summary_json atomically; IoError on failure.
void write_summary_json(const std::string& path, const RunSummary& summary);

}  // namespace rtmini
