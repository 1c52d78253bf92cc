// Numbers from the command line and the scene that used to be accepted and
// meant "no limit" or ended in an internal message: each is refused with a
// message naming the flag or the key and the range.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "process_support.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace input_bounds_test {

namespace fs = std::filesystem;
using test::Outcome;
using test::run_master;
using test::run_program;

const std::string kSoil = test::source_path("scenes/soil.toml");

// scenes/soil.toml with its ss_macro_step line replaced by `line`.
std::string soil_scene_with(const std::string& name, const std::string& line) {
  const fs::path path = test::temp_dir("input_bounds_" + name) / "soil.toml";
  std::ifstream in(kSoil);
  std::ofstream out(path);
  for (std::string l; std::getline(in, l);)
    out << (l.rfind("ss_macro_step", 0) == 0 ? line : l) << "\n";
  return path.string();
}

void expect_refused(const Outcome& o, const std::string& text) {
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find(text), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find("plan_rates"), std::string::npos) << o.output;
}

TEST(InputBounds, AHugeCutWindowIsRefusedWithAUserMessage) {
  const Outcome o =
      run_master("run --scene " + kSoil + " --case ss-xt-jacobi --macro-step ss=1e300 --check");
  expect_refused(o, "--macro-step ss=1e300: the window 1e+300 s of cut ss is ");
  expect_refused(o, "a cut's window is at most 1e+09 finest windows");
}

TEST(InputBounds, ASceneWindowThatIsNoMultipleOfHIsRefused) {
  expect_refused(
      run_master("run --scene " + soil_scene_with("odd", "ss_macro_step = 1.5e-4") +
                 " --case ss-xt-jacobi --check"),
      "key 'coupling.ss_macro_step': the window 0.00015 s is not an integer multiple (at most "
      "1e9) of simulation.macro_step = 0.0001 s; the nearest multiples are 0.0001 s and 0.0002 s");
}

TEST(InputBounds, ASceneWindowOfZeroIsRefused) {
  expect_refused(run_master("run --scene " + soil_scene_with("zero", "ss_macro_step = 0") +
                            " --case ss-xt-jacobi --check"),
                 "key 'coupling.ss_macro_step': 0 is no window: leave the key out");
}

TEST(InputBounds, ASceneWindowThatIsAMultipleStillRuns) {
  const Outcome o = run_master("run --scene " + soil_scene_with("fine", "ss_macro_step = 5e-4") +
                               " --case ss-xt-jacobi --check");
  EXPECT_EQ(o.status, 0) << o.output;
}

TEST(InputBounds, AStepBudgetOfNanIsRefused) {
  expect_refused(run_master("run --scene " + kSoil +
                            " --case ss-xt-jacobi --step-budget nan "
                            "--check"),
                 "expected seconds from 0.1 to 86400, got nan");
}

TEST(InputBounds, ANodesSecondsAreBounded) {
  for (const char* option : {"--max-step-seconds", "--idle-timeout", "--message-timeout"})
    for (const char* value : {"nan", "1e-300", "1e300", "inf", "0"}) {
      const Outcome o = run_program("soil_node", std::string(option) + " " + value + " --check");
      expect_refused(o, "expected seconds from 0.001 to 86400, got " + std::string(value));
    }
  EXPECT_EQ(run_program("soil_node", "--max-step-seconds 0.5 --check").status, 0);
}

TEST(InputBounds, OneAddressForTwoRolesIsRefusedAtOnce) {
  const auto t0 = std::chrono::steady_clock::now();
  expect_refused(run_master("run --scene " + test::source_path("scenes/paper.toml") +
                            " --case wr-xx-jacobi --node vehicle=127.0.0.1:9 --node "
                            "track=127.0.0.1:9"),
                 "the track and vehicle participants were both given 127.0.0.1:9: a node "
                 "serves one participant");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

}  // namespace input_bounds_test
}  // namespace railcosim
