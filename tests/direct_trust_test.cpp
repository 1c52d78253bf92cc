// The master on the direct data plane against a node that keeps its report
// stream busy without reporting a step: one byte every 0.5 s, or an empty
// Reports frame every second. The deadline is for the next step report, so
// the master fails on its own naming that node, and a signal ends the wait.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <thread>

#include "fake_node.hpp"
#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

extern char** environ;

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

// Sleeps `t` in slices; false once `stop` is set.
bool nap(milliseconds t, const std::atomic<bool>& stop) {
  for (auto slept = milliseconds(0); slept < t; slept += milliseconds(20)) {
    if (stop) return false;
    std::this_thread::sleep_for(milliseconds(20));
  }
  return !stop;
}

bool send_bytes(int fd, const char* data, std::size_t size) {
  return ::send(fd, data, size, MSG_NOSIGNAL) == static_cast<ssize_t>(size);
}

// Passes report frames on until one reports macro step 20, then trickles
// (`trickling` is set when the trickle begins):
// the next frame one byte every 0.5 s (`bytes`), or an empty Reports frame
// every second.
test::FakeNode::Reports trickle_after_step_20(bool bytes, std::atomic<bool>& trickling) {
  return [bytes, &trickling](int fd, const std::string& frame, const std::atomic<bool>& stop) {
    if (!trickling) {
      wire::Envelope e;
      e.ParseFromArray(frame.data() + 4, static_cast<int>(frame.size() - 4));
      send_bytes(fd, frame.data(), frame.size());
      bool past = false;
      for (const auto& r : e.reports().reports()) past = past || r.step() >= 20;
      if (!past) return;
      trickling = true;
      wire::Envelope empty;
      empty.set_id(e.id());
      empty.mutable_reports();
      const std::string idle = encode_frame(empty);
      if (bytes)
        for (std::size_t k = 0; k < idle.size() && nap(milliseconds(500), stop); ++k)
          send_bytes(fd, &idle[k], 1);
      else
        while (nap(milliseconds(1000), stop) && send_bytes(fd, idle.data(), idle.size())) {
        }
    }
  };
}

// wr-xx-jacobi on the paper scene: the vehicle on the fake node, the track
// on a real one, step deadlines within [0.5 s, 3 s]. Returns the failure's
// message and the run's seconds (a few milliseconds of steps, then the wait).
std::pair<std::string, double> run_against_trickle(bool bytes) {
  std::atomic<bool> trickling{false};
  test::FakeNode vehicle("vehicle", nullptr, {}, trickle_after_step_20(bytes, trickling));
  remote::LaunchedNode track("track_node", milliseconds(10000));
  const Scene scene = test::paper_scene();
  remote::RemoteTimeouts t;
  t.step_min = milliseconds(500);
  t.step_max = milliseconds(3000);
  const remote::ParticipantFactory make =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    const Address& at = c.participant.role == "vehicle" ? vehicle.address() : track.address();
    return std::make_unique<remote::RemoteParticipant>(at, scene, c, t);
  };
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  const auto t0 = Clock::now();
  try {
    run::run_cosim(scene, parse_case("wr-xx-jacobi"), o, make, "tcp");
  } catch (const remote::NodeFailure& e) {
    const std::string m = e.what();
    EXPECT_TRUE(trickling);
    EXPECT_NE(m.find("vehicle node at " + vehicle.address().str() + ": no reply within "),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("the track participant(s) wait for its data"), std::string::npos) << m;
    // The step is named once (it said "its last step report was for macro
    // step 20 ... at macro step 20").
    EXPECT_NE(m.find("ms (its step reports reached this macro step; "), std::string::npos) << m;
    EXPECT_EQ(m.find("its last step report was for"), std::string::npos) << m;
    return {m, std::chrono::duration<double>(Clock::now() - t0).count()};
  }
  ADD_FAILURE() << "the run went through";
  return {"", 0};
}

TEST(DirectTrust, ANodeTricklingBytesIsNamedAfterTheStepDeadline) {
  const auto [m, seconds] = run_against_trickle(true);
  EXPECT_NE(m.find("byte(s) of a frame it has not finished"), std::string::npos) << m;
  // At most the 3 s deadline from the last step report (bytes do not extend it).
  EXPECT_LT(seconds, 4.0) << m;
}

TEST(DirectTrust, ANodeSendingEmptyReportFramesIsNamedAfterTheStepDeadline) {
  const auto [m, seconds] = run_against_trickle(false);
  EXPECT_NE(m.find("report frame(s) without a step report"), std::string::npos) << m;
  EXPECT_LT(seconds, 4.0) << m;
}

// A vehicle node whose report stream stops after macro step 20 while it runs
// its window to the end: the master names it, not the track node (it once
// granted a new window and blamed OUT_OF_ORDER on whichever node came first).
TEST(DirectTrust, ANodeWhoseReportsStopShortIsNamed) {
  test::FakeNode vehicle("vehicle", nullptr, {},
                         [](int fd, const std::string& frame, const std::atomic<bool>&) {
                           wire::Envelope e;
                           e.ParseFromArray(frame.data() + 4, static_cast<int>(frame.size() - 4));
                           for (const auto& r : e.reports().reports())
                             if (r.step() > 20) return;
                           send_bytes(fd, frame.data(), frame.size());
                         });
  remote::LaunchedNode track("track_node", milliseconds(10000));
  Scene scene = test::paper_scene();
  scene = with_keys(scene, {{"simulation.end_time", 200 * scene.macro_step}});
  const remote::ParticipantFactory make =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    const Address& at = c.participant.role == "vehicle" ? vehicle.address() : track.address();
    return std::make_unique<remote::RemoteParticipant>(at, scene, c);
  };
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  try {
    run::run_cosim(scene, parse_case("wr-xx-jacobi"), o, make, "tcp");
    ADD_FAILURE() << "the run went through";
  } catch (const remote::NodeFailure& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("vehicle node at " + vehicle.address().str() +
                     ": its window ended at macro step 200, but its step reports stop at "
                     "macro step "),
              std::string::npos)
        << m;
    EXPECT_EQ(m.find("OUT_OF_ORDER"), std::string::npos) << m;
  }
}

// A vehicle node (wr-xx+ss-xx-jacobi: vehicle | track | soil) that passes
// its report frames on up to macro step 5, then withholds them (while its
// session runs on, sending its peer its data) and, with its last frame of
// the window, says it waits for the soil and holds its WindowDone back. The
// soil's own reports reach the window's end: the master names the vehicle,
// whose claim they refute, not the soil (it named the soil).
TEST(DirectTrust, ANodeFalselyClaimingToWaitForAPeerIsNamedNotThePeer) {
  constexpr long steps = 200;
  test::FakeNode vehicle("vehicle", nullptr, {},
                         [](int fd, const std::string& frame, const std::atomic<bool>& stop) {
                           wire::Envelope e;
                           e.ParseFromArray(frame.data() + 4, static_cast<int>(frame.size() - 4));
                           wire::Envelope early;  // its reports up to macro step 5
                           early.set_id(e.id());
                           early.mutable_reports();
                           long last = 0;
                           for (const auto& r : e.reports().reports()) {
                             last = std::max(last, static_cast<long>(r.step()));
                             if (r.step() <= 5) *early.mutable_reports()->add_reports() = r;
                           }
                           if (early.reports().reports_size() > 0) {
                             const std::string f = encode_frame(early);
                             send_bytes(fd, f.data(), f.size());
                           }
                           if (last < steps) return;
                           wire::Envelope claim;
                           claim.set_id(e.id());
                           claim.mutable_reports()->set_waiting_for("soil");
                           const std::string c = encode_frame(claim);
                           send_bytes(fd, c.data(), c.size());
                           while (nap(milliseconds(100), stop)) {
                           }
                         });
  remote::LaunchedNode track("track_node", milliseconds(10000));
  remote::LaunchedNode soil("soil_node", milliseconds(10000));
  Scene scene = load_scene(test::source_path("scenes/soil.toml"));
  scene = with_keys(scene, {{"simulation.end_time", steps * scene.macro_step}});
  remote::RemoteTimeouts t;
  t.step_min = milliseconds(500);
  t.step_max = milliseconds(3000);
  const remote::ParticipantFactory make =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    const std::string& role = c.participant.role;
    const Address& at = role == "soil"      ? soil.address()
                        : role == "vehicle" ? vehicle.address()
                                            : track.address();
    return std::make_unique<remote::RemoteParticipant>(at, scene, c, t);
  };
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  try {
    run::run_cosim(scene, parse_case("wr-xx+ss-xx-jacobi"), o, make, "tcp");
    ADD_FAILURE() << "the run went through";
  } catch (const remote::NodeFailure& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("vehicle node at " + vehicle.address().str() + ": no reply within "),
              std::string::npos)
        << m;
    // The failure names macro step 5 once: the node's reports reached it.
    EXPECT_NE(m.find("its step reports reached this macro step; it says it waits for the "
                     "soil participant, with which it has no peer link"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find(") at macro step 5 (t = 0.0005 s)"), std::string::npos) << m;
  }
}

// The master program: on its own it fails within the documented step
// deadline (50 times the slowest step, within [2 s, 30 s]; here about 3 s)
// naming the node, and writes
// summary.json; with SIGINT it stops within a second.
struct TrickledMaster {
  std::atomic<bool> trickling{false};
  test::FakeNode vehicle{"vehicle", nullptr, {}, trickle_after_step_20(true, trickling)};
  remote::LaunchedNode track{"track_node", milliseconds(10000)};
  fs::path out;
  pid_t pid = 0;
  explicit TrickledMaster(const std::string& name) : out(test::temp_dir(name)) {
    const std::string master = std::string(RAILCOSIM_BIN_DIR) + "/master";
    std::vector<std::string> args = {master,    "run",
                                     "--scene", test::source_path("scenes/paper.toml"),
                                     "--case",  "wr-xx-jacobi",
                                     "--node",  "vehicle=" + vehicle.address().str(),
                                     "--node",  "track=" + track.address().str(),
                                     "--out",   out.string()};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn(&pid, master.c_str(), nullptr, nullptr, argv.data(), environ);
    const auto t0 = Clock::now();
    while (!trickling && Clock::now() - t0 < std::chrono::seconds(20))
      std::this_thread::sleep_for(milliseconds(5));
  }
  // Waits for the master; its exit status and the seconds it took.
  std::pair<int, double> wait() {
    const auto t0 = Clock::now();
    int status = 0;
    ::waitpid(pid, &status, 0);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1,
            std::chrono::duration<double>(Clock::now() - t0).count()};
  }
  std::string summary() const { return test::read_file(out / "wr-xx-jacobi" / "summary.json"); }
  ~TrickledMaster() { fs::remove_all(out); }
};

TEST(DirectTrust, TheMasterFailsOnItsOwnNamingATricklingNodeAndWritesTheSummary) {
  TrickledMaster run("trickle_own");
  ASSERT_TRUE(run.trickling);
  const auto [status, seconds] = run.wait();
  EXPECT_EQ(status, 1);
  EXPECT_LT(seconds, 5.0);
  const std::string s = run.summary();
  EXPECT_NE(s.find("\"status\": \"failed\""), std::string::npos) << s;
  EXPECT_NE(s.find("vehicle node at " + run.vehicle.address().str() + ": no reply within "),
            std::string::npos)
      << s;
}

TEST(DirectTrust, SigintStopsAMasterWaitingOnATricklingNodeWithinASecond) {
  TrickledMaster run("trickle_sigint");
  ASSERT_TRUE(run.trickling);
  std::this_thread::sleep_for(milliseconds(300));
  ::kill(run.pid, SIGINT);
  const auto [status, seconds] = run.wait();
  EXPECT_EQ(status, 1);
  EXPECT_LT(seconds, 1.0);
  const std::string s = run.summary();
  EXPECT_NE(s.find("\"status\": \"failed\""), std::string::npos) << s;
  EXPECT_NE(s.find("interrupted by signal 2 at macro step"), std::string::npos) << s;
}

}  // namespace
}  // namespace railcosim
