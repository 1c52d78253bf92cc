// The master against nodes that lie, drip or stall: every bad reply fails
// the run with a message naming the node that sent it, its address, the
// macro step and what was wrong; every wait is a deadline for a whole
// message, and a signal ends it.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "fake_node.hpp"
#include "remote/remote_participant.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

extern char** environ;

namespace railcosim {
namespace reply_check_test {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The paper scene cut short: 20 macro steps are enough to meet every kind
// of reply, and keep each run at a few milliseconds.
Scene short_scene() {
  const Scene s = test::paper_scene();
  return with_keys(s, {{"simulation.end_time", 20 * s.macro_step}});
}

run::RunOptions options(const Scene& s) {
  run::RunOptions o;
  o.macro_step = s.macro_step;
  o.tolerance = s.tolerance;
  return o;
}

// wr-xx-jacobi with participant `role` on `node` (the track holds the rail
// and its deflection, the vehicle the wheel's history), the other in-process.
run::RunRecord run_against(const test::FakeNode& node, remote::RemoteTimeouts timeouts = {},
                           const std::string& role = "track") {
  const Scene scene = short_scene();
  const remote::ParticipantFactory make =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    if (c.participant.role == role)
      return std::make_unique<remote::RemoteParticipant>(node.address(), scene, c, timeouts);
    return std::make_unique<Subsystem>(scene, c);
  };
  return run::run_cosim(scene, parse_case("wr-xx-jacobi"), options(scene), make, "tcp");
}

// Runs against a node that edits its replies with `lie`; expects the run to
// fail naming that node, its address, a macro step (or "before the run")
// and `what`.
void expect_refused(const test::FakeNode::Edit& lie, const std::string& what,
                    const std::string& role = "track") {
  test::FakeNode node(role, lie);
  try {
    run_against(node, {}, role);
    ADD_FAILURE() << "a node that lies (" << what << ") was believed";
  } catch (const remote::NodeFailure& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(role + " node at " + node.address().str()), std::string::npos) << m;
    EXPECT_TRUE(m.find("at macro step") != std::string::npos ||
                m.find("before the run") != std::string::npos)
        << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
  }
}

// Edits the step report that reaches communication point 3.
test::FakeNode::Edit at_step_3(std::function<void(wire::Envelope&)> f) {
  return [f](const wire::Envelope& req, wire::Envelope& reply) {
    if (req.has_step() && req.step().step() == 2 && reply.has_step_report()) f(reply);
    return false;
  };
}

// Edits the final results.
test::FakeNode::Edit in_results(std::function<void(wire::Results&)> f) {
  return [f](const wire::Envelope& req, wire::Envelope& reply) {
    if (req.has_get_results() && reply.has_results()) f(*reply.mutable_results());
    return false;
  };
}

TEST(ReplyCheck, AnHonestNodeIsBelieved) {
  test::FakeNode node("track", nullptr);
  const run::RunRecord r = run_against(node);
  EXPECT_EQ(r.status, "ok");
  EXPECT_EQ(r.deflection.size(), static_cast<std::size_t>(short_scene().rail_nodes()));
}

TEST(ReplyCheck, WrongStepNumberTimeOrIdIsRefused) {
  expect_refused(at_step_3([](wire::Envelope& r) { r.mutable_step_report()->set_step(7); }),
                 "names communication point 7, the request asked for 3");
  expect_refused(at_step_3([](wire::Envelope& r) {
                   r.mutable_step_report()->set_t(r.step_report().t() + 1e-4);
                 }),
                 "the step report gives t = 0.0004 s for communication point 3");
  expect_refused(at_step_3([](wire::Envelope& r) { r.set_id(r.id() + 5); }), "carries id");
}

TEST(ReplyCheck, NonFiniteValuesOfAFiniteStateAreRefused) {
  expect_refused(
      at_step_3([](wire::Envelope& r) { r.mutable_step_report()->set_history(0, kNaN); }),
      "history value [0] is nan", "vehicle");
  expect_refused(
      at_step_3([](wire::Envelope& r) { r.mutable_step_report()->set_max_abs_displacement(kNaN); }),
      "maximum displacement is nan");
  expect_refused(
      at_step_3([](wire::Envelope& r) {
        r.mutable_step_report()->mutable_outputs()->mutable_interfaces(0)->set_displacement(
            0, std::numeric_limits<double>::infinity());
      }),
      "output displacement at interface wr [0] is inf");
}

TEST(ReplyCheck, WrongNumberOfInterfacesValuesOrHistoryIsRefused) {
  expect_refused(at_step_3([](wire::Envelope& r) {
                   r.mutable_step_report()->mutable_outputs()->clear_interfaces();
                 }),
                 "the outputs have 0 interfaces, the participant 1");
  expect_refused(
      at_step_3([](wire::Envelope& r) {
        r.mutable_step_report()->mutable_outputs()->mutable_interfaces(0)->add_displacement(0.0);
      }),
      "output displacement at interface wr has 2 values, expected 1");
  expect_refused(
      at_step_3([](wire::Envelope& r) {
        r.mutable_step_report()->mutable_outputs()->mutable_interfaces(0)->add_force(1.0);
      }),
      "output force at interface wr has 1 value, expected 0 (not sent there)");
  expect_refused(at_step_3([](wire::Envelope& r) { r.mutable_step_report()->clear_history(); }),
                 "carries 0 history values", "vehicle");
}

// Edits the declarations of configure.
test::FakeNode::Edit declaring(std::function<void(wire::Configured&)> f) {
  return [f](const wire::Envelope& req, wire::Envelope& reply) {
    if (req.has_configure() && reply.has_configured()) f(*reply.mutable_configured());
    return false;
  };
}

// A declared name goes into history.csv as it is: one that would forge a
// row, an empty one, one the node declares twice are refused naming the node
// and the name (before, the forged row reached the file and the run was ok).
TEST(ReplyCheck, ChannelNamesOutsideTheDocumentedSetAreRefused) {
  const std::string rule = "1 to 64 characters from A-Z, a-z, 0-9 and _, the first a letter";
  expect_refused(declaring([](wire::Configured& c) { c.add_history("soil_peak_m,fake\n9,9,9"); }),
                 "the history channel 'soil_peak_m?fake?9?9?9': a name with a character other "
                 "than A-Z, a-z, 0-9 and _; a name is " +
                     rule);
  expect_refused(declaring([](wire::Configured& c) { c.add_history(""); }),
                 "the history channel '': an empty name");
  expect_refused(declaring([](wire::Configured& c) { c.add_history("9lives"); }),
                 "'9lives': a name that does not start with a letter");
  expect_refused(declaring([](wire::Configured& c) { c.add_history(std::string(65, 'a')); }),
                 "a name of 65 characters (at most 64)");
  expect_refused(declaring([](wire::Configured& c) {
                   c.add_history("peak");
                   c.add_history("peak");
                 }),
                 "the history channel 'peak', which it declares already");
  expect_refused(declaring([](wire::Configured& c) { c.add_results("rail w"); }),
                 "the result field 'rail?w'");
}

// A node that declares a channel another participant declares (the
// vehicle's wheel_m) would overwrite its column: the run is refused naming both.
TEST(ReplyCheck, AChannelDeclaredByTwoParticipantsIsRefused) {
  test::FakeNode node("track", declaring([](wire::Configured& c) { c.add_history("wheel_m"); }));
  try {
    run_against(node);
    ADD_FAILURE() << "a second wheel_m was accepted";
  } catch (const std::exception& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("track node at " + node.address().str() +
                     " declares the history channel 'wheel_m', which vehicle"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("declares too"), std::string::npos) << m;
  }
}

TEST(ReplyCheck, ResultsOfTheWrongSizeOrNotFiniteAreRefused) {
  const std::string nodes = std::to_string(short_scene().rail_nodes());
  // More rail values than the rail has nodes: the master once wrote memory
  // beyond its array of positions into deflection.csv.
  expect_refused(in_results([](wire::Results& r) {
                   for (int k = 0; k < 40; ++k) r.mutable_fields(0)->add_values(0.0);
                 }),
                 "result field 'rail_w_m' has " + std::to_string(short_scene().rail_nodes() + 40) +
                     " values, the model " + nodes);
  expect_refused(in_results([](wire::Results& r) { r.mutable_fields(0)->clear_values(); }),
                 "result field 'rail_w_m' has 0 values");
  expect_refused(in_results([](wire::Results& r) { r.mutable_fields(0)->set_values(3, kNaN); }),
                 "result field 'rail_w_m' [3] is nan");
  expect_refused(in_results([](wire::Results& r) { r.clear_fields(); }),
                 "the results carry 0 fields, the node declared 1");
  expect_refused(in_results([](wire::Results& r) { r.set_micro_steps(-4); }),
                 "negative micro-step count (-4)");
}

// A node that drips its reply one byte at a time: the deadline holds for
// the whole message (before, every byte restarted it).
TEST(ReplyCheck, ADrippingNodeMeetsTheDeadlineOfAWholeMessage) {
  test::FakeNode node(
      "track", [](const wire::Envelope& req, wire::Envelope&) { return req.has_step(); },
      milliseconds(40));
  remote::RemoteTimeouts t;
  t.step_max = milliseconds(400);  // the first step's deadline
  const auto t0 = Clock::now();
  try {
    run_against(node, t);
    ADD_FAILURE() << "a node that drips its replies held the master";
  } catch (const remote::NodeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("no reply within 400 ms at macro step 0"),
              std::string::npos)
        << e.what();
  }
  // The deadline, plus the time to open the session: far from the 40 ms x
  // (frame bytes) x 20 steps that a deadline per read would allow.
  EXPECT_LT(Clock::now() - t0, milliseconds(1500));
}

// A signal ends a wait on a node within kInterruptPoll, however long its
// deadline.
TEST(ReplyCheck, ASignalEndsAWaitOnANode) {
  test::FakeNode node(
      "track", [](const wire::Envelope& req, wire::Envelope&) { return req.has_step(); },
      milliseconds(200));
  std::atomic<int> stop{0};
  set_interrupt_flag(&stop);
  Clock::time_point raised;
  std::thread raiser([&] {
    while (!node.dripping()) std::this_thread::sleep_for(milliseconds(5));
    std::this_thread::sleep_for(milliseconds(100));
    raised = Clock::now();
    stop = SIGTERM;
  });
  Clock::time_point caught;
  try {
    run_against(node);
    ADD_FAILURE() << "the run ignored the signal";
  } catch (const remote::NodeFailure& e) {
    caught = Clock::now();
    EXPECT_NE(std::string(e.what()).find("interrupted by signal 15"), std::string::npos)
        << e.what();
  }
  raiser.join();
  set_interrupt_flag(nullptr);
  // The wait looks at the flag every kInterruptPoll (100 ms): well within a second.
  EXPECT_LT(caught - raised, std::chrono::seconds(1));
}

// The master program under SIGTERM while a node drips: it exits within a
// second and leaves a summary.json saying why.
TEST(ReplyCheck, TheMasterAnswersSigtermWhileANodeDrips) {
  test::FakeNode node(
      "track", [](const wire::Envelope& req, wire::Envelope&) { return req.has_step(); },
      milliseconds(200));
  namespace fs = std::filesystem;
  const fs::path out =
      fs::temp_directory_path() / ("railcosim_sigterm_" + std::to_string(getpid()));
  fs::remove_all(out);
  const std::string master = std::string(RAILCOSIM_BIN_DIR) + "/master";
  const std::string scene = test::source_path("scenes/paper.toml");
  const std::string track = "track=" + node.address().str();
  std::vector<std::string> args = {master,         "run",    "--scene", scene,   "--case",
                                   "wr-xx-jacobi", "--node", track,     "--out", out.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, master.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  const auto t_wait = Clock::now();
  while (!node.dripping() && Clock::now() - t_wait < std::chrono::seconds(20))
    std::this_thread::sleep_for(milliseconds(10));
  ASSERT_TRUE(node.dripping());
  ::kill(pid, SIGTERM);
  const auto t0 = Clock::now();
  int status = 0;
  waitpid(pid, &status, 0);
  // A wait looks at the flag every kInterruptPoll; the rest is stopping the
  // vehicle node and writing the files.
  EXPECT_LT(Clock::now() - t0, std::chrono::seconds(1));
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream in(out / "wr-xx-jacobi" / "summary.json");
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find("\"status\": \"failed\""), std::string::npos) << s.str();
  EXPECT_NE(s.str().find("signal 15"), std::string::npos) << s.str();
  fs::remove_all(out);
}

}  // namespace reply_check_test
}  // namespace railcosim
