#include "rtmini/io/summary_json.hpp"

#include "rtmini/io/atomic_file.hpp"

namespace rtmini {

std::string format_summary_json(const RunSummary& s) {
  // ordered_json keeps insertion order for the top level; nested objects from
  // nlohmann::json keep their sorted keys, so the whole text is stable.
  nlohmann::ordered_json j;
  j["app"] = s.app;
  j["version"] = s.version;
  j["git_hash"] = s.git_hash;
  j["backend"] = s.backend;
  j["ranks"] = s.ranks;
  j["threads"] = s.threads;
  // json and ordered_json are unrelated types: a text round trip is the one conversion.
  j["scene"] = nlohmann::ordered_json::parse(s.scene.dump());
  j["parameters"] = nlohmann::ordered_json::parse(s.parameters.dump());
  nlohmann::ordered_json phases = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : s.phases) phases[name] = seconds;
  j["phases"] = phases;
  j["figure_of_merit"] = {{"name", s.fom_name}, {"value", s.fom_value}, {"unit", s.fom_unit}};
  j["verification_hash"] = s.verification_hash;
  j["peak_memory_bytes"] = s.peak_memory_bytes;
  if (!s.errors.is_null()) j["errors"] = nlohmann::ordered_json::parse(s.errors.dump());
  return j.dump(2) + "\n";
}

// Atomic (temporary + rename): a job script or the analysis package reading the summary while
// the run ends sees the old file or the whole new one, never a truncated JSON.
void write_summary_json(const std::string& path, const RunSummary& summary) {
  write_text_atomic(path, format_summary_json(summary));
}

}  // namespace rtmini
