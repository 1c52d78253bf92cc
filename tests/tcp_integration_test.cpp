// Cases over real TCP, against real node processes (one per participant),
// bitwise equal to their in-process twins: every case of the paper scene,
// three-participant cases of the soil scene, and a master run given a soil
// node the test started. Then how the master reports nodes that misbehave.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "cosim_support.hpp"
#include "one_shot_peer.hpp"
#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using remote::DataPlane;
using remote::inproc_factory;
using remote::LaunchedNode;
using remote::NodeFailure;
using remote::NodePool;
using remote::RemoteParticipant;
using remote::RemoteTimeouts;
using remote::tcp_transport;

namespace fs = std::filesystem;

// The soil scene shortened to 0.05 s (500 macro steps of 1e-4 s): long
// enough for the wheel to cross three sleeper bays and the soil to respond,
// short enough that the three-participant cases add about a second each.
constexpr double kSoilEndTime = 0.05;

Scene soil_scene() {
  return with_keys(load_scene(test::source_path("scenes/soil.toml")),
                   {{"simulation.end_time", kSoilEndTime}});
}

using test::config_of;

// Runs a case in-process and over TCP and expects the same record bit for bit.
void expect_tcp_equals_inproc(const Scene& scene, const std::string& name, Feedthrough feedthrough,
                              NodePool& pool, DataPlane plane = DataPlane::kDirect,
                              long window_steps = 0) {
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  o.feedthrough = feedthrough;
  o.data_plane = plane;
  o.direct.window_steps = window_steps;
  const CaseSpec spec = parse_case(name);
  const run::RunRecord local = run::run_cosim(scene, spec, o, inproc_factory(scene), "inproc");
  const run::RunRecord remote =
      run::run_cosim(scene, spec, o, tcp_transport(scene, {}, pool).factory, "tcp");
  ASSERT_EQ(remote.status, local.status) << remote.message;
  EXPECT_EQ(remote.macro_steps, local.macro_steps);
  EXPECT_EQ(remote.macro_steps, scene.macro_steps());
  EXPECT_EQ(remote.micro_steps, local.micro_steps);
  EXPECT_EQ(remote.micro_steps.size(), spec.cuts.size() + 1);  // one count per participant
  ASSERT_EQ(remote.deflection.size(), local.deflection.size());
  EXPECT_EQ(remote.deflection, local.deflection);  // exact double equality
  EXPECT_EQ(remote.soil, local.soil);
  EXPECT_EQ(remote.extra_channels, local.extra_channels);
  ASSERT_EQ(remote.history.size(), local.history.size());
  for (std::size_t i = 0; i < local.history.size(); ++i) {
    EXPECT_EQ(remote.history[i].t, local.history[i].t) << i;
    EXPECT_EQ(remote.history[i].wheel, local.history[i].wheel) << i;
    EXPECT_EQ(remote.history[i].contact_force, local.history[i].contact_force) << i;
    EXPECT_EQ(remote.history[i].extra, local.history[i].extra) << i;
  }
  EXPECT_EQ(remote.transport, "tcp");
  EXPECT_EQ(remote.data_plane, to_string(plane));
}

std::string test_name(const char* case_name, Feedthrough f) {
  std::string n = std::string(case_name) + "_" + to_string(f);
  for (char& ch : n)
    if (ch == '-' || ch == '+') ch = '_';
  return n;
}

class TcpIntegration : public ::testing::TestWithParam<std::pair<const char*, Feedthrough>> {
 protected:
  // One node per role serves every case of the suite, session after session.
  static void SetUpTestSuite() { pool_ = std::make_unique<NodePool>(); }
  static void TearDownTestSuite() { pool_.reset(); }
  static inline std::unique_ptr<NodePool> pool_;
};

// Direct data plane: the nodes exchange with each other in one window.
TEST_P(TcpIntegration, PaperCaseBitwiseEqualToInProcess) {
  expect_tcp_equals_inproc(test::paper_scene(), GetParam().first, GetParam().second, *pool_);
}

// The master relays every value, one request per macro step.
TEST_P(TcpIntegration, PaperCaseRelayedBitwiseEqualToInProcess) {
  expect_tcp_equals_inproc(test::paper_scene(), GetParam().first, GetParam().second, *pool_,
                           DataPlane::kRelay);
}

// Windows of 7 macro steps (2500 is not a multiple): the nodes carry their
// state and the data in flight from one window to the next.
TEST(TcpWindows, ManyWindowsBitwiseEqualToInProcess) {
  NodePool pool;
  expect_tcp_equals_inproc(test::paper_scene(), "rs-xt-gauss-seidel", Feedthrough::kLagged, pool,
                           DataPlane::kDirect, 7);
  expect_tcp_equals_inproc(test::paper_scene(), "wr-xt-jacobi", Feedthrough::kResolved, pool,
                           DataPlane::kDirect, 7);
}

INSTANTIATE_TEST_SUITE_P(AllCases, TcpIntegration,
                         ::testing::Values(std::pair{"wr-xx-jacobi", Feedthrough::kLagged},
                                           std::pair{"wr-xx-gauss-seidel", Feedthrough::kLagged},
                                           std::pair{"wr-xt-jacobi", Feedthrough::kLagged},
                                           std::pair{"wr-xt-jacobi", Feedthrough::kResolved},
                                           std::pair{"wr-xt-gauss-seidel", Feedthrough::kLagged},
                                           std::pair{"rs-xx-jacobi", Feedthrough::kLagged},
                                           std::pair{"rs-xx-gauss-seidel", Feedthrough::kLagged},
                                           std::pair{"rs-xt-jacobi", Feedthrough::kLagged},
                                           std::pair{"rs-xt-gauss-seidel", Feedthrough::kLagged}),
                         [](const auto& param_info) {
                           return test_name(param_info.param.first, param_info.param.second);
                         });

// Three participants (vehicle | track | soil), each in its own node process.
class TcpSoil : public TcpIntegration {};

TEST_P(TcpSoil, ThreeNodesBitwiseEqualToInProcess) {
  expect_tcp_equals_inproc(soil_scene(), GetParam().first, GetParam().second, *pool_);
}

TEST_P(TcpSoil, ThreeNodesRelayedBitwiseEqualToInProcess) {
  expect_tcp_equals_inproc(soil_scene(), GetParam().first, GetParam().second, *pool_,
                           DataPlane::kRelay);
}

INSTANTIATE_TEST_SUITE_P(
    SoilCases, TcpSoil,
    ::testing::Values(std::pair{"wr-xx+ss-xx-jacobi", Feedthrough::kLagged},
                      std::pair{"wr-xt+ss-xt-gauss-seidel", Feedthrough::kLagged},
                      std::pair{"wr-xt+ss-xt-jacobi", Feedthrough::kResolved},
                      std::pair{"wr-xx+rs-xx+ss-xx-gauss-seidel", Feedthrough::kLagged}),
    [](const auto& param_info) {
      return test_name(param_info.param.first, param_info.param.second);
    });

// --- the master program, given a soil node ---------------------------------

using test::Outcome;
using test::run_master;

std::string file_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(TcpMaster, ARunWithAGivenSoilNodeEqualsTheInProcessRun) {
  const fs::path dir =
      fs::temp_directory_path() / ("railcosim_given_soil_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A scene copy with the shortened end time.
  std::string scene_text = file_text(test::source_path("scenes/soil.toml"));
  const std::string key = "end_time = 0.25";
  const auto at = scene_text.find(key);
  ASSERT_NE(at, std::string::npos) << "scenes/soil.toml no longer says " << key;
  scene_text.replace(at, key.size(), "end_time = 0.05");
  const fs::path scene = dir / "soil.toml";
  std::ofstream(scene) << scene_text;

  const std::string c = "wr-xx+ss-xt-gauss-seidel";
  {
    LaunchedNode soil("soil_node", std::chrono::seconds(10));
    const Outcome tcp = run_master("run --scene " + scene.string() + " --case " + c +
                                   " --node soil=" + soil.address().str() + " --verbose --out " +
                                   (dir / "tcp").string());
    ASSERT_EQ(tcp.status, 0) << tcp.output;
    // The master started the vehicle and track nodes, and no soil node of its own.
    EXPECT_NE(tcp.output.find("started vehicle_node"), std::string::npos) << tcp.output;
    EXPECT_NE(tcp.output.find("started track_node"), std::string::npos) << tcp.output;
    EXPECT_EQ(tcp.output.find("started soil_node"), std::string::npos) << tcp.output;
  }
  const Outcome local = run_master("run --scene " + scene.string() + " --case " + c +
                                   " --transport inproc --out " + (dir / "inproc").string());
  ASSERT_EQ(local.status, 0) << local.output;
  for (const char* f : {"deflection.csv", "history.csv", "soil.csv"}) {
    const std::string a = file_text(dir / "tcp" / c / f), b = file_text(dir / "inproc" / c / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, b) << f << " over TCP differs from the in-process run";
  }
  EXPECT_NE(file_text(dir / "tcp" / c / "summary.json").find("\"transport\": \"tcp\""),
            std::string::npos);
  fs::remove_all(dir);
}

// --- nodes that misbehave ---------------------------------------------------

// Its word alone (nothing has grown: a tolerance no step can meet) ends the
// run failed, naming the node, not diverged.
TEST(TcpNodes, ANodeThatGivesUpOnAStepWhileNothingGrowsMakesTheRunFailed) {
  const Scene scene = with_keys(test::paper_scene(), {{"simulation.end_time", 0.001}});
  NodePool pool;
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = 1e-30;  // no step can meet it
  const run::RunRecord r = run::run_cosim(scene, parse_case("wr-xx-gauss-seidel"), o,
                                          tcp_transport(scene, {}, pool).factory, "tcp");
  EXPECT_EQ(r.status, "failed");
  EXPECT_NE(r.message.find("micro steps"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("node at 127.0.0.1:"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("not judged diverged"), std::string::npos) << r.message;
}

TEST(TcpNodes, GarbageFromANodeIsAFailureNamingIt) {
  const Scene scene = test::paper_scene();
  test::OneShotPeer fake(std::string("\0\0\0\6garbag", 10));
  try {
    RemoteParticipant p(fake.address(), scene, config_of(scene, "wr-xx-jacobi", "track"));
    FAIL() << "accepted garbage as a hello reply";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("track node at " + fake.address().str()), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a message"), std::string::npos) << msg;
  }
}

TEST(TcpNodes, ANodeThatNeverAnswersTheHelloTimesOut) {
  const Scene scene = test::paper_scene();
  test::OneShotPeer fake("");
  RemoteTimeouts t;
  t.reply = std::chrono::milliseconds(300);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    RemoteParticipant p(fake.address(), scene, config_of(scene, "wr-xx-jacobi", "vehicle"), t);
    FAIL() << "no timeout";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("vehicle node at " + fake.address().str()), std::string::npos) << msg;
    EXPECT_NE(msg.find("no reply within 300 ms"), std::string::npos) << msg;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

TEST(TcpNodes, ANodeOfTheWrongRoleIsNamedInTheError) {
  const Scene scene = soil_scene();
  LaunchedNode track("track_node", std::chrono::seconds(10));
  try {
    RemoteParticipant p(track.address(), scene, config_of(scene, "ss-xx-jacobi", "soil"));
    FAIL() << "connected to a track node as the soil";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("soil node at " + track.address().str()), std::string::npos) << msg;
    EXPECT_NE(msg.find("WRONG_ROLE"), std::string::npos) << msg;
    // The node's own words name both participants.
    EXPECT_NE(msg.find("serves the track participant, not the soil"), std::string::npos) << msg;
  }
}

TEST(TcpNodes, AnUnreachableNodeIsNamedWithItsAddress) {
  const Scene scene = test::paper_scene();
  RemoteTimeouts t;
  t.connect = std::chrono::milliseconds(300);
  try {
    // Port 1 on loopback: nothing listens there.
    RemoteParticipant p({"127.0.0.1", 1}, scene, config_of(scene, "wr-xx-jacobi", "track"), t);
    FAIL() << "connected to nothing";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("track node"), std::string::npos) << msg;
    EXPECT_NE(msg.find("127.0.0.1:1"), std::string::npos) << msg;
  }
}

// A session in progress holds a node (BUSY to everyone else; a connection
// that only says nothing does not: the node takes several hellos side by
// side). The master asks again while the node is busy: the run goes on
// once the other session leaves (it once failed at the first BUSY) ...
TEST(TcpNodes, TheMasterAsksABusyNodeAgainUntilTheBlockerLeaves) {
  const Scene scene = test::paper_scene();
  LaunchedNode track("track_node", std::chrono::seconds(10));
  auto blocker = std::make_unique<RemoteParticipant>(track.address(), scene,
                                                     config_of(scene, "wr-xx-jacobi", "track"));
  std::thread leave([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    blocker.reset();
  });
  const auto t0 = std::chrono::steady_clock::now();
  try {
    RemoteParticipant p(track.address(), scene, config_of(scene, "wr-xx-jacobi", "track"));
    EXPECT_EQ(p.channels().results.size(), 1u);
  } catch (const NodeFailure& e) {
    ADD_FAILURE() << e.what();
  }
  leave.join();
  EXPECT_GT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(400));
}

// ... and gives up after the stated time, naming the node and its address.
TEST(TcpNodes, ANodeBusyForLongerThanTheRetryTimeIsNamed) {
  const Scene scene = test::paper_scene();
  LaunchedNode track("track_node", std::chrono::seconds(10));
  const RemoteParticipant blocker(track.address(), scene,
                                  config_of(scene, "wr-xx-jacobi", "track"));
  RemoteTimeouts t;
  t.busy = std::chrono::milliseconds(500);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    RemoteParticipant p(track.address(), scene, config_of(scene, "wr-xx-jacobi", "track"), t);
    ADD_FAILURE() << "a busy node took the session";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("track node at " + track.address().str() + ": hello failed: BUSY"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("asked again for 500 ms"), std::string::npos) << msg;
  }
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GT(took, std::chrono::milliseconds(400));
  EXPECT_LT(took, std::chrono::milliseconds(2000));
}

}  // namespace
}  // namespace railcosim
