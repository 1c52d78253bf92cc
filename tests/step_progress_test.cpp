// A node's macro step that legitimately takes long, against one that only
// pretends to work: the master program over TCP, on both data planes, with
// the track served by tests/broken_node.cpp. Its macro step 300 takes 4 s
// (the steps before it a few milliseconds each, so the step deadline is its
// floor of 2 s) while the node sends progress frames that advance
// (slow-working), or frames that never advance (stuck-progress). The first
// must end `ok`, the second be named within the deadline, and the step budget
// (--step-budget, [coupling] step_budget) ends even a working step.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>

#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct ProgressRun {
  test::Outcome outcome;
  std::string summary;
  std::string track;  // the track node's address
  double seconds = 0;
};

// Runs wr-xx-jacobi of the paper scene shortened to 400 macro steps (with
// `extra_scene` appended), the track on `broken_node MODE`.
ProgressRun run_with_track(const std::string& name, const std::string& mode,
                           const std::string& plane, const std::string& flags = "",
                           const std::string& extra_scene = "") {
  const fs::path dir = test::temp_dir(name);
  std::string text = test::read_file(test::source_path("scenes/paper.toml"));
  text = std::regex_replace(text, std::regex("\nend_time = [^\n]*"), "\nend_time = 0.04");
  std::ofstream(dir / "scene.toml") << text << extra_scene;
  remote::LaunchedNode track(
      remote::LaunchCommand{"broken_node",
                            {std::string(RAILCOSIM_BIN_DIR) + "/broken_node", mode, "--listen",
                             "127.0.0.1:0", "--role", "track"},
                            {}},
      std::chrono::milliseconds(10000));
  ProgressRun r;
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

void expect_ok(const ProgressRun& r) {
  EXPECT_EQ(r.outcome.status, 0) << r.outcome.output;
  EXPECT_NE(r.summary.find("\"status\": \"ok\""), std::string::npos) << r.summary;
  // The 4 s step was taken, not skipped.
  EXPECT_GT(r.seconds, 4.0) << r.outcome.output;
}

void expect_stuck_named(const ProgressRun& r) {
  EXPECT_EQ(r.outcome.status, 1) << r.outcome.output;
  EXPECT_NE(r.summary.find("\"status\": \"failed\""), std::string::npos) << r.summary;
  EXPECT_NE(r.outcome.output.find("track node at " + r.track + ": no progress for "),
            std::string::npos)
      << r.outcome.output;
  EXPECT_NE(r.outcome.output.find("progress frame(s) since then did not advance"),
            std::string::npos)
      << r.outcome.output;
  // Within the deadline of its step (at least 2 s; the node itself gives up
  // after 30 s, the step budget after 120 s).
  EXPECT_LT(r.seconds, 10.0) << r.outcome.output;
}

TEST(StepProgress, ALongStepShowingProgressEndsOkRelayed) {
  expect_ok(run_with_track("progress_relay", "slow-working", "relay"));
}

TEST(StepProgress, ALongStepShowingProgressEndsOkDirect) {
  expect_ok(run_with_track("progress_direct", "slow-working", "direct"));
}

TEST(StepProgress, ProgressThatNeverAdvancesIsNamedRelayed) {
  expect_stuck_named(run_with_track("stuck_relay", "stuck-progress", "relay"));
}

TEST(StepProgress, ProgressThatNeverAdvancesIsNamedDirect) {
  expect_stuck_named(run_with_track("stuck_direct", "stuck-progress", "direct"));
}

// The budget ends a step however much progress it shows: the flag on the
// relayed plane, the scene's key on the direct one.
TEST(StepProgress, TheStepBudgetEndsAWorkingStep) {
  for (const auto& [plane, flags, scene] :
       {std::tuple<std::string, std::string, std::string>{"relay", "--step-budget 1", ""},
        {"direct", "", "\n[coupling]\nstep_budget = 1\n"}}) {
    const ProgressRun r = run_with_track("budget_" + plane, "slow-working", plane, flags, scene);
    EXPECT_EQ(r.outcome.status, 1) << r.outcome.output;
    EXPECT_NE(r.outcome.output.find("track node at " + r.track + ": step budget of 1 s exhausted"),
              std::string::npos)
        << plane << "\n"
        << r.outcome.output;
    EXPECT_LT(r.seconds, 4.0) << r.outcome.output;
  }
}

}  // namespace
}  // namespace railcosim
