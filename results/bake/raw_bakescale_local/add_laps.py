import sys
p=sys.argv[1]
s=open(p).read()
s=s.replace('#include <algorithm>\n','#include <algorithm>\n#include <chrono>\n#include <cstdlib>\n#include <ctime>\n',1)
s=s.replace('''using Exec = Kokkos::DefaultExecutionSpace;
''','''using Exec = Kokkos::DefaultExecutionSpace;

// LAPS (temporary instrumentation)
int g_lap_rank = 0;
void lap(const char* what) {
  static const bool on = std::getenv("RTMINI_LAPS") != nullptr;
  if (!on) return;
  using C = std::chrono::steady_clock;
  static C::time_point last = C::now();
  static double last_cpu = 0;
  Kokkos::fence();
  const C::time_point t = C::now();
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  const double cpu = ts.tv_sec + 1e-9 * ts.tv_nsec;
  std::fprintf(stderr, "lap r%d %-24s %.4f cpu %.4f\\n", g_lap_rank, what,
               std::chrono::duration<double>(t - last).count(), cpu - last_cpu);
  last = t;
  last_cpu = cpu;
}
''',1)
n=0
def rep(a,b):
    global s,n
    if a in s:
        s=s.replace(a,b,1); n+=1
    else:
        print('missing anchor:',a[:60],file=sys.stderr)
rep('''  scene_ =
      std::make_unique<BakeSceneDevice>''','''  g_lap_rank = comm_.rank();
  lap("setup.start");
  scene_ =
      std::make_unique<BakeSceneDevice>''')
rep('''  chef_ = std::make_unique<Chef>(*scene_, c_, my_items_);
}''','''  lap("setup.pilot");
  chef_ = std::make_unique<Chef>(*scene_, c_, my_items_);
  lap("setup.chef");
}''')
rep('''    totals_.rays += traced_.rays;
''','''    totals_.rays += traced_.rays;
    lap("map.trace");
''')
rep('''    if (c_.balance == Balance::kCost) rebalance_by_traced_cost();
''','''    if (c_.balance == Balance::kCost) rebalance_by_traced_cost();
    lap("map.rebalance");
''')
rep('''    count_reads();
  }
  timer_.stop();''','''    count_reads();
    lap("map.count_reads");
  }
  timer_.stop();''')
rep('''  if (std::equal(from.begin(), from.end(), batches_.begin(), batches_.end(), same)) return;
''','''  if (std::equal(from.begin(), from.end(), batches_.begin(), batches_.end(), same)) return;
  lap("rebal.recut");
''')
rep('''  // Hits received from other ranks: the entries''','''  lap("rebal.move");
  // Hits received from other ranks: the entries''')
rep('''void BakeRun::finish_fused_plan() {
''','''void BakeRun::finish_fused_plan() {
  lap("fin.start");
''')
rep('''  pending_ = PendingHalo{};
''','''  pending_ = PendingHalo{};
  lap("fin.layout_copy");
''')
rep('''  exchange_ = std::make_unique<MapExchange>(comm_, host_, layout_, owner_, halo_entries());
  report_map_plan();
}''','''  exchange_ = std::make_unique<MapExchange>(comm_, host_, layout_, owner_, halo_entries());
  lap("fin.exchange_plan");
  report_map_plan();
}''')
rep('''    totals_.rays += trace(it, next_);
''','''    lap("it.before");
    totals_.rays += trace(it, next_);
    lap("it.trace");
''')
rep('''    exchange(it, rec);
''','''    lap("it.barrier");
    exchange(it, rec);
    lap("it.exchange");
''')
open(p,'w').write(s)
print(n,'anchors')
