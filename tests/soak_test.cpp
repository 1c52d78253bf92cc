// Soak: 200 sessions back to back against one pair of nodes. Their resident
// memory must not grow by more than 10% once the first sessions have warmed
// them up (allocator pools, caches): anything a session leaks would add up.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "node_launcher.hpp"
#include "remote_participant.hpp"
#include "runner.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

long resident_kib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

TEST(Soak, TwoHundredSessionsDoNotGrowTheNodes) {
  Scene scene = test::paper_scene();
  scene.end_time = 0.005;  // 50 macro steps a session
  LaunchedNode vehicle("vehicle_node", std::chrono::seconds(10));
  LaunchedNode track("track_node", std::chrono::seconds(10));
  const Address va = vehicle.address(), ta = track.address();
  const ParticipantFactory tcp = [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<RemoteParticipant>(c.side == Side::kS1 ? va : ta, scene, c);
  };
  RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  // Alternate the cuts so that both kinds of subsystem are built and freed.
  const CaseSpec cases[] = {parse_case("wr-xx-jacobi"), parse_case("rs-xt-gauss-seidel")};
  long warm_v = 0, warm_t = 0;
  std::vector<double> first_deflection;
  for (int s = 0; s < 200; ++s) {
    const RunRecord r = run_cosim(scene, cases[s % 2], o, tcp, "tcp");
    ASSERT_EQ(r.status, "ok") << "session " << s << ": " << r.message;
    if (s == 0) first_deflection = r.deflection;
    if (s % 2 == 0) {
      ASSERT_EQ(r.deflection, first_deflection) << "session " << s;  // the same every time
    }
    if (s == 19) {
      warm_v = resident_kib(vehicle.pid());
      warm_t = resident_kib(track.pid());
    }
  }
  const long end_v = resident_kib(vehicle.pid()), end_t = resident_kib(track.pid());
  ASSERT_GT(warm_v, 0);
  ASSERT_GT(warm_t, 0);
  EXPECT_LE(end_v, warm_v * 11 / 10)
      << "vehicle node: " << warm_v << " KiB after 20 sessions, " << end_v << " KiB after 200";
  EXPECT_LE(end_t, warm_t * 11 / 10)
      << "track node: " << warm_t << " KiB after 20 sessions, " << end_t << " KiB after 200";
  std::printf(
      "resident memory after 20 / 200 sessions: vehicle %ld / %ld KiB, track %ld / %ld KiB\n",
      warm_v, end_v, warm_t, end_t);
}

}  // namespace
}  // namespace railcosim
