// One step-deadline rule on both data planes, with a floor the user raises:
// the track served by tests/broken_node.cpp slow-silent takes 3 s on its
// macro step 300 without a word (the steps before it a few milliseconds
// each, so the deadline is its floor). At the default floor of 2 s both
// planes name the silent node within seconds; with --step-deadline-floor 5,
// or [coupling] step_deadline_floor = 5, both end `ok`.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>

#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace deadline_floor_test {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct FloorRun {
  test::Outcome outcome;
  std::string summary, track;
  double seconds = 0;
};

FloorRun run_silent_track(const std::string& name, const std::string& plane,
                          const std::string& flags, const std::string& extra_scene = "") {
  const fs::path dir = test::temp_dir(name);
  std::string text = test::read_file(test::source_path("scenes/paper.toml"));
  text = std::regex_replace(text, std::regex("\nend_time = [^\n]*"), "\nend_time = 0.04");
  std::ofstream(dir / "scene.toml") << text << extra_scene;
  remote::LaunchedNode track(
      remote::LaunchCommand{"broken_node",
                            {std::string(RAILCOSIM_BIN_DIR) + "/broken_node", "slow-silent",
                             "--listen", "127.0.0.1:0", "--role", "track"},
                            {}},
      std::chrono::milliseconds(10000));
  FloorRun r;
  r.track = track.address().str();
  const auto t0 = Clock::now();
  r.outcome = test::run_master(
      "run --scene " + (dir / "scene.toml").string() + " --case wr-xx-jacobi --data-plane " +
      plane + " --node track=" + r.track + " --out " + (dir / "out").string() + " " + flags);
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.summary = test::read_file(dir / "out" / "wr-xx-jacobi" / "summary.json");
  fs::remove_all(dir);
  return r;
}

void expect_named_at_floor(const FloorRun& r) {
  EXPECT_EQ(r.outcome.status, 1) << r.outcome.output;
  EXPECT_NE(r.outcome.output.find("track node at " + r.track + ": no reply within 2000 ms"),
            std::string::npos)
      << r.outcome.output;
  EXPECT_LT(r.seconds, 10.0) << r.outcome.output;
}

void expect_ok(const FloorRun& r) {
  EXPECT_EQ(r.outcome.status, 0) << r.outcome.output;
  EXPECT_NE(r.summary.find("\"status\": \"ok\""), std::string::npos) << r.summary;
  EXPECT_GT(r.seconds, 3.0) << r.outcome.output;  // the 3 s step was taken
}

TEST(DeadlineFloor, TheDefaultFloorNamesASilentStepOnTheRelayedPlane) {
  expect_named_at_floor(run_silent_track("floor_relay", "relay", ""));
}

TEST(DeadlineFloor, TheDefaultFloorNamesASilentStepOnTheDirectPlane) {
  expect_named_at_floor(run_silent_track("floor_direct", "direct", ""));
}

TEST(DeadlineFloor, ARaisedFloorLetsTheSilentStepFinishOnTheRelayedPlane) {
  expect_ok(run_silent_track("floor_relay_5", "relay", "--step-deadline-floor 5"));
}

TEST(DeadlineFloor, ARaisedFloorLetsTheSilentStepFinishOnTheDirectPlane) {
  expect_ok(run_silent_track("floor_direct_5", "direct", "--step-deadline-floor 5"));
}

TEST(DeadlineFloor, TheScenesFloorDoesTheSame) {
  expect_ok(
      run_silent_track("floor_scene", "direct", "", "\n[coupling]\nstep_deadline_floor = 5\n"));
}

TEST(DeadlineFloor, AFloorOutOfRangeIsRefused) {
  for (const char* value : {"nan", "0.01", "1e300"}) {
    const test::Outcome o =
        test::run_master("run --scene " + test::source_path("scenes/paper.toml") +
                         " --case wr-xx-jacobi --check --step-deadline-floor " + value);
    EXPECT_NE(o.status, 0) << o.output;
    EXPECT_NE(o.output.find("expected seconds from 0.1 to 86400, got " + std::string(value)),
              std::string::npos)
        << o.output;
  }
}

}  // namespace deadline_floor_test
}  // namespace railcosim
