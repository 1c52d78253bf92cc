// A node as any client sees it: a real TCP server on loopback, driven through
// real sockets, bad frames included.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "connection.hpp"
#include "cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "remote/remote_participant.hpp"
#include "server.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;

// Inputs of the right shape for a participant, every value non-zero so that
// the participant really moves.
CouplingData some_inputs(const Scene& scene, const ParticipantSpec& p, double scale) {
  CouplingData in = engine::zero_inputs(scene, p);
  for (InterfaceData& i : in) {
    for (double& x : i.displacement) x = 1e-3 * scale;
    for (double& x : i.velocity) x = 1e-2 * scale;
    for (double& x : i.force) x = 5e4 * scale;
  }
  return in;
}

// Serves the `role()` participant; the sessions that still work after an
// error drive participant `session_participant()` of `session_case()`.
class NodeTest : public ::testing::Test {
 protected:
  virtual std::string role() const { return "track"; }
  virtual Scene scene() const { return test::paper_scene(); }
  virtual const char* session_case() const { return "rs-xx-jacobi"; }

  void SetUp() override {
    NodeOptions o;
    o.role = role();
    ServerLimits limits;
    limits.max_frame_bytes = 1 << 16;
    limits.idle_timeout = milliseconds(1500);
    limits.handshake_timeout = milliseconds(500);
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0}, limits);
    thread_ = std::thread([this] { server_->run(false); });
    address_ = server_->local_address();
    scene_ = scene();
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }

  std::unique_ptr<Connection> connect() {
    return Connection::connect(address_, milliseconds(5000));
  }

  wire::Envelope hello(const std::string& participant,
                       std::uint32_t version = kProtocolVersion) const {
    return hello_envelope(participant, scene_fingerprint(scene_), version);
  }
  wire::Envelope hello() const { return hello(role()); }

  // The configuration of the participant named `role` in a case.
  SubsystemConfig config(const char* case_name, const std::string& participant) const {
    return test::config_of(scene_, case_name, participant);
  }

  // Hello, then configure with `conf`; expects Configured.
  void open(Connection& c, const wire::Envelope& conf) {
    c.send(hello());
    ASSERT_TRUE(c.receive(milliseconds(5000)).has_hello_reply());
    c.send(conf);
    const wire::Envelope r = c.receive(milliseconds(5000));
    ASSERT_TRUE(r.has_configured()) << body_name(r) << " " << r.ShortDebugString();
  }

  // Expects the next frame to be an error with `code`, then the end of the
  // session; returns the error's message.
  std::string expect_error_then_close(Connection& c, wire::Error::Code code) {
    const wire::Envelope reply = c.receive(milliseconds(5000));
    EXPECT_TRUE(reply.has_error()) << body_name(reply);
    EXPECT_EQ(reply.error().code(), code)
        << wire::Error::Code_Name(reply.error().code()) << ": " << reply.error().message();
    EXPECT_FALSE(reply.error().message().empty());
    EXPECT_THROW(c.receive(milliseconds(5000)), NetError);  // closed
    return reply.error().message();
  }

  // A whole short session through the master's own proxy, bitwise equal to
  // an in-process twin: the node still serves.
  void expect_a_session_still_works() {
    const SubsystemConfig cfg = config(session_case(), role());
    remote::RemoteParticipant remote(address_, scene_, cfg);
    Subsystem local(scene_, cfg);
    EXPECT_EQ(remote.channels().history, local.channels().history);
    EXPECT_EQ(remote.channels().results, local.channels().results);
    const CouplingData in = some_inputs(scene_, cfg.participant, 1.0);
    EXPECT_EQ(remote.statics(in), local.statics(in));
    const StepResult r0 = remote.initialize(in), l0 = local.initialize(in);
    EXPECT_EQ(r0.outputs, l0.outputs);
    EXPECT_EQ(r0.history, l0.history);
    for (long n = 0; n < 3; ++n) {
      const CouplingData held = some_inputs(scene_, cfg.participant, 1.0 + 0.1 * n);
      remote.set_inputs(n, held);
      local.set_inputs(n, held);
      const StepResult r = remote.step(n), l = local.step(n);
      EXPECT_EQ(r.outputs, l.outputs);
      EXPECT_EQ(r.history, l.history);
    }
    EXPECT_EQ(remote.save(), local.save());
    EXPECT_EQ(remote.results().fields, local.results().fields);
  }

  std::unique_ptr<NodeServer> server_;
  std::thread thread_;
  Address address_;
  Scene scene_;
};

TEST_F(NodeTest, OversizedFrameGetsAnErrorAndTheNodeServesOn) {
  auto c = connect();
  c->send_raw(std::string("\x7f\xff\xff\xff", 4));
  expect_error_then_close(*c, wire::Error::FRAME_TOO_LARGE);
  expect_a_session_still_works();
}

TEST_F(NodeTest, TruncatedFrameGetsAnErrorAndTheNodeServesOn) {
  auto c = connect();
  const std::string frame = encode_frame(hello());
  c->send_raw(frame.substr(0, frame.size() / 2));
  c->shutdown_send();
  expect_error_then_close(*c, wire::Error::BAD_FRAME);
  expect_a_session_still_works();
}

TEST_F(NodeTest, GarbageGetsAnErrorAndTheNodeServesOn) {
  auto c = connect();
  c->send_raw(std::string("\0\0\0\4\xde\xad\xbe\xef", 8));
  expect_error_then_close(*c, wire::Error::BAD_FRAME);
  expect_a_session_still_works();
}

TEST_F(NodeTest, VersionMismatchGetsAnErrorAndTheNodeServesOn) {
  auto c = connect();
  c->send(hello(role(), kProtocolVersion + 1));
  expect_error_then_close(*c, wire::Error::VERSION_MISMATCH);
  expect_a_session_still_works();
}

TEST_F(NodeTest, ARoleItCannotServeIsAWrongRoleNamingBoth) {
  auto c = connect();
  c->send(hello("vehicle"));
  const std::string msg = expect_error_then_close(*c, wire::Error::WRONG_ROLE);
  EXPECT_NE(msg.find("track"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vehicle"), std::string::npos) << msg;
  expect_a_session_still_works();
}

TEST_F(NodeTest, AConfigureForAnotherParticipantThanTheHelloIsAWrongRole) {
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  c->send(configure_envelope(scene_, config("rs-xx-jacobi", "vehicle")));
  const std::string msg = expect_error_then_close(*c, wire::Error::WRONG_ROLE);
  EXPECT_NE(msg.find("track"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vehicle"), std::string::npos) << msg;
}

TEST_F(NodeTest, AMessageBeforeHelloIsOutOfOrder) {
  auto c = connect();
  wire::Envelope e;
  e.mutable_step()->set_step(0);
  c->send(e);
  expect_error_then_close(*c, wire::Error::OUT_OF_ORDER);
}

TEST_F(NodeTest, ASecondClientIsToldTheNodeIsBusy) {
  auto first = connect();
  first->send(hello());
  ASSERT_TRUE(first->receive(milliseconds(5000)).has_hello_reply());
  auto second = connect();
  expect_error_then_close(*second, wire::Error::BUSY);
  // The first session is unharmed.
  wire::Envelope bye;
  bye.mutable_shutdown();
  first->send(bye);
  EXPECT_TRUE(first->receive(milliseconds(5000)).has_ack());
}

TEST_F(NodeTest, APeerThatSaysNothingIsTimedOutAndTheNodeServesOn) {
  auto c = connect();
  const auto t0 = std::chrono::steady_clock::now();
  expect_error_then_close(*c, wire::Error::TIMEOUT);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, milliseconds(3000));
  expect_a_session_still_works();
}

TEST_F(NodeTest, ASessionThatFallsSilentIsTimedOut) {
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  expect_error_then_close(*c, wire::Error::TIMEOUT);
}

TEST_F(NodeTest, InputsThatDoNotFitAreABadRequest) {
  const SubsystemConfig cfg = config("wr-xx-jacobi", "track");
  const CouplingData good = some_inputs(scene_, cfg.participant, 1.0);
  CouplingData not_finite = good, too_short = good, too_many_interfaces = good;
  not_finite[0].displacement[0] = NAN;
  too_short[0].displacement.clear();
  too_many_interfaces.push_back(good[0]);
  for (const CouplingData& bad : {not_finite, too_short, too_many_interfaces}) {
    auto c = connect();
    open(*c, configure_envelope(scene_, cfg));
    wire::Envelope init;
    *init.mutable_initialize()->mutable_inputs() = to_wire(good);
    c->send(init);
    ASSERT_TRUE(c->receive(milliseconds(5000)).has_step_report());
    wire::Envelope step;
    step.mutable_step()->set_step(0);
    step.mutable_step()->set_h(scene_.macro_step);
    *step.mutable_step()->mutable_inputs() = to_wire(bad);
    c->send(step);
    const std::string msg = expect_error_then_close(*c, wire::Error::BAD_REQUEST);
    EXPECT_NE(msg.find("inputs rejected"), std::string::npos) << msg;
  }
  expect_a_session_still_works();
}

TEST_F(NodeTest, AnUnknownMessageTypeIsRefused) {
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  // A field number this node does not know: to it, an envelope with no body.
  wire::Envelope e;
  e.set_id(5);
  std::string bytes = e.SerializeAsString() + std::string("\xfa\x06\x00", 3);  // field 111, empty
  std::string frame(4, '\0');
  frame[3] = static_cast<char>(bytes.size());
  c->send_raw(frame + bytes);
  expect_error_then_close(*c, wire::Error::BAD_FRAME);
}

TEST_F(NodeTest, SessionsFollowOneAnother) {
  for (int i = 0; i < 3; ++i) expect_a_session_still_works();
  EXPECT_EQ(server_->sessions(), 3);
}

// A soil node, on the scene with a lumped soil.
class SoilNodeTest : public NodeTest {
 protected:
  std::string role() const override { return "soil"; }
  Scene scene() const override { return load_scene(test::source_path("scenes/soil.toml")); }
  const char* session_case() const override { return "wr-xx+ss-xx-jacobi"; }
};

TEST_F(SoilNodeTest, ServesTheSoilOfAThreeParticipantCase) {
  expect_a_session_still_works();
}

TEST_F(SoilNodeTest, AnInterfaceAboveItsComponentsIsABadInterface) {
  // The soil asked to take the rail's side of the wheel/rail contact.
  SubsystemConfig cfg = config("ss-xx-jacobi", "soil");
  cfg.participant.interfaces = config("wr-xx-jacobi", "track").participant.interfaces;
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  c->send(configure_envelope(scene_, cfg));
  const std::string msg = expect_error_then_close(*c, wire::Error::BAD_INTERFACE);
  EXPECT_NE(msg.find("soil"), std::string::npos) << msg;
  EXPECT_NE(msg.find("wr"), std::string::npos) << msg;
  expect_a_session_still_works();
}

TEST_F(SoilNodeTest, AWrongNumberOfCouplingPointsIsABadInterface) {
  wire::Envelope conf = configure_envelope(scene_, config("wr-xx+ss-xx-jacobi", "soil"));
  auto* x = conf.mutable_configure()->mutable_interfaces(0)->mutable_x();
  ASSERT_EQ(x->size(), scene_.sleeper_count);
  x->Truncate(3);
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  c->send(conf);
  const std::string msg = expect_error_then_close(*c, wire::Error::BAD_INTERFACE);
  EXPECT_NE(msg.find("soil"), std::string::npos) << msg;
  EXPECT_NE(msg.find("ss"), std::string::npos) << msg;
  EXPECT_NE(msg.find("3 coupling points"), std::string::npos) << msg;
  expect_a_session_still_works();
}

}  // namespace
}  // namespace railcosim
