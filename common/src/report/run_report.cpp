#include "rtmini/report/run_report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>

#include "rtmini/report/hash.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini {

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
  // Phases in first-seen order; each rank's total per name, then the max over ranks.
  std::vector<std::string> order;
  std::map<std::string, double> totals;
  for (const auto& p : timer.phases()) {
    if (!totals.count(p.first)) order.push_back(p.first);
    totals[p.first] += p.second.second - p.second.first;
  }
  // Ranks may time different phases (rank 0 alone writes checkpoints): reduce over the
  // union of all ranks' names, in first-seen order, so every rank makes the same calls.
  std::vector<char> packed;
  for (const auto& name : order)
    packed.insert(packed.end(), name.c_str(), name.c_str() + name.size() + 1);
  const std::vector<char> all = comm.allgatherv(packed);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < all.size();) {
    std::string name(all.data() + i);
    i += name.size() + 1;
    if (std::find(names.begin(), names.end(), name) == names.end())
      names.push_back(std::move(name));
  }
  for (const auto& name : names) {
    const auto it = totals.find(name);
    s.phases.emplace_back(name, comm.max(it == totals.end() ? 0.0 : it->second));
  }
  s.phases.emplace_back("total", comm.max(timer.now()));
  s.fom_name = fom_name;
  s.fom_unit = fom_unit;
  s.fom_value = fom_value;
  s.verification_hash = hash_hex(verification_hash);
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
