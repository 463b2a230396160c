#include "rtmini/io/summary_json.hpp"

#include <gtest/gtest.h>

#include "io_test_util.hpp"

namespace rtmini {
namespace {

RunSummary make_summary() {
  RunSummary s;
  s.app = "sketchtrace";
  s.version = "0.1.0";
  s.git_hash = "deadbeef";
  s.backend = "OpenMP";
  s.ranks = 4;
  s.threads = 2;
  s.scene = {{"triangles", 12}, {"file", "two_spheres.toml"}};
  s.parameters = {{"spp", 16}, {"width", 640}};
  s.phases = {{"read", 0.5}, {"bvh", 0.25}, {"trace", 12.75}};
  s.fom_name = "rays_per_second";
  s.fom_unit = "rays/s";
  s.fom_value = 1.5e9;
  s.verification_hash = "0123456789abcdef";
  s.peak_memory_bytes = 123456789012LL;
  return s;
}

TEST(SummaryJson, ParsesBackWithStableOrder) {
  test::TempDir dir;
  const RunSummary s = make_summary();
  write_summary_json(dir.file("s.json"), s);
  EXPECT_EQ(test::count_files(dir.path()), 1);
  const std::string text = test::read_file(dir.file("s.json"));
  const auto j = nlohmann::ordered_json::parse(text);

  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  EXPECT_EQ(keys,
            (std::vector<std::string>{"app", "version", "git_hash", "backend", "ranks", "threads",
                                      "scene", "parameters", "phases", "figure_of_merit",
                                      "verification_hash", "peak_memory_bytes"}));
  EXPECT_EQ(j["app"], "sketchtrace");
  EXPECT_EQ(j["ranks"], 4);
  EXPECT_EQ(j["scene"]["triangles"], 12);
  EXPECT_EQ(j["parameters"]["width"], 640);
  std::vector<std::string> phases;
  for (const auto& item : j["phases"].items()) phases.push_back(item.key());
  EXPECT_EQ(phases, (std::vector<std::string>{"read", "bvh", "trace"}));  // run order kept
  EXPECT_EQ(j["phases"]["trace"], 12.75);
  EXPECT_EQ(j["figure_of_merit"]["name"], "rays_per_second");
  EXPECT_EQ(j["figure_of_merit"]["value"], 1.5e9);
  EXPECT_EQ(j["figure_of_merit"]["unit"], "rays/s");
  EXPECT_EQ(j["peak_memory_bytes"], 123456789012LL);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(format_summary_json(s), text);  // same input, same bytes
}

TEST(SummaryJson, ErrorsOnlyWhenGiven) {
  RunSummary s = make_summary();
  EXPECT_FALSE(nlohmann::json::parse(format_summary_json(s)).contains("errors"));
  s.errors = {{"rmse", 0.01}, {"max_abs", 0.2}};
  const auto j = nlohmann::json::parse(format_summary_json(s));
  EXPECT_EQ(j["errors"]["rmse"], 0.01);
}

}  // namespace
}  // namespace rtmini
