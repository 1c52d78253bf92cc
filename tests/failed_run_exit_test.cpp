// A run whose participant gives up on a step without a divergence to show
// for it (a node's STEP_FAILED, its displacements calm) is `failed`, and the
// master program exits 1 for it on every path: relayed, on the direct plane's
// windows, in lock step (implicit coupling) and implicit multirate (the
// soil's cut at 5 H, relayed). It once wrote status `failed` and exited 0.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;

struct FailedRun {
  test::Outcome outcome;
  std::string summary;
  std::string node;  // the broken node's address
};

// `master run --scene SCENE --case CASE FLAGS` with ROLE on `broken_node
// fails-step` (the others started by the master).
FailedRun run_with_failing(const std::string& name, const std::string& scene,
                           const std::string& case_name, const std::string& role,
                           const std::string& flags) {
  const fs::path dir = test::temp_dir(name);
  remote::LaunchedNode node(
      remote::LaunchCommand{"broken_node",
                            {std::string(RAILCOSIM_BIN_DIR) + "/broken_node", "fails-step",
                             "--listen", "127.0.0.1:0", "--role", role},
                            {}},
      std::chrono::milliseconds(10000));
  FailedRun r;
  r.node = node.address().str();
  r.outcome = test::run_master("run --scene " + test::source_path("scenes/" + scene) + " --case " +
                               case_name + " --node " + role + "=" + r.node + " --out " +
                               (dir / "out").string() + " " + flags);
  r.summary = test::read_file(dir / "out" / case_name / "summary.json");
  fs::remove_all(dir);
  return r;
}

// `mode`: the summary's data_plane_mode, "" for the relayed plane.
void expect_failed(const FailedRun& r, const std::string& role, const std::string& mode) {
  EXPECT_EQ(r.outcome.status, 1) << r.outcome.output;
  if (!mode.empty()) {
    EXPECT_NE(r.summary.find("\"data_plane_mode\": \"" + mode + "\""), std::string::npos)
        << r.summary;
  }
  EXPECT_NE(r.summary.find("\"status\": \"failed\""), std::string::npos) << r.summary;
  // The failure and the node are named on stderr, with the reason.
  EXPECT_NE(r.outcome.output.find("failed: "), std::string::npos) << r.outcome.output;
  EXPECT_NE(r.outcome.output.find(role + " node at " + r.node), std::string::npos)
      << r.outcome.output;
  EXPECT_NE(r.outcome.output.find("the integrator gave up on macro step 10"), std::string::npos)
      << r.outcome.output;
  EXPECT_NE(r.outcome.output.find("not judged diverged"), std::string::npos) << r.outcome.output;
}

TEST(FailedRunExit, RelayedExitsOne) {
  expect_failed(
      run_with_failing("failed_relay", "paper.toml", "wr-xx-jacobi", "track", "--data-plane relay"),
      "track", "");
}

TEST(FailedRunExit, DirectWindowsExitOne) {
  expect_failed(run_with_failing("failed_direct", "paper.toml", "wr-xx-jacobi", "track",
                                 "--data-plane direct"),
                "track", "windows");
}

TEST(FailedRunExit, LockStepExitsOne) {
  expect_failed(run_with_failing("failed_lockstep", "paper.toml", "wr-xx-jacobi", "track",
                                 "--data-plane direct --coupling implicit"),
                "track", "lock step");
}

TEST(FailedRunExit, ImplicitMultirateExitsOne) {
  expect_failed(run_with_failing("failed_multirate", "soil.toml", "wr-xx+ss-xx-jacobi", "soil",
                                 "--coupling implicit"),
                "soil", "");  // multirate implicit coupling runs relayed
}

}  // namespace
}  // namespace railcosim
