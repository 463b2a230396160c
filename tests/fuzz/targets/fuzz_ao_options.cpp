// The `bake ao` command line (AoCli): one argument per input line. CLI11's ParseError is
// accepted like InputError: the apps' shared parse_command_line turns it into one (exit 2).
#include <vector>

#include "ao_options.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  std::string_view rest = as_view(data, size);
  std::vector<std::string> args{"bake"};
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    args.emplace_back(rest.substr(0, end));
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  expect_input_error_only([&] {
    CLI::App app("bake ao");
    rtmini::ao::AoCli cli;
    rtmini::ao::AoOptions options;
    cli.add_to(app, options);
    try {
      app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::ParseError&) {
      return;
    }
    cli.finish(options);
  });
  return 0;
}
