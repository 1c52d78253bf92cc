// The master's participants over any FramedChannel: a RemoteParticipant over
// the in-process channel (inproc_channel.hpp), whose node sessions threads
// of this test serve, runs a paper case bit for bit as in process and as
// over TCP; a channel the far end closes fails as TCP's does.
#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "cosim_support.hpp"
#include "inproc_channel.hpp"
#include "one_shot_peer.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using remote::ChannelOpener;
using remote::DataPlane;
using remote::inproc_factory;
using remote::NodeFailure;
using remote::NodePool;
using remote::ParticipantFactory;
using remote::RemoteParticipant;
using remote::tcp_transport;

using std::chrono::milliseconds;

// The paper scene shortened to 0.05 s (500 macro steps).
Scene short_paper_scene() {
  return with_keys(test::paper_scene(), {{"simulation.end_time", 0.05}});
}

std::string channel_peer(const std::string& role) {
  return "in-process " + role + " node";
}

// Participants as remote proxies over in-process channels to node sessions.
ParticipantFactory channel_factory(const Scene& scene, test::InprocNodes& nodes,
                                   bool offer_direct = false) {
  return [&scene, &nodes, offer_direct](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    NodeOptions node;
    node.role = c.participant.role;
    return std::make_unique<RemoteParticipant>(
        nodes.opener(node, channel_peer(c.participant.role), offer_direct),
        channel_peer(c.participant.role), scene, c);
  };
}

run::RunOptions options_of(const Scene& scene, DataPlane plane) {
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  o.data_plane = plane;
  return o;
}

void expect_same_run(const run::RunRecord& a, const run::RunRecord& b) {
  ASSERT_EQ(a.status, b.status) << a.message << " / " << b.message;
  EXPECT_EQ(a.macro_steps, b.macro_steps);
  EXPECT_EQ(a.micro_steps, b.micro_steps);
  EXPECT_EQ(a.deflection, b.deflection);  // exact double equality
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t i = 0; i < a.history.size(); ++i) {
    EXPECT_EQ(a.history[i].t, b.history[i].t) << i;
    EXPECT_EQ(a.history[i].wheel, b.history[i].wheel) << i;
    EXPECT_EQ(a.history[i].contact_force, b.history[i].contact_force) << i;
    EXPECT_EQ(a.history[i].extra, b.history[i].extra) << i;
  }
}

TEST(FramedChannel, APaperCaseOverTheInProcessChannelEqualsInProcessAndTcpBitwise) {
  const Scene scene = short_paper_scene();
  const CaseSpec spec = parse_case("wr-xx-jacobi");
  const run::RunOptions relay = options_of(scene, DataPlane::kRelay);
  const run::RunRecord local = run::run_cosim(scene, spec, relay, inproc_factory(scene), "inproc");
  run::RunRecord channel;
  {
    test::InprocNodes nodes;
    channel = run::run_cosim(scene, spec, relay, channel_factory(scene, nodes), "tcp");
  }
  NodePool pool;
  const run::RunRecord tcp = run::run_cosim(scene, spec, options_of(scene, DataPlane::kDirect),
                                            tcp_transport(scene, {}, pool).factory, "tcp");
  ASSERT_EQ(local.status, "ok") << local.message;
  EXPECT_EQ(local.macro_steps, scene.macro_steps());
  EXPECT_EQ(local.history.size(), 501u);  // the static state and 500 macro steps
  EXPECT_EQ(channel.transport, "tcp");
  EXPECT_EQ(channel.data_plane, "relay");
  EXPECT_EQ(tcp.data_plane, "direct");
  expect_same_run(channel, local);
  expect_same_run(channel, tcp);
}

wire::Envelope a_hello() {
  return hello_envelope("track", 1);
}

NetError::Kind kind_of_receive(FramedChannel& channel) {
  try {
    channel.receive(milliseconds(5000));
  } catch (const NetError& e) {
    return e.kind();
  }
  ADD_FAILURE() << "a frame from a peer that sent none";
  return NetError::Kind::kIo;
}

TEST(FramedChannel, AChannelClosedByTheFarEndIsClosedAsOverTcp) {
  test::OneShotPeer peer("", test::OneShotPeer::After::kHangUp);
  auto tcp = Connection::connect(peer.address(), milliseconds(2000));
  tcp->send(a_hello(), milliseconds(1000));
  EXPECT_EQ(kind_of_receive(*tcp), NetError::Kind::kClosed);

  auto [master_end, node_end] = test::InprocChannel::pair("node", "master");
  master_end->send(a_hello(), milliseconds(1000));
  EXPECT_EQ(node_end->receive(milliseconds(1000)).body_case(), wire::Envelope::kHello);
  node_end->close();
  EXPECT_EQ(kind_of_receive(*master_end), NetError::Kind::kClosed);
  // Where TCP may still take a frame or two, the in-process channel refuses
  // it at once, with the same kind.
  try {
    master_end->send(a_hello(), milliseconds(1000));
    FAIL() << "sent on a channel the peer closed";
  } catch (const NetError& e) {
    EXPECT_EQ(e.kind(), NetError::Kind::kClosed);
  }
}

TEST(FramedChannel, ASilentPeerTimesOutAsOverTcp) {
  auto [master_end, node_end] = test::InprocChannel::pair("node", "master");
  try {
    master_end->receive(milliseconds(50));
    FAIL() << "a frame from a peer that sent none";
  } catch (const NetError& e) {
    EXPECT_EQ(e.kind(), NetError::Kind::kTimeout);
    EXPECT_EQ(std::string(e.what()), "no reply within 50 ms");
  }
}

// The master's error names the node the same way over either channel.
TEST(FramedChannel, ANodeThatHangsUpOnTheHelloFailsAlikeOverBothChannels) {
  const Scene scene = test::paper_scene();
  const SubsystemConfig config = test::config_of(scene, "wr-xx-jacobi", "track");
  std::string over_tcp;
  test::OneShotPeer peer("", test::OneShotPeer::After::kHangUp);
  try {
    RemoteParticipant p(peer.address(), scene, config);
    FAIL() << "a session with a node that hung up";
  } catch (const NodeFailure& e) {
    over_tcp = e.what();
  }
  // The node's end reads the hello and closes, as the TCP peer does.
  std::thread node;
  ChannelOpener hang_up = [&node](milliseconds) -> std::unique_ptr<FramedChannel> {
    auto [master_end, node_end] = test::InprocChannel::pair("node", "master");
    node = std::thread([end = std::move(node_end)] {
      end->receive(milliseconds(5000));
      end->close();
    });
    return std::move(master_end);
  };
  try {
    RemoteParticipant p(hang_up, "in-process track node", scene, config);
    FAIL() << "a session with a node that hung up";
  } catch (const NodeFailure& e) {
    EXPECT_EQ(std::string(e.what()),
              "track node at in-process track node: hello: the peer closed "
              "the connection before the run");
    EXPECT_EQ(over_tcp, "track node at " + peer.address().str() +
                            ": hello: the peer closed the connection before the run");
  }
  node.join();
}

TEST(FramedChannel, TheDirectPlaneRefusesANodeOverAnotherChannelByName) {
  const Scene scene = short_paper_scene();
  test::InprocNodes nodes;
  try {
    run::run_cosim(scene, parse_case("wr-xx-jacobi"), options_of(scene, DataPlane::kDirect),
                   channel_factory(scene, nodes, true), "tcp");
    FAIL() << "the direct plane over in-process channels";
  } catch (const NodeFailure& e) {
    EXPECT_EQ(std::string(e.what()),
              "vehicle node at in-process vehicle node: the direct data plane needs a TCP "
              "connection to the node, and this one is another channel: use --data-plane relay");
  }
}

}  // namespace
}  // namespace railcosim
