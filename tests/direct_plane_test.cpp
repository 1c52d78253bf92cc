// The direct data plane where it can go wrong: a node killed in the middle of
// a window, and peers that must not be let in (wrong participant, wrong
// session, wrong or missing secret). Its bitwise equality with the in-process
// runs is in tcp_integration_test (every case, two to four participants) and
// netns_test.sh (across network hosts).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <limits>
#include <thread>

#include "auth.hpp"
#include "connection.hpp"
#include "cosim_support.hpp"
#include "one_shot_peer.hpp"
#include "process_support.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "server.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

long count_lines(const fs::path& p) {
  const std::string text = test::read_file(p);
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

// Starts `master ARGS` with its output to `log`; returns its pid.
pid_t start_master(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string program = std::string(RAILCOSIM_BIN_DIR) + "/master";
    std::vector<char*> argv{const_cast<char*>(program.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    FILE* f = std::fopen(log.c_str(), "w");
    if (f) {
      ::dup2(::fileno(f), STDOUT_FILENO);
      ::dup2(::fileno(f), STDERR_FILENO);
    }
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

// A track node killed in the middle of a run of 25,000 macro steps on the
// direct plane, `coupling` the run's coupling options: the master names the
// node, its address and the macro step within 3 s, and history.csv keeps
// every step that both nodes had reported, equal to the in-process run's rows.
void kill_the_track_node(const std::vector<std::string>& coupling) {
  const fs::path dir = test::temp_dir("kill");
  const std::string scene = test::source_path("scenes/paper.toml");
  const std::string c = "rs-xx-jacobi";
  // H = 1e-5 s: 25,000 macro steps, several seconds over loopback.
  remote::LaunchedNode vehicle("vehicle_node", milliseconds(10000));
  remote::LaunchedNode track("track_node", milliseconds(10000));
  std::vector<std::string> args{"run",
                                "--scene",
                                scene,
                                "--case",
                                c,
                                "--macro-step",
                                "1e-5",
                                "--node",
                                "vehicle=" + vehicle.address().str(),
                                "--node",
                                "track=" + track.address().str(),
                                "--out",
                                (dir / "tcp").string()};
  args.insert(args.end(), coupling.begin(), coupling.end());
  const pid_t master = start_master(args, dir / "master.log");
  ASSERT_GT(master, 0);
  const fs::path history = dir / "tcp" / c / "history.csv";
  const auto started = Clock::now();
  long seen = 0;
  while ((seen = count_lines(history)) < 2000 && Clock::now() - started < std::chrono::seconds(60))
    std::this_thread::sleep_for(milliseconds(5));
  ASSERT_GE(seen, 2000) << test::read_file(dir / "master.log");

  ASSERT_EQ(::kill(track.pid(), SIGKILL), 0);
  const auto killed = Clock::now();
  int status = 0;
  while (::waitpid(master, &status, WNOHANG) == 0 &&
         Clock::now() - killed < std::chrono::seconds(10))
    std::this_thread::sleep_for(milliseconds(5));
  const double waited = std::chrono::duration<double>(Clock::now() - killed).count();
  EXPECT_LT(waited, 3.0) << "the master took " << waited << " s to report the dead node";
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_NE(WEXITSTATUS(status), 0);

  const std::string log = test::read_file(dir / "master.log");
  const std::string summary = test::read_file(dir / "tcp" / c / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"failed\""), std::string::npos) << summary;
  std::string options;
  for (const std::string& a : coupling) options += a + " ";
  for (const std::string& needle :
       {std::string("track node at ") + track.address().str(), std::string("macro step"),
        std::string("closed the connection")})
    EXPECT_NE(summary.find(needle), std::string::npos) << needle << " not in " << summary;

  // Every row the file holds is whole and equal to the in-process run's.
  ASSERT_EQ(test::run_master("run --scene " + scene + " --case " + c + " --macro-step 1e-5 " +
                             options + "--transport inproc --out " + (dir / "inproc").string())
                .status,
            0);
  const std::string got = test::read_file(history);
  const std::string want = test::read_file(dir / "inproc" / c / "history.csv");
  ASSERT_FALSE(got.empty());
  ASSERT_EQ(got.back(), '\n') << "a partial last row";
  EXPECT_EQ(want.compare(0, got.size(), got), 0) << "the history differs from the in-process run";
  EXPECT_GE(count_lines(history), seen) << "rows written before the kill were lost";
  fs::remove_all(dir);
}

// Explicit coupling: the nodes are in a window of 25,000 macro steps.
TEST(DirectPlane, ANodeKilledInAWindowIsNamedWithinThreeSecondsAndTheHistoryIsKept) {
  kill_the_track_node({});
}

// Implicit coupling in lock step: the node dies in the middle of an iteration.
TEST(DirectPlane, ANodeKilledInAnImplicitIterationIsNamedWithinThreeSeconds) {
  kill_the_track_node({"--coupling", "implicit", "--inputs", "linear"});
}

// A track node with a shared secret, in a session of the direct data plane
// that expects a peer link from the vehicle participant.
class PeerRefusal : public ::testing::Test {
 protected:
  static constexpr const char* kSecret = "a shared secret of the track node";

  void SetUp() override { start(nullptr); }

  // The session, its one link to the vehicle participant accepted here, or
  // made by this node to `connect_to` when given.
  void start(const Address* connect_to) {
    NodeOptions o;
    o.role = "track";
    o.token = kSecret;
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0});
    thread_ = std::thread([this] { server_->run(false); });
    scene_ = test::paper_scene();
    master_ = Connection::connect(server_->local_address(), milliseconds(5000));
    master_->send(hello_envelope("track", scene_fingerprint(scene_)));
    const wire::Envelope challenge = master_->receive(milliseconds(5000));
    ASSERT_TRUE(challenge.has_challenge());
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(kSecret, "track", challenge.challenge().nonce()));
    master_->send(auth);
    ASSERT_TRUE(master_->receive(milliseconds(5000)).has_hello_reply());
    const SubsystemConfig cfg = test::config_of(scene_, "rs-xx-jacobi", "track");
    master_->send(configure_envelope(scene_, cfg));
    ASSERT_TRUE(master_->receive(milliseconds(5000)).has_configured());
    wire::Envelope init;
    *init.mutable_initialize()->mutable_inputs() =
        to_wire(engine::zero_inputs(scene_, cfg.participant));
    master_->send(init);
    ASSERT_TRUE(master_->receive(milliseconds(5000)).has_step_report());
    wire::Envelope links;
    links.mutable_links()->set_session(session_);
    links.mutable_links()->set_timeout_ms(1500);
    auto* l = links.mutable_links()->add_links();
    l->set_peer("vehicle");
    l->add_interfaces(0);
    if (connect_to != nullptr) {
      l->set_host(connect_to->host);
      l->set_port(connect_to->port);
    }
    master_->send(links);
    ASSERT_TRUE(master_->receive(milliseconds(5000)).has_ack());
    // The window makes the node wait for its peer.
    wire::Envelope window;
    window.mutable_window()->set_first_step(0);
    window.mutable_window()->set_end_step(10);
    master_->send(window);
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }

  // A connection that says hello as a peer; returns the node's first reply.
  wire::Envelope peer_hello(const std::string& peer_of, const std::string& session,
                            Connection& c) const {
    wire::Envelope e;
    auto* h = e.mutable_hello();
    h->set_protocol_version(kProtocolVersion);
    h->set_role("peer");
    h->set_participant("track");
    h->set_peer_of(peer_of);
    h->set_session(session);
    c.send(e);
    return c.receive(milliseconds(5000));
  }

  // The same, answering the node's challenge with its secret; returns the
  // reply to the answer.
  wire::Envelope peer_hello_with_secret(const std::string& peer_of, const std::string& session,
                                        Connection& c) const {
    const wire::Envelope challenge = peer_hello(peer_of, session, c);
    EXPECT_TRUE(challenge.has_challenge()) << body_name(challenge);
    wire::Envelope auth;
    auth.mutable_auth()->set_mac(auth_answer(kSecret, "track", challenge.challenge().nonce()));
    c.send(auth);
    return c.receive(milliseconds(5000));
  }

  static std::string refusal(const wire::Envelope& reply, wire::Error::Code code) {
    EXPECT_TRUE(reply.has_error()) << body_name(reply);
    EXPECT_EQ(reply.error().code(), code) << wire::Error::Code_Name(reply.error().code());
    return reply.error().message();
  }

  std::unique_ptr<NodeServer> server_;
  std::thread thread_;
  Scene scene_;
  std::unique_ptr<Connection> master_;
  const std::string session_ = "0123456789abcdef0123456789abcdef";
};

TEST_F(PeerRefusal, AnUnexpectedParticipantAWrongSessionAndAWrongSecretAreRefused) {
  const Address at = server_->local_address();
  auto soil = Connection::connect(at, milliseconds(5000));
  const std::string who =
      refusal(peer_hello_with_secret("soil", session_, *soil), wire::Error::WRONG_ROLE);
  EXPECT_NE(who.find("expects peer links from vehicle"), std::string::npos) << who;
  EXPECT_NE(who.find("soil"), std::string::npos) << who;

  auto stranger = Connection::connect(at, milliseconds(5000));
  const std::string key =
      refusal(peer_hello_with_secret("vehicle", std::string(32, 'x'), *stranger),
              wire::Error::UNAUTHORIZED);
  EXPECT_NE(key.find("session key"), std::string::npos) << key;

  auto guesser = Connection::connect(at, milliseconds(5000));
  const wire::Envelope challenge = peer_hello("vehicle", session_, *guesser);
  ASSERT_TRUE(challenge.has_challenge()) << body_name(challenge);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(
      auth_answer("not the secret", "track", challenge.challenge().nonce()));
  guesser->send(auth);
  const std::string secret =
      refusal(guesser->receive(milliseconds(5000)), wire::Error::UNAUTHORIZED);
  EXPECT_NE(secret.find("--token-file"), std::string::npos) << secret;

  // The master hears at once whom the node waits for (so that it can name
  // that node if it never comes).
  const wire::Envelope waiting = master_->receive(milliseconds(5000));
  ASSERT_TRUE(waiting.has_reports()) << body_name(waiting);
  EXPECT_EQ(waiting.reports().waiting_for(), "vehicle");
  EXPECT_EQ(waiting.reports().reports_size(), 0);
  // The real peer never came: the window fails, naming it and the refusals.
  const wire::Envelope failed = master_->receive(milliseconds(5000));
  const std::string why = refusal(failed, wire::Error::TIMEOUT);
  EXPECT_NE(why.find("from vehicle did not open within 1500 ms"), std::string::npos) << why;
  EXPECT_NE(why.find("refused meanwhile"), std::string::npos) << why;
}

// An impostor listening at the vehicle's address, without the secret: the
// track node connects, the impostor answers its hello as the vehicle but
// cannot prove it holds the secret, and the node refuses the link before it
// sends any coupling data (the accepting end must authenticate too).
class PeerImpostor : public PeerRefusal {
 protected:
  void SetUp() override {
    wire::Envelope reply;
    reply.mutable_hello_reply()->set_participant("vehicle");
    reply.mutable_hello_reply()->set_protocol_version(kProtocolVersion);
    impostor_ = std::make_unique<test::OneShotPeer>(encode_frame(reply, kDefaultMaxFrameBytes));
    const Address at = impostor_->address();
    start(&at);
  }
  std::unique_ptr<test::OneShotPeer> impostor_;
};

TEST_F(PeerImpostor, ANodeRefusesAnAcceptingEndThatCannotProveTheSecret) {
  wire::Envelope failed = master_->receive(milliseconds(5000));
  while (failed.has_reports()) failed = master_->receive(milliseconds(5000));
  const std::string why = refusal(failed, wire::Error::UNAUTHORIZED);
  EXPECT_NE(why.find("peer link to the vehicle participant at " + impostor_->address().str()),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("cannot prove that it holds the shared secret"), std::string::npos) << why;
}

// A peer that opens its link and then stays silent: the window fails after
// the link's deadline, and the message states that deadline (it once said
// 50 ms, the length of one slice of the wait).
TEST_F(PeerRefusal, ASilentPeerIsReportedWithTheRealWait) {
  auto vehicle = Connection::connect(server_->local_address(), milliseconds(5000));
  const wire::Envelope challenge = peer_hello("vehicle", session_, *vehicle);
  ASSERT_TRUE(challenge.has_challenge()) << body_name(challenge);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer(kSecret, "track", challenge.challenge().nonce()));
  vehicle->send(auth);
  ASSERT_TRUE(vehicle->receive(milliseconds(5000)).has_hello_reply());
  const auto t0 = Clock::now();
  wire::Envelope reply;
  do reply = master_->receive(milliseconds(5000));
  while (reply.has_reports());
  const std::string why = refusal(reply, wire::Error::PEER_FAILED);
  EXPECT_NE(why.find("the vehicle participant at "), std::string::npos) << why;
  EXPECT_NE(why.find(" sent nothing within 1500 ms"), std::string::npos) << why;
  EXPECT_EQ(reply.error().sender(), "") << "a silent link blames nobody's data";
  EXPECT_GT(Clock::now() - t0, milliseconds(1300));
}

// A peer whose data at point 1 holds a NaN: the node refuses it naming the
// sender, and the step report it had computed still reaches the master
// before the error (the reports not yet sent were once lost).
TEST_F(PeerRefusal, BadDataFromAPeerIsBlamedOnItAndTheReportsAreKept) {
  auto vehicle = Connection::connect(server_->local_address(), milliseconds(5000));
  const wire::Envelope challenge = peer_hello("vehicle", session_, *vehicle);
  ASSERT_TRUE(challenge.has_challenge()) << body_name(challenge);
  wire::Envelope auth;
  auth.mutable_auth()->set_mac(auth_answer(kSecret, "track", challenge.challenge().nonce()));
  vehicle->send(auth);
  ASSERT_TRUE(vehicle->receive(milliseconds(5000)).has_hello_reply());
  // Data of the right shape: the vehicle's own outputs at rest.
  const SubsystemConfig cfg = test::config_of(scene_, "rs-xx-jacobi", "vehicle");
  Subsystem sub(scene_, cfg);
  InterfaceData data = sub.initialize(engine::zero_inputs(scene_, cfg.participant)).outputs[0];
  for (long point = 0; point < 2; ++point) {
    if (point == 1)
      for (auto* v : {&data.displacement, &data.velocity, &data.force})
        if (!v->empty()) v->front() = std::numeric_limits<double>::quiet_NaN();
    wire::Envelope e;
    e.mutable_peer_data()->set_point(point);
    to_wire(data, e.mutable_peer_data()->mutable_data()->add_interfaces());
    vehicle->send(e);
  }
  long reported = 0;
  wire::Envelope reply;
  do {
    reply = master_->receive(milliseconds(5000));
    for (const auto& r : reply.reports().reports()) reported = static_cast<long>(r.step());
  } while (reply.has_reports());
  EXPECT_EQ(reported, 1) << "the report of the step done before the bad data was lost";
  const std::string why = refusal(reply, wire::Error::PEER_FAILED);
  EXPECT_NE(why.find("the vehicle participant at "), std::string::npos) << why;
  EXPECT_NE(why.find(" sent a non-finite value for point 1 at macro step 1"), std::string::npos)
      << why;
  EXPECT_EQ(reply.error().sender(), "vehicle") << "the sender is the root cause";
}

// A vehicle node without the secret that the track node requires: the
// master, which holds the secret, refuses the vehicle at its hello (it cannot
// prove the secret), before any peer link, naming it and what to pass.
TEST(DirectPlane, ANodeWithoutTheSecretIsRefusedBeforeItsPeerLinksWithAClearError) {
  const std::string secret = "the track node's shared secret";
  NodeOptions v;
  v.role = "vehicle";
  NodeOptions t;
  t.role = "track";
  t.token = secret;
  NodeServer vehicle(v, Address{"127.0.0.1", 0}), track(t, Address{"127.0.0.1", 0});
  std::thread tv([&] { vehicle.run(false); }), tt([&] { track.run(false); });
  const Scene scene = test::paper_scene();
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  remote::NodePool pool;
  const remote::SceneTransport tcp = remote::tcp_transport(
      scene, {{"vehicle", vehicle.local_address()}, {"track", track.local_address()}}, pool,
      secret);
  try {
    run::run_cosim(scene, parse_case("wr-xx-jacobi"), o, tcp.factory, tcp.name);
    ADD_FAILURE() << "the run went through";
  } catch (const remote::NodeFailure& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vehicle node at " + vehicle.local_address().str()), std::string::npos)
        << what;
    EXPECT_NE(what.find("it asked no challenge"), std::string::npos) << what;
    EXPECT_NE(what.find("same --token-file"), std::string::npos) << what;
  }
  vehicle.stop();
  track.stop();
  tv.join();
  tt.join();
}

}  // namespace
}  // namespace railcosim
