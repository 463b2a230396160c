// rtmini-ao: the AO baking mode as a standalone binary (same options as `bake ao`).
#include "ao_mode.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"

int main(int argc, char** argv) {
  return rtmini::app_main(
      "rtmini-ao", argc, argv, [](rtmini::Communicator& comm, int ac, char** av) {
        using namespace rtmini;
        CLI::App app{"rtmini-ao: ambient-occlusion baking onto mesh vertices (same as `bake ao`)",
                     "rtmini-ao"};
        CommonOptions common;
        add_common_options(app, common);
        ao::AoOptions options;
        ao::AoCli cli;
        cli.add_to(app, options);
        if (const auto done = parse_command_line(app, ac, av, common, comm.is_root())) return *done;
        cli.finish(options);
        options.summary = common.summary;
        options.timings = common.timings;
        options.progress = progress_wanted(common);
        options.max_memory = common.memory_limit();
        return run_ao_mode(comm, options);
      });
}
