// rtmini-ao: the AO baking mode as a standalone binary (same options as `bake --mode ao`).
#include "ao_mode.hpp"
#include "rtmini/report/app_main.hpp"

int main(int argc, char** argv) {
  return rtmini::app_main("bake", argc, argv, [](rtmini::Communicator& comm, int ac, char** av) {
    return rtmini::run_ao_mode(comm, ac, av);
  });
}
