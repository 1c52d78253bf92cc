// The master as a user runs it: a real process, real files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <signal.h>

#include <chrono>
#include <thread>

#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;

using test::Outcome;
using test::read_file;
using test::run_master;

using test::temp_dir;

// Starts `master ARGS` in a thread and returns once `history` holds more
// than `rows` lines (or after a minute); join() the thread for the outcome.
std::thread start_master_until(const std::string& args, const fs::path& history, long rows,
                               Outcome& outcome) {
  std::thread t([args, &outcome] { outcome = run_master(args); });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < give_up) {
    const std::string h = read_file(history);
    if (std::count(h.begin(), h.end(), '\n') > rows) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return t;
}

// The integer value of a top-level key of summary.json (-1 if absent).
long json_long(const std::string& json, const std::string& key) {
  const std::string k = "\"" + key + "\": ";
  const auto at = json.find(k);
  return at == std::string::npos ? -1 : std::stol(json.substr(at + k.size()));
}

TEST(MasterCli, MonolithicRunWritesTheThreeFiles) {
  const fs::path out = temp_dir("cli_mono");
  const Outcome o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                               " --case monolithic --out " + out.string());
  ASSERT_EQ(o.status, 0) << o.output;
  const fs::path dir = out / "monolithic";
  const std::string deflection = read_file(dir / "deflection.csv");
  const std::string history = read_file(dir / "history.csv");
  const std::string summary = read_file(dir / "summary.json");
  EXPECT_EQ(deflection.rfind("x_m,w_m\n", 0), 0u);
  EXPECT_EQ(std::count(deflection.begin(), deflection.end(), '\n'), 102);
  EXPECT_EQ(history.rfind("t_s,wheel_m,contact_force_N\n", 0), 0u);
  EXPECT_EQ(std::count(history.begin(), history.end(), '\n'), 2502);
  for (const char* key :
       {"\"case\": \"monolithic\"", "\"split\"", "\"coupling\"", "\"scheme\"", "\"feedthrough\"",
        "\"macro_step_s\": 0.0001", "\"t_end_s\": 0.25", "\"wall_s\"", "\"macro_steps\": 2500",
        "\"micro_steps\": {\"monolithic\"", "\"status\": \"ok\"", "\"max_abs_error_m\": 0",
        "\"rel_l2_error\": 0", "\"transport\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  fs::remove_all(out);
}

TEST(MasterCli, BadSceneStopsBeforeRunningAndNamesTheKey) {
  const fs::path out = temp_dir("cli_bad");
  std::string text = read_file(test::source_path("scenes/paper.toml"));
  text.replace(text.find("density = 7850.0"), 16, "density = -7850.0");
  std::ofstream(out / "bad.toml") << text;
  const Outcome o = run_master("run --scene " + (out / "bad.toml").string() +
                               " --case monolithic --out " + (out / "res").string());
  EXPECT_NE(o.status, 0);
  EXPECT_NE(o.output.find("bad.toml: key 'rail.density': must be positive"), std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(out / "res")) << "nothing may run on a bad scene";
  fs::remove_all(out);
}

TEST(MasterCli, UnknownCaseListsTheValidOnes) {
  const Outcome o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                               " --case wr-xy-jacobi --transport inproc");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("unknown case 'wr-xy-jacobi'"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("rs-xt-gauss-seidel"), std::string::npos) << o.output;
}

// An external soil is a program of its own: without its address the run
// must stop and name the flag (it used to run the built-in lumped soil).
TEST(MasterCli, AnExternalSoilWithoutItsAddressNamesTheFlag) {
  const fs::path out = temp_dir("cli_external");
  std::string text = read_file(test::source_path("scenes/soil.toml"));
  text.replace(text.find("model = \"lumped\""), 16, "model = \"external\"");
  std::ofstream(out / "external.toml") << text;
  const Outcome o = run_master("run --scene " + (out / "external.toml").string() +
                               " --case wr-xx+ss-xx-jacobi --out " + (out / "res").string());
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("the scene's soil is external (soil.model = \"external\"): start its "
                          "program and give its address with --node soil=HOST:PORT"),
            std::string::npos)
      << o.output;
  EXPECT_FALSE(fs::exists(out / "res" / "wr-xx+ss-xx-jacobi" / "soil.csv")) << "nothing may run";
  // A study starts its own nodes: it cannot reach the external soil either.
  const Outcome s = run_master("study --scene " + (out / "external.toml").string() + " --out " +
                               (out / "study").string());
  EXPECT_EQ(s.status, 2) << s.output;
  EXPECT_NE(s.output.find("external.toml: the scene's soil is external (soil.model = "
                          "\"external\"): a study starts its own nodes and cannot reach that "
                          "program; run each case with master run --node soil=HOST:PORT"),
            std::string::npos)
      << s.output;
  EXPECT_FALSE(fs::exists(out / "study" / "plan.txt")) << "nothing may run";
  fs::remove_all(out);
}

// The FE soil is started by the master over TCP: in process it cannot run,
// nor be studied.
TEST(MasterCli, TheFeSoilNeedsTcp) {
  const fs::path out = temp_dir("cli_fe");
  std::ofstream(out / "fe.toml") << read_file(test::source_path("scenes/ground_vibration_ci.toml"));
  const Outcome o =
      run_master("run --scene " + (out / "fe.toml").string() +
                 " --case ss-xt-jacobi --transport inproc --out " + (out / "res").string());
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("the scene's soil is the FE soil (soil.model = \"fe\"), a program of "
                          "its own that the master starts over TCP: use --transport tcp (the "
                          "default), not --transport inproc"),
            std::string::npos)
      << o.output;
  const Outcome s = run_master("study --scene " + (out / "fe.toml").string() +
                               " --transport inproc --out " + (out / "study").string());
  EXPECT_EQ(s.status, 2) << s.output;
  EXPECT_NE(s.output.find("fe.toml: the scene's soil is the FE soil (soil.model = \"fe\"), a "
                          "program of its own that the study starts and reaches over TCP: use "
                          "--transport tcp (the default), not --transport inproc"),
            std::string::npos)
      << s.output;
  EXPECT_FALSE(fs::exists(out / "study" / "plan.txt")) << "nothing may run";
  const Outcome m = run_master("run --scene " + (out / "fe.toml").string() +
                               " --case monolithic --out " + (out / "res").string());
  EXPECT_NE(m.status, 0) << m.output;
  EXPECT_NE(m.output.find("there is no monolithic reference"), std::string::npos) << m.output;
  fs::remove_all(out);
}

// The soil from Green's functions, another soil the master starts: the same
// refusals, naming it by its row of the table of started soils.
TEST(MasterCli, TheGreenSoilNeedsTcp) {
  const fs::path out = temp_dir("cli_green");
  const std::string scene = test::source_path("scenes/ground_vibration_green_ci.toml");
  const Outcome o =
      run_master("run --scene " + scene + " --case ss-xt-jacobi --transport inproc --out " +
                 (out / "res").string());
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_NE(o.output.find("the scene's soil is the Green's-function soil (soil.model = "
                          "\"green\"), a program of its own that the master starts over TCP: use "
                          "--transport tcp"),
            std::string::npos)
      << o.output;
  const Outcome s = run_master("study --scene " + scene + " --transport inproc --out " +
                               (out / "study").string());
  EXPECT_EQ(s.status, 2) << s.output;
  EXPECT_NE(s.output.find("(soil.model = \"green\"), a program of its own that the study "
                          "starts and reaches over TCP"),
            std::string::npos)
      << s.output;
  fs::remove_all(out);
}

TEST(MasterCli, TcpRunAgainstNodesStartedByHand) {
  remote::LaunchedNode vehicle("vehicle_node", std::chrono::seconds(10));
  remote::LaunchedNode track("track_node", std::chrono::seconds(10));
  const fs::path out = temp_dir("cli_tcp");
  const Outcome o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                               " --case rs-xx-gauss-seidel --vehicle " + vehicle.address().str() +
                               " --track " + track.address().str() + " --out " + out.string());
  ASSERT_EQ(o.status, 0) << o.output;
  const std::string summary = read_file(out / "rs-xx-gauss-seidel" / "summary.json");
  EXPECT_NE(summary.find("\"transport\": \"tcp\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"status\": \"ok\""), std::string::npos) << summary;
  // The map and the probe build the scene's participants in process, not
  // what runs behind a node given by address: that run's stability is not
  // judged (no rho, no probe), only its own defect along the run.
  EXPECT_NE(summary.find("\"stability\": {\"verdict\": \"not judged\", \"basis\": \"\", "
                         "\"rho\": null"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"probe_s\": null, \"defect_growth\": "), std::string::npos) << summary;
  // Its errors are measured against the co-simulation of the same nodes
  // (implicit, substep waveforms, at H / 2), not the built-in monolithic run.
  EXPECT_NE(summary.find("\"reference\": {\"kind\": \"co-simulation\", \"macro_step_s\": 5e-05, "
                         "\"coupling\": \"implicit-waveform3-iqn-ils\""),
            std::string::npos)
      << summary;
  fs::remove_all(out);
}

// A long TCP run of rs-xx-jacobi against nodes started here, in the middle
// of which `signal` is sent to the track node.
struct FaultedRun {
  remote::LaunchedNode vehicle{"vehicle_node", std::chrono::seconds(10)};
  remote::LaunchedNode track{"track_node", std::chrono::seconds(10)};
  fs::path out;
  fs::path history;
  Outcome outcome;
  double seconds_to_exit = 0;

  FaultedRun(const std::string& name, int signal)
      : out(temp_dir(name)), history(out / "rs-xx-jacobi" / "history.csv") {
    // A fine macro step makes the run long enough to be caught in the middle.
    std::thread master = start_master_until(
        "run --scene " + test::source_path("scenes/paper.toml") +
            " --case rs-xx-jacobi --macro-step 1e-5 --vehicle " + vehicle.address().str() +
            " --track " + track.address().str() + " --out " + out.string(),
        history, 200, outcome);
    const auto at = std::chrono::steady_clock::now();
    ::kill(track.pid(), signal);
    master.join();
    seconds_to_exit = std::chrono::duration<double>(std::chrono::steady_clock::now() - at).count();
    if (signal == SIGSTOP) ::kill(track.pid(), SIGCONT);
  }
  ~FaultedRun() { fs::remove_all(out); }
};

TEST(MasterCli, ANodeKilledMidRunStopsTheMasterWithItsNameAddressAndStep) {
  const FaultedRun run("cli_kill", SIGKILL);
  const Outcome& o = run.outcome;
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_LT(run.seconds_to_exit, 5.0);
  EXPECT_NE(o.output.find("track node at " + run.track.address().str()), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("at macro step "), std::string::npos) << o.output;
  // The history up to the failure is on disk, and the summary says why.
  const std::string h = read_file(run.history);
  EXPECT_GT(std::count(h.begin(), h.end(), '\n'), 200);
  EXPECT_LT(std::count(h.begin(), h.end(), '\n'), 25002);
  const std::string summary = read_file(run.out / "rs-xx-jacobi" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("track node"), std::string::npos) << summary;
  // The macro steps done, one per history row after t = 0 (a failed run
  // once said 0).
  const long rows = json_long(summary, "history_rows");
  EXPECT_GT(rows, 200) << summary;
  EXPECT_EQ(json_long(summary, "macro_steps"), rows - 1) << summary;
}

TEST(MasterCli, AHungNodeIsReportedWithinSeconds) {
  // The node stops answering but keeps its connection open.
  const FaultedRun run("cli_hang", SIGSTOP);
  const Outcome& o = run.outcome;
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_LT(run.seconds_to_exit, 10.0);
  EXPECT_NE(o.output.find("track node at " + run.track.address().str() + ": no reply within"),
            std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("at macro step "), std::string::npos) << o.output;
}

TEST(MasterCli, AnInterruptedRunLeavesAFailedSummary) {
  const fs::path out = temp_dir("cli_sigint");
  const fs::path history = out / "rs-xx-jacobi" / "history.csv";
  Outcome o;
  std::thread master =
      start_master_until("run --scene " + test::source_path("scenes/paper.toml") +
                             " --case rs-xx-jacobi --macro-step 1e-5 --out " + out.string(),
                         history, 100, o);
  // The out folder names this master process alone.
  std::system(("pkill -INT -f -- '--out " + out.string() + "'").c_str());
  master.join();
  EXPECT_NE(o.status, 0) << o.output;
  const std::string summary = read_file(out / "rs-xx-jacobi" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("interrupted by signal 2 at macro step"), std::string::npos) << summary;
  const std::string h = read_file(history);
  EXPECT_GT(std::count(h.begin(), h.end(), '\n'), 100);
  fs::remove_all(out);
}

TEST(MasterCli, ANodeThatStartsLateIsWaitedFor) {
  // Find a free port, then start the track node on it a second after the master.
  std::string port;
  {
    remote::LaunchedNode probe("track_node", std::chrono::seconds(10));
    port = std::to_string(probe.address().port);
  }
  remote::LaunchedNode vehicle("vehicle_node", std::chrono::seconds(10));
  const fs::path out = temp_dir("cli_late");
  Outcome o;
  std::thread master([&] {
    o = run_master("run --scene " + test::source_path("scenes/paper.toml") +
                   " --case wr-xx-gauss-seidel --vehicle " + vehicle.address().str() +
                   " --track 127.0.0.1:" + port + " --out " + out.string());
  });
  std::this_thread::sleep_for(std::chrono::seconds(1));
  remote::LaunchedNode track("track_node", std::chrono::seconds(10), "127.0.0.1:" + port);
  master.join();
  EXPECT_EQ(o.status, 0) << o.output;
  fs::remove_all(out);
}

}  // namespace
}  // namespace railcosim
