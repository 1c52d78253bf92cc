// Every case of the paper scene over real TCP, against real node processes,
// bitwise equal to its in-process twin.
#include <gtest/gtest.h>

#include <memory>
#include <thread>

#include "evaluation.hpp"
#include "node_launcher.hpp"
#include "remote_participant.hpp"
#include "runner.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

struct Nodes {
  LaunchedNode vehicle{"vehicle_node", std::chrono::seconds(10)};
  LaunchedNode track{"track_node", std::chrono::seconds(10)};
};

class TcpIntegration : public ::testing::TestWithParam<std::pair<const char*, Feedthrough>> {
 protected:
  // One pair of nodes serves every case, session after session.
  static void SetUpTestSuite() { nodes_ = std::make_unique<Nodes>(); }
  static void TearDownTestSuite() { nodes_.reset(); }
  static inline std::unique_ptr<Nodes> nodes_;
};

TEST_P(TcpIntegration, BitwiseEqualToInProcess) {
  const Scene scene = test::paper_scene();
  const auto [name, feedthrough] = GetParam();
  RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  o.feedthrough = feedthrough;
  const Address vehicle = nodes_->vehicle.address(), track = nodes_->track.address();
  const ParticipantFactory tcp = [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<RemoteParticipant>(c.side == Side::kS1 ? vehicle : track, scene, c);
  };
  const CaseSpec spec = parse_case(name);
  const RunRecord local = run_cosim(scene, spec, o, inproc_factory(scene), "inproc");
  const RunRecord remote = run_cosim(scene, spec, o, tcp, "tcp");
  ASSERT_EQ(remote.status, local.status) << remote.message;
  EXPECT_EQ(remote.macro_steps, local.macro_steps);
  EXPECT_EQ(remote.micro_steps, local.micro_steps);
  ASSERT_EQ(remote.deflection.size(), local.deflection.size());
  EXPECT_EQ(remote.deflection, local.deflection);  // exact double equality
  ASSERT_EQ(remote.history.size(), local.history.size());
  for (std::size_t i = 0; i < local.history.size(); ++i) {
    EXPECT_EQ(remote.history[i].t, local.history[i].t) << i;
    EXPECT_EQ(remote.history[i].wheel, local.history[i].wheel) << i;
    EXPECT_EQ(remote.history[i].contact_force, local.history[i].contact_force) << i;
  }
  EXPECT_EQ(remote.transport, "tcp");
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
                           std::string n = std::string(param_info.param.first) + "_" +
                                           to_string(param_info.param.second);
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

TEST(TcpNodes, ANodeThatGivesUpOnAStepMakesTheRunDiverged) {
  Scene scene = test::paper_scene();
  scene.end_time = 0.001;
  LaunchedNode vehicle("vehicle_node", std::chrono::seconds(10));
  LaunchedNode track("track_node", std::chrono::seconds(10));
  RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = 1e-30;  // no step can meet it
  const Address va = vehicle.address(), ta = track.address();
  const ParticipantFactory tcp = [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<RemoteParticipant>(c.side == Side::kS1 ? va : ta, scene, c);
  };
  const RunRecord r = run_cosim(scene, parse_case("wr-xx-gauss-seidel"), o, tcp, "tcp");
  EXPECT_EQ(r.status, "diverged");
  EXPECT_NE(r.message.find("micro steps"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("node"), std::string::npos) << r.message;
}

// A fake node: accepts one connection, reads whatever comes, and answers
// with `reply` (nothing at all if empty), then keeps the connection open.
class FakeNode {
 public:
  explicit FakeNode(std::string reply) : reply_(std::move(reply)), acceptor_(io_) {
    using boost::asio::ip::tcp;
    acceptor_.open(tcp::v4());
    acceptor_.bind({boost::asio::ip::make_address("127.0.0.1"), 0});
    acceptor_.listen();
    thread_ = std::thread([this] {
      boost::system::error_code ec;
      tcp::socket s(io_);
      acceptor_.accept(s, ec);
      if (ec) return;
      char buf[4096];
      s.read_some(boost::asio::buffer(buf), ec);  // the hello
      if (!reply_.empty()) boost::asio::write(s, boost::asio::buffer(reply_), ec);
      while (!ec) s.read_some(boost::asio::buffer(buf), ec);  // until the master hangs up
    });
  }
  ~FakeNode() {
    boost::system::error_code ec;
    acceptor_.close(ec);
    thread_.join();
  }
  Address address() const { return {"127.0.0.1", acceptor_.local_endpoint().port()}; }

 private:
  std::string reply_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::thread thread_;
};

TEST(TcpNodes, GarbageFromANodeIsAFailureNamingIt) {
  const Scene scene = test::paper_scene();
  FakeNode fake(std::string("\0\0\0\6garbag", 10));
  try {
    RemoteParticipant p(
        fake.address(), scene,
        {Split::kWheelRail, Side::kS2, Coupling::kXX, scene.macro_step, scene.tolerance});
    FAIL() << "accepted garbage as a hello reply";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("track node at " + fake.address().str()), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a message"), std::string::npos) << msg;
  }
}

TEST(TcpNodes, ANodeThatNeverAnswersTheHelloTimesOut) {
  const Scene scene = test::paper_scene();
  FakeNode fake("");
  RemoteTimeouts t;
  t.reply = std::chrono::milliseconds(300);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    RemoteParticipant p(
        fake.address(), scene,
        {Split::kWheelRail, Side::kS1, Coupling::kXX, scene.macro_step, scene.tolerance}, t);
    FAIL() << "no timeout";
  } catch (const NodeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("no reply within 300 ms"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

TEST(TcpNodes, ANodeOfTheWrongRoleIsNamedInTheError) {
  const Scene scene = test::paper_scene();
  LaunchedNode track("track_node", std::chrono::seconds(10));
  try {
    RemoteParticipant p(
        track.address(), scene,
        {Split::kWheelRail, Side::kS1, Coupling::kXX, scene.macro_step, scene.tolerance});
    FAIL() << "connected to a track node as the vehicle";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("vehicle node at " + track.address().str()), std::string::npos) << msg;
    EXPECT_NE(msg.find("WRONG_ROLE"), std::string::npos) << msg;
  }
}

TEST(TcpNodes, AnUnreachableNodeIsNamedWithItsAddress) {
  const Scene scene = test::paper_scene();
  RemoteTimeouts t;
  t.connect = std::chrono::milliseconds(300);
  try {
    // Port 1 on loopback: nothing listens there.
    RemoteParticipant p(
        {"127.0.0.1", 1}, scene,
        {Split::kWheelRail, Side::kS2, Coupling::kXX, scene.macro_step, scene.tolerance}, t);
    FAIL() << "connected to nothing";
  } catch (const NodeFailure& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("track node"), std::string::npos) << msg;
    EXPECT_NE(msg.find("127.0.0.1:1"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace railcosim
