#include "rtmini/report/memory_check.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "rtmini/io/cli_values.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
// cgroup v1 reports "no limit" as a page-rounded 2^63-1; anything this large is no limit.
constexpr double kNoLimit = 1e18;

// The first number in `path`, or -1 when the file is missing or says "max".
double read_number(const std::string& path) {
  std::ifstream in(path);
  double v = -1;
  if (!(in >> v)) return -1;
  return v;
}

// This process's cgroup path for `controller` ("" = the v2 unified hierarchy), or "" when none.
std::string cgroup_path(const std::string& controller) {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string list = line.substr(a + 1, b - a - 1);
    const bool match = controller.empty()
                           ? list.empty()
                           : ("," + list + ",").find("," + controller + ",") != std::string::npos;
    if (match) return line.substr(b + 1);
  }
  return "";
}

// The smallest "limit minus usage" over `dir` and its parents up to `root` (a limit set higher
// up binds too); usage leaves out inactive page cache, which the kernel reclaims first.
// -1 when no level sets a limit.
double cgroup_headroom(std::string dir, const std::string& root, const char* limit_file,
                       const char* usage_file, const char* inactive_key) {
  double best = -1;
  for (;;) {
    const double limit = read_number(dir + "/" + limit_file);
    if (limit >= 0 && limit < kNoLimit) {
      const double usage =
          read_number(dir + "/" + usage_file) - read_field(dir + "/memory.stat", inactive_key);
      const double room = std::max(0.0, limit - std::max(0.0, usage));
      best = best < 0 ? room : std::min(best, room);
    }
    if (dir.size() <= root.size()) break;
    dir = dir.substr(0, dir.find_last_of('/'));
  }
  return best;
}

// Host bytes this node offers (before sharing among its ranks) and the source of the figure.
std::pair<double, std::string> node_host_memory() {
  double best = read_field("/proc/meminfo", "MemAvailable:") * 1024.0;
  std::string source = "MemAvailable";
  const std::string v2 = cgroup_path("");
  double room = -1;
  const char* name = "cgroup memory.max";
  if (!v2.empty() && std::ifstream("/sys/fs/cgroup/cgroup.controllers")) {
    room = cgroup_headroom("/sys/fs/cgroup" + (v2 == "/" ? std::string() : v2), "/sys/fs/cgroup",
                           "memory.max", "memory.current", "inactive_file");
  } else {
    const std::string v1 = cgroup_path("memory"), root = "/sys/fs/cgroup/memory";
    std::string dir = root + (v1 == "/" ? std::string() : v1);
    if (!std::ifstream(dir + "/memory.limit_in_bytes")) dir = root;  // namespaced: we are the root
    room = cgroup_headroom(dir, root, "memory.limit_in_bytes", "memory.usage_in_bytes",
                           "total_inactive_file");
    name = "cgroup memory.limit_in_bytes";
  }
  if (room >= 0 && (best <= 0 || room < best)) {
    best = room;
    source = name;
  }
  return {best, source};
}

std::string gib(double bytes) {
  char buf[32];
  const double g = bytes / kGiB;
  std::snprintf(buf, sizeof buf, g < 1000 ? "%.3g GiB" : "%.0f GiB", g);
  return buf;
}

// One rank's figures, gathered so every rank takes the same decision.
struct RankMemory {
  double host_need, host_have, device_need, device_have;
  int host_source;  // 0 MemAvailable, 1 cgroup v2, 2 cgroup v1, 3 --max-memory
};

const char* source_name(int s) {
  switch (s) {
    case 1:
      return "cgroup memory.max";
    case 2:
      return "cgroup memory.limit_in_bytes";
    case 3:
      return "--max-memory";
    default:
      return "MemAvailable";
  }
}

int source_code(const std::string& s) {
  if (s == "cgroup memory.max") return 1;
  if (s == "cgroup memory.limit_in_bytes") return 2;
  return 0;
}

}  // namespace

double read_field(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {  // by line: /proc/self/status has words as values too
    std::istringstream fields(line);
    std::string k;
    double v = 0;
    if (fields >> k && k == key && fields >> v) return v;
  }
  return 0;
}

std::int64_t parse_memory_limit(const std::string& flag, const std::string& text) {
  if (text.empty()) return 0;
  if (text == "unlimited") return kMemoryUnlimited;
  const std::int64_t bytes = parse_byte_size(flag, text);
  if (bytes <= 0) throw InputError(flag + " must be > 0 bytes or 'unlimited' (got '" + text + "')");
  return bytes;
}

double resident_bytes() {
  long pages_total = 0, pages_resident = 0;
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f) {
    if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
    std::fclose(f);
  }
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

MemoryBudget memory_budget(const Communicator& comm) {
  MemoryBudget b;
  const auto [host, source] = node_host_memory();
  b.host = host / std::max(1, comm.node_size());
  b.host_source = source;
  if (compat::kDeviceMemory) {
    const compat::DeviceMemoryInfo d = compat::device_memory_info();
    if (d.free_bytes >= 0) {
      // Ranks of a node take the node's devices round-robin (Kokkos' default mapping).
      const int devices = std::max(1, d.devices);
      const int sharing = (comm.node_size() + devices - 1) / devices;
      b.device = d.free_bytes / std::max(1, sharing);
    }
  }
  return b;
}

MemoryPeak expected_peak(const MemoryNeed& need) {
  MemoryPeak p;
  p.host = resident_bytes() + need.host;
  if (compat::kDeviceMemory)
    p.device = need.views;
  else
    p.host += need.views;
  return p;
}

MemoryPeak require_memory(const Communicator& comm, const MemoryNeed& need, std::int64_t limit) {
  const MemoryPeak peak = expected_peak(need);
  if (limit == kMemoryUnlimited) return peak;
  RankMemory mine{peak.host, 0, peak.device, -1, 3};
  if (limit > 0) {
    // One figure per rank, as the estimates printed in the banners: host and device together.
    mine.host_need = peak.host + peak.device;
    mine.host_have = static_cast<double>(limit);
    mine.device_need = 0;
  } else {
    const MemoryBudget b = memory_budget(comm);
    mine.host_have = b.host;
    mine.host_source = source_code(b.host_source);
    mine.device_have = b.device;
  }
  const std::vector<RankMemory> all = comm.allgatherv(std::vector<RankMemory>{mine});
  for (std::size_t r = 0; r < all.size(); ++r) {
    const RankMemory& m = all[r];
    if (m.host_have > 0 && m.host_need > m.host_have)
      throw IoError("needs ~" + gib(m.host_need) + " on rank " + std::to_string(r) + ", " +
                    gib(m.host_have) + " available (" + source_name(m.host_source) +
                    "); --max-memory overrides");
    if (m.device_have >= 0 && m.device_need > m.device_have)
      throw IoError("needs ~" + gib(m.device_need) + " of device memory on rank " +
                    std::to_string(r) + ", " + gib(m.device_have) +
                    " available (cudaMemGetInfo); --max-memory overrides");
  }
  return peak;
}

}  // namespace rtmini
