// A node against clients that drip, flood, ask for too much or hold it with
// a long step: every wait is a deadline for a whole message, a session holds
// a bounded amount of memory, a reply over the limit is an error reply, a
// step's work is bounded in time, the node keeps answering meanwhile, and
// it tells a client nothing about itself before the authentication.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>
#include <vector>

#include "auth.hpp"
#include "connection.hpp"
#include "engine/coupled_statics.hpp"
#include "remote/remote_participant.hpp"
#include "scene_text.hpp"
#include "server.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

const std::string kToken = "a shared secret of the tests, long enough";

// Resident memory of this process (the node runs in it), KiB.
long rss_kib() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

class NodeLimitsTest : public ::testing::Test {
 protected:
  void start(ServerLimits limits, std::optional<std::string> token = std::nullopt,
             std::optional<Scene> pinned = std::nullopt) {
    NodeOptions o;
    o.role = "track";
    o.token = token;
    o.pinned_scene = pinned;
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0}, limits);
    thread_ = std::thread([this] { server_->run(false); });
    address_ = server_->local_address();
  }
  void TearDown() override {
    if (!server_) return;
    server_->stop();
    thread_.join();
  }

  // The track of wr-xx-jacobi on `scene`.
  SubsystemConfig track_config(const Scene& scene) const {
    SubsystemConfig cfg;
    for (const ParticipantSpec& p : partition(scene, parse_case("wr-xx-jacobi")))
      if (p.role == "track") cfg.participant = p;
    cfg.macro_step = scene.macro_step;
    cfg.tolerance = scene.tolerance;
    return cfg;
  }

  // Opens a configured and initialised session on `c`.
  void open(Connection& c, const Scene& scene, const SubsystemConfig& cfg) {
    c.send(hello_envelope("track", scene_fingerprint(scene)));
    ASSERT_TRUE(c.receive(milliseconds(5000)).has_hello_reply());
    c.send(configure_envelope(scene, cfg));
    ASSERT_TRUE(c.receive(milliseconds(5000)).has_configured());
    wire::Envelope init;
    *init.mutable_initialize()->mutable_inputs() =
        to_wire(engine::zero_inputs(scene, cfg.participant));
    c.send(init);
    ASSERT_TRUE(c.receive(milliseconds(5000)).has_step_report());
  }

  // A whole short session through the master's proxy: the node serves.
  void expect_served(const std::optional<std::string>& token = std::nullopt) {
    const Scene scene = test::paper_scene();
    const SubsystemConfig cfg = track_config(scene);
    remote::RemoteParticipant remote(address_, scene, cfg, {}, token);
    remote.initialize(engine::zero_inputs(scene, cfg.participant));
    remote.set_inputs(0, engine::zero_inputs(scene, cfg.participant));
    EXPECT_EQ(remote.step(0).outputs.size(), 1u);
  }

  std::unique_ptr<NodeServer> server_;
  std::thread thread_;
  Address address_;
};

// A client that drips its hello one byte every 100 ms does not hold the
// node past the hello deadline, with or without a shared secret (before, each
// byte restarted the deadline and the node answered BUSY to everyone else).
TEST_F(NodeLimitsTest, ADrippingClientDoesNotHoldTheNode) {
  for (const bool with_token : {false, true}) {
    SCOPED_TRACE(with_token ? "with a token" : "without a token");
    ServerLimits limits;
    limits.handshake_timeout = milliseconds(500);
    const std::optional<std::string> token =
        with_token ? std::optional<std::string>(kToken) : std::nullopt;
    start(limits, token);
    auto dripper = Connection::connect(address_, milliseconds(5000));
    const std::string frame = encode_frame(hello_envelope("track", 1));
    const auto t0 = Clock::now();
    std::size_t sent = 0;
    // Drip until well past the deadline (or until the node hangs up).
    try {
      while (Clock::now() - t0 < milliseconds(900)) {
        dripper->send_raw(frame.substr(sent++ % frame.size(), 1), milliseconds(500));
        std::this_thread::sleep_for(milliseconds(100));
      }
    } catch (const NetError&) {
    }
    expect_served(token);
    TearDown();
    server_.reset();
  }
}

// A client that floods small requests and never reads the replies: the node
// stops reading it (backpressure), drops it when a reply cannot be delivered
// within the message timeout, and its memory stays bounded.
TEST_F(NodeLimitsTest, AFloodWithoutReadingKeepsMemoryBounded) {
  ServerLimits limits;
  limits.message_timeout = milliseconds(700);
  start(limits);
  // A saved state of 30,000 doubles.
  const Scene scene = with_keys(test::paper_scene(), {{"sleepers.count", 2000}});
  auto flood = Connection::connect(address_, milliseconds(5000));
  open(*flood, scene, track_config(scene));
  // Save replies are the whole state (some 270 kB) for a request of a few
  // bytes: a node that queued its replies grew by about 100 MB a second.
  wire::Envelope save;
  save.mutable_save();
  std::string burst;
  while (burst.size() < (1u << 20)) burst += encode_frame(save);
  const long before = rss_kib();
  const auto t0 = Clock::now();
  std::size_t sent = 0;
  try {
    while (Clock::now() - t0 < milliseconds(2000)) {
      flood->send_raw(burst, milliseconds(300));
      sent += burst.size();
    }
  } catch (const NetError&) {
    // The node no longer reads: what backpressure looks like from here.
  }
  const long grown = rss_kib() - before;
  // Bound: one request buffer (a read of 64 KiB plus one frame) and one
  // reply (270 kB here, at most --max-frame-bytes, 8 MiB) per session; the
  // socket buffers are the kernel's. Measured: about 1 MiB; a node that
  // queued its replies grew by 33 MiB in the same 2 s, and on.
  EXPECT_LT(grown, 16 * 1024) << "KiB grown while " << sent << " bytes of requests were sent";
  flood.reset();
  expect_served();
}

// A reply larger than the node's own frame limit is an error reply naming
// the limit, and the node serves on (before, the node process exited).
TEST_F(NodeLimitsTest, AnOversizedReplyIsAnErrorReply) {
  ServerLimits limits;
  limits.max_frame_bytes = 4096;  // the paper track's saved state is some 7 kB
  start(limits);
  const Scene scene = test::paper_scene();
  auto c = Connection::connect(address_, milliseconds(5000));
  open(*c, scene, track_config(scene));
  wire::Envelope save;
  save.mutable_save();
  c->send(save);
  const wire::Envelope reply = c->receive(milliseconds(5000));
  ASSERT_TRUE(reply.has_error()) << body_name(reply);
  EXPECT_EQ(reply.error().code(), wire::Error::FRAME_TOO_LARGE);
  EXPECT_NE(reply.error().message().find("exceeds this node's --max-frame-bytes of 4096"),
            std::string::npos)
      << reply.error().message();
  c.reset();
  expect_served();
}

// A step that would grind for seconds (a long track, a tolerance no step
// can meet) ends at the node's time limit; meanwhile another client gets BUSY
// at once, and stopping the node does not wait for the step.
TEST_F(NodeLimitsTest, ALongStepIsBoundedAndTheNodeAnswersMeanwhile) {
  ServerLimits limits;
  limits.max_step_time = milliseconds(800);
  start(limits);
  const Scene scene = with_keys(test::paper_scene(), {{"sleepers.count", 2000}});
  SubsystemConfig cfg = track_config(scene);
  cfg.tolerance = 1e-30;
  auto c = Connection::connect(address_, milliseconds(5000));
  open(*c, scene, cfg);
  CouplingData in = engine::zero_inputs(scene, cfg.participant);
  in[0].displacement[0] = 1e-3;  // the wheel pressed into the rail: the track moves
  wire::Envelope step;
  step.mutable_step()->set_step(0);
  step.mutable_step()->set_h(scene.macro_step);
  *step.mutable_step()->mutable_inputs() = to_wire(in);
  const auto t0 = Clock::now();
  c->send(step);
  std::this_thread::sleep_for(milliseconds(100));
  auto other = Connection::connect(address_, milliseconds(5000));
  other->send(hello_envelope("track", scene_fingerprint(scene)));
  const wire::Envelope busy = other->receive(milliseconds(300));
  ASSERT_TRUE(busy.has_error());
  EXPECT_EQ(busy.error().code(), wire::Error::BUSY);
  const wire::Envelope reply = c->receive(milliseconds(5000));
  ASSERT_TRUE(reply.has_error()) << body_name(reply);
  EXPECT_EQ(reply.error().code(), wire::Error::STEP_FAILED);
  EXPECT_NE(reply.error().message().find("--max-step-seconds"), std::string::npos)
      << reply.error().message();
  // The limit plus at most 16 micro steps of the long track.
  EXPECT_LT(Clock::now() - t0, milliseconds(1500));
}

// A node pinned to a scene tells a client that has not proved the secret
// nothing about it: the hello gets the challenge whatever its fingerprint,
// and a wrong answer a refusal that names no scene.
TEST_F(NodeLimitsTest, NothingAboutTheSceneBeforeAuthentication) {
  const Scene scene = test::paper_scene();
  start(ServerLimits{}, kToken, scene);
  auto c = Connection::connect(address_, milliseconds(5000));
  c->send(hello_envelope("track", 12345));  // not the pinned scene's fingerprint
  const wire::Envelope challenge = c->receive(milliseconds(5000));
  ASSERT_TRUE(challenge.has_challenge()) << challenge.ShortDebugString();
  wire::Envelope auth;
  auth.mutable_auth()->set_mac("wrong");
  c->send(auth);
  const wire::Envelope refused = c->receive(milliseconds(5000));
  ASSERT_TRUE(refused.has_error());
  EXPECT_EQ(refused.error().code(), wire::Error::UNAUTHORIZED);
  EXPECT_EQ(refused.error().message().find("paper.toml"), std::string::npos);
  EXPECT_EQ(refused.error().message().find("fingerprint"), std::string::npos);
  // With the secret, the scene check still holds.
  auto d = Connection::connect(address_, milliseconds(5000));
  d->send(hello_envelope("track", 12345));
  const wire::Envelope nonce = d->receive(milliseconds(5000));
  ASSERT_TRUE(nonce.has_challenge());
  wire::Envelope right;
  right.mutable_auth()->set_mac(auth_answer(kToken, "track", nonce.challenge().nonce()));
  d->send(right);
  const wire::Envelope mismatch = d->receive(milliseconds(5000));
  ASSERT_TRUE(mismatch.has_error());
  EXPECT_EQ(mismatch.error().code(), wire::Error::SCENE_MISMATCH);
}

// A node with a secret, idle: a hello for another participant gets
// the challenge, not the name of the one the node serves.
TEST(NodeLimitsIdle, ANodeWithASecretDoesNotTellItsRoleBeforeAuthentication) {
  NodeOptions o;
  o.role = "track";
  o.token = kToken;
  NodeServer server(o, Address{"127.0.0.1", 0});
  std::thread t([&] { server.run(false); });
  struct Stop {
    NodeServer& s;
    std::thread& t;
    ~Stop() {
      s.stop();
      t.join();
    }
  } stop{server, t};
  auto c = Connection::connect(server.local_address(), milliseconds(5000));
  c->send(hello_envelope("vehicle", 1));
  const wire::Envelope challenge = c->receive(milliseconds(5000));
  ASSERT_TRUE(challenge.has_challenge()) << challenge.ShortDebugString();
  // With the right answer, the role check holds.
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer(kToken, "vehicle", challenge.challenge().nonce()));
  c->send(auth);
  const wire::Envelope wrong = c->receive(milliseconds(5000));
  ASSERT_TRUE(wrong.has_error());
  EXPECT_EQ(wrong.error().code(), wire::Error::WRONG_ROLE);
  // Two clients saying hello at once both get the challenge (neither holds
  // the node before it has authenticated); the first to answer holds the
  // session, the second is answered BUSY, naming nobody.
  auto d = Connection::connect(server.local_address(), milliseconds(5000));
  auto e = Connection::connect(server.local_address(), milliseconds(5000));
  e->send(hello_envelope("track", 1));
  d->send(hello_envelope("track", 1));
  const wire::Envelope ce = e->receive(milliseconds(5000)), cd = d->receive(milliseconds(5000));
  ASSERT_TRUE(ce.has_challenge()) << ce.ShortDebugString();
  ASSERT_TRUE(cd.has_challenge()) << cd.ShortDebugString();
  wire::Envelope answer;
  answer.mutable_auth()->set_mac(auth_answer(kToken, "track", ce.challenge().nonce()));
  e->send(answer);
  const wire::Envelope first = e->receive(milliseconds(5000));
  ASSERT_TRUE(first.has_hello_reply()) << first.ShortDebugString();
  answer.mutable_auth()->set_mac(auth_answer(kToken, "track", cd.challenge().nonce()));
  d->send(answer);
  const wire::Envelope second = d->receive(milliseconds(5000));
  ASSERT_TRUE(second.has_error()) << second.ShortDebugString();
  EXPECT_EQ(second.error().code(), wire::Error::BUSY);
  EXPECT_EQ(second.error().message(), kBusyText);
}

// One client that says hello and stays silent before authenticating does
// not keep the node from the master: its hello waits out its own deadline
// beside the master's, which is served at once; the same with eight such
// clients, and a ninth is answered BUSY.
TEST_F(NodeLimitsTest, ASilentClientBeforeAuthenticationHoldsNobody) {
  start(ServerLimits{}, kToken);
  std::vector<std::unique_ptr<Connection>> silent;
  for (int k = 0; k < 8; ++k) {
    silent.push_back(Connection::connect(address_, milliseconds(5000)));
    silent.back()->send(hello_envelope("track", 1));
    ASSERT_TRUE(silent.back()->receive(milliseconds(5000)).has_challenge());
  }
  auto ninth = Connection::connect(address_, milliseconds(5000));
  ninth->send(hello_envelope("track", 1));
  const wire::Envelope busy = ninth->receive(milliseconds(5000));
  ASSERT_TRUE(busy.has_error()) << busy.ShortDebugString();
  EXPECT_EQ(busy.error().code(), wire::Error::BUSY);
  silent.pop_back();  // one closes: room for the master's hello
  std::this_thread::sleep_for(milliseconds(100));
  const auto t0 = Clock::now();
  expect_served(kToken);
  EXPECT_LT(Clock::now() - t0, milliseconds(3000));
}

}  // namespace
}  // namespace railcosim
