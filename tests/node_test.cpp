// A node as any client sees it: a real TCP server on loopback, driven through
// real sockets, bad frames included.
#include <gtest/gtest.h>

#include <thread>

#include "connection.hpp"
#include "remote_participant.hpp"
#include "server.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;

class NodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    NodeOptions o;
    o.role = wire::ROLE_TRACK;
    ServerLimits limits;
    limits.max_frame_bytes = 1 << 16;
    limits.idle_timeout = milliseconds(1500);
    limits.handshake_timeout = milliseconds(500);
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0}, limits);
    thread_ = std::thread([this] { server_->run(false); });
    address_ = server_->local_address();
    scene_ = test::paper_scene();
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }

  std::unique_ptr<Connection> connect() {
    return Connection::connect(address_, milliseconds(5000));
  }

  wire::Envelope hello(wire::Role expected = wire::ROLE_TRACK,
                       std::uint32_t version = kProtocolVersion) {
    return hello_envelope(expected, scene_fingerprint(scene_), version);
  }

  // Expects the next frame to be an error with `code`, then the end of the session.
  void expect_error_then_close(Connection& c, wire::Error::Code code) {
    const wire::Envelope reply = c.receive(milliseconds(5000));
    ASSERT_TRUE(reply.has_error()) << body_name(reply);
    EXPECT_EQ(reply.error().code(), code) << reply.error().message();
    EXPECT_FALSE(reply.error().message().empty());
    EXPECT_THROW(c.receive(milliseconds(5000)), NetError);  // closed
  }

  // A whole short session through the master's own proxy: the node still serves.
  void expect_a_session_still_works() {
    SubsystemConfig cfg{Split::kRailSleepers, Side::kS2, Coupling::kXX, scene_.macro_step,
                        scene_.tolerance};
    RemoteParticipant remote(address_, scene_, cfg);
    Subsystem local(scene_, cfg);
    EXPECT_EQ(remote.initialize().outputs, local.initialize().outputs);
    const CouplingData in =
        Subsystem(scene_, {cfg.split, Side::kS1, cfg.coupling, cfg.macro_step, cfg.tolerance})
            .initialize()
            .outputs;
    for (long n = 0; n < 3; ++n) {
      remote.set_inputs(n, in);
      local.set_inputs(n, in);
      EXPECT_EQ(remote.step(n).outputs, local.step(n).outputs);
    }
    EXPECT_EQ(remote.save(), local.save());
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
  c->send(hello(wire::ROLE_TRACK, kProtocolVersion + 1));
  expect_error_then_close(*c, wire::Error::VERSION_MISMATCH);
  expect_a_session_still_works();
}

TEST_F(NodeTest, WrongRoleIsRefused) {
  auto c = connect();
  c->send(hello(wire::ROLE_VEHICLE));
  expect_error_then_close(*c, wire::Error::WRONG_ROLE);
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

TEST_F(NodeTest, NonFiniteInputsAreABadRequest) {
  SubsystemConfig cfg{Split::kWheelRail, Side::kS2, Coupling::kXX, scene_.macro_step,
                      scene_.tolerance};
  auto c = connect();
  c->send(hello());
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_hello_reply());
  const wire::Envelope conf =
      configure_envelope(scene_, cfg.split, cfg.coupling, cfg.macro_step, cfg.tolerance);
  c->send(conf);
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_ack());
  wire::Envelope init;
  init.mutable_initialize();
  c->send(init);
  ASSERT_TRUE(c->receive(milliseconds(5000)).has_step_report());
  wire::Envelope step;
  step.mutable_step()->set_step(0);
  step.mutable_step()->set_h(scene_.macro_step);
  step.mutable_step()->mutable_inputs()->add_points()->set_displacement(NAN);
  c->send(step);
  expect_error_then_close(*c, wire::Error::BAD_REQUEST);
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

}  // namespace
}  // namespace railcosim
