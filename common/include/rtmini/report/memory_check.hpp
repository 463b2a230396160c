#pragma once
// Resource check before the big allocations (issue 17): every program estimates what it will
// hold at its peak on each rank and refuses (exit 3, one line) when that exceeds what the rank
// can have: on the host min(cgroup limit minus usage, MemAvailable) shared among the ranks of
// the node, on a device its free memory shared among the ranks using it. `--max-memory`
// (report/common_options.hpp) replaces the machine's figure by a limit, or skips the check.
// The decision is collective: one rank short stops every rank.
#include <cstdint>
#include <string>

#include "rtmini/parallel/communicator.hpp"

namespace rtmini {

// --max-memory: 0 = not given (check against the machine), kMemoryUnlimited = no check,
// else a byte limit per rank.
inline constexpr std::int64_t kMemoryUnlimited = -1;

// "unlimited" or a byte size (io/cli_values.hpp parse_byte_size); InputError otherwise.
std::int64_t parse_memory_limit(const std::string& flag, const std::string& text);

// What a run will still allocate on this rank from the point of the check: host bytes, and
// bytes in the default memory space (Views). The check adds the resident set the process
// already holds (runtime, libraries, what was read so far); in a host-only build the Views
// count against the host.
struct MemoryNeed {
  double host = 0;
  double views = 0;
};

// The number after `key` on its line of a "key value [unit]" file (/proc/meminfo,
// /proc/self/status, /proc/self/smaps_rollup, a cgroup's memory.stat), or 0 when absent. The
// unit is the file's: kB in /proc, bytes in memory.stat.
double read_field(const std::string& path, const std::string& key);

// This process's resident set now (bytes; the peak is report/run_report.hpp's
// peak_resident_bytes).
double resident_bytes();

// What this rank can have: host bytes and where that figure comes from; device bytes (-1 when
// the Views live in host memory or the runtime cannot tell).
struct MemoryBudget {
  double host = 0;
  std::string host_source;
  double device = -1;
};
MemoryBudget memory_budget(const Communicator& comm);

// The peak this rank expects: resident now + need (host), views (device builds).
struct MemoryPeak {
  double host = 0;
  double device = 0;
};
MemoryPeak expected_peak(const MemoryNeed& need);

// Collective: throws IoError on every rank ("needs ~X GiB on rank r, Y GiB available
// (source); --max-memory overrides") when any rank's expected peak exceeds its budget, or
// `limit` when one was given. Returns this rank's expected peak (for the banner).
MemoryPeak require_memory(const Communicator& comm, const MemoryNeed& need, std::int64_t limit);

}  // namespace rtmini
