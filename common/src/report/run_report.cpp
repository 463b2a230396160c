#include "rtmini/report/run_report.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include "rtmini/report/hash.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini {

// VmHWM, the kernel's high-water mark of this process's resident memory (Linux only): no
// sampling thread, and nothing is missed between samples. Without /proc the answer is 0, which
// the summary shows as it is rather than a guess.
std::int64_t peak_resident_bytes() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmHWM:") {
      std::int64_t kb = 0;
      in >> kb;
      return kb * 1024;
    }
    std::getline(in, key);
  }
  return 0;
}

RunSummary RunReport::finish(const Communicator& comm, const std::string& summary_path) {
  RunSummary s;
  s.app = app;
  s.version = version_string();
  s.git_hash = git_hash();
  s.backend = compat::backend_name();
  s.ranks = comm.size();
  s.threads = compat::concurrency();
  s.scene = scene;
  s.parameters = parameters;
  s.errors = errors;
  // Each rank's total per phase name (a phase timed several times adds up), then the max over
  // ranks: the summary reports the slowest rank, which is what the run waited for. The max runs
  // over the names every rank agrees on, so every rank makes the same collective calls.
  std::map<std::string, double> totals;
  for (const auto& p : timer.phases()) totals[p.first] += p.second.second - p.second.first;
  for (const auto& name : agreed_phase_names(comm, timer)) {
    const auto it = totals.find(name);
    s.phases.emplace_back(name, comm.max(it == totals.end() ? 0.0 : it->second));
  }
  s.phases.emplace_back("total", comm.max(timer.now()));
  s.fom_name = fom_name;
  s.fom_unit = fom_unit;
  s.fom_value = fom_value;
  s.verification_hash = hash_hex(verification_hash);
  // A program that knows its own peak better (device memory on a GPU) sets peak_memory_bytes.
  const std::int64_t mine = peak_memory_bytes > 0 ? peak_memory_bytes : peak_resident_bytes();
  s.peak_memory_bytes = static_cast<std::int64_t>(comm.max(static_cast<double>(mine)));
  if (comm.is_root()) {
    if (!summary_path.empty()) write_summary_json(summary_path, s);
    std::printf("%s: %s = %.6g %s, verification %s\n", app.c_str(), fom_name.c_str(), fom_value,
                fom_unit.c_str(), s.verification_hash.c_str());
    std::fflush(stdout);
  }
  return s;
}

}  // namespace rtmini
