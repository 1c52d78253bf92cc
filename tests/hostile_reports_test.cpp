// The master on the direct data plane against a node that lies about its
// window: report frames with another request's id, a step report past the
// window's end, a WindowDone naming another step than its reports reached.
// Each is refused, naming that node (before, all three were tolerated and
// the run ended `ok`).
#include <gtest/gtest.h>
#include <sys/socket.h>

#include "fake_node.hpp"
#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using std::chrono::milliseconds;

// Rewrites a report frame with `edit` and sends it.
test::FakeNode::Reports rewrite_reports(std::function<void(wire::Envelope&)> edit) {
  return [edit](int fd, const std::string& frame, const std::atomic<bool>&) {
    wire::Envelope e;
    e.ParseFromArray(frame.data() + 4, static_cast<int>(frame.size() - 4));
    edit(e);
    const std::string out = encode_frame(e);
    (void)::send(fd, out.data(), out.size(), MSG_NOSIGNAL);
  };
}

// Whether `e` reports macro step `step`.
bool reports_step(const wire::Envelope& e, long step) {
  for (const auto& r : e.reports().reports())
    if (static_cast<long>(r.step()) == step) return true;
  return false;
}

// wr-xx-jacobi over 200 macro steps, one window, the vehicle on `vehicle`
// and the track on a real node: the failure's message ("" if none).
std::string run_against(test::FakeNode& vehicle) {
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
  } catch (const remote::NodeFailure& e) {
    return e.what();
  }
  return "";
}

TEST(HostileReports, ReportFramesWithAnotherIdAreRefused) {
  test::FakeNode vehicle("vehicle", nullptr, {}, rewrite_reports([](wire::Envelope& e) {
                           if (reports_step(e, 21) || e.reports().reports_size() == 0)
                             e.set_id(e.id() + 1000);
                         }));
  const std::string m = run_against(vehicle);
  EXPECT_NE(
      m.find("vehicle node at " + vehicle.address().str() + ": bad reply: the reply carries id "),
      std::string::npos)
      << m;
}

TEST(HostileReports, AStepReportPastTheWindowsEndIsRefused) {
  test::FakeNode vehicle("vehicle", nullptr, {}, rewrite_reports([](wire::Envelope& e) {
                           if (!reports_step(e, 200)) return;
                           wire::StepReport extra =
                               e.reports().reports(e.reports().reports_size() - 1);
                           extra.set_step(201);
                           extra.set_t(extra.t() * 201.0 / 200.0);
                           *e.mutable_reports()->add_reports() = extra;
                         }));
  const std::string m = run_against(vehicle);
  EXPECT_NE(m.find("vehicle node at " + vehicle.address().str() +
                   ": bad reply: a step report for macro step 201, past the end of the window "
                   "granted (macro step 200)"),
            std::string::npos)
      << m;
}

TEST(HostileReports, AWindowDoneAtAnotherStepIsRefused) {
  test::FakeNode vehicle(
      "vehicle",
      [](const wire::Envelope&, wire::Envelope& reply) {
        if (reply.has_window_done()) reply.mutable_window_done()->set_step(150);
        return false;
      },
      {}, rewrite_reports([](wire::Envelope&) {}));
  const std::string m = run_against(vehicle);
  EXPECT_NE(m.find("vehicle node at " + vehicle.address().str() +
                   ": its window ended at macro step 150, but its step reports stop at macro "
                   "step 200"),
            std::string::npos)
      << m;
}

}  // namespace
}  // namespace railcosim
