// Soak: 200 sessions back to back against one set of nodes (vehicle, track
// and soil). Their resident memory must not grow by more than 10% once the
// first sessions have warmed them up (allocator pools, caches): anything a
// session leaks would add up.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "remote/node_launcher.hpp"
#include "remote/remote_participant.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
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
  // 50 macro steps a session.
  const Scene scene = with_keys(load_scene(test::source_path("scenes/soil.toml")),
                                {{"simulation.end_time", 0.005}});
  const std::vector<std::string> roles = {"vehicle", "track", "soil"};
  std::map<std::string, std::unique_ptr<remote::LaunchedNode>> nodes;
  std::map<std::string, Address> at;
  for (const std::string& role : roles) {
    nodes[role] = std::make_unique<remote::LaunchedNode>(role + "_node", std::chrono::seconds(10));
    at[role] = nodes[role]->address();
  }
  const remote::ParticipantFactory tcp =
      [&](const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    return std::make_unique<remote::RemoteParticipant>(at.at(c.participant.role), scene, c);
  };
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  // Every session uses the three nodes; alternating the cuts builds and
  // frees both kinds of vehicle and track participant (with and without the
  // rail) and both kinds of soil participant (receiving forces or motions).
  const CaseSpec cases[] = {parse_case("wr-xx+ss-xt-gauss-seidel"),
                            parse_case("rs-xt+ss-xx-jacobi")};
  std::map<std::string, long> warm;
  std::vector<double> first_deflection;
  for (int s = 0; s < 200; ++s) {
    const run::RunRecord r = run::run_cosim(scene, cases[s % 2], o, tcp, "tcp");
    ASSERT_EQ(r.status, "ok") << "session " << s << ": " << r.message;
    ASSERT_EQ(r.micro_steps.size(), 3u) << "session " << s;
    if (s == 0) first_deflection = r.deflection;
    if (s % 2 == 0) {
      ASSERT_EQ(r.deflection, first_deflection) << "session " << s;  // the same every time
    }
    if (s == 19)
      for (const std::string& role : roles) warm[role] = resident_kib(nodes[role]->pid());
  }
  for (const std::string& role : roles) {
    const long end = resident_kib(nodes[role]->pid());
    ASSERT_GT(warm[role], 0) << role;
    EXPECT_LE(end, warm[role] * 11 / 10)
        << role << " node: " << warm[role] << " KiB after 20 sessions, " << end << " KiB after 200";
    std::printf("%s node: resident memory %ld KiB after 20 sessions, %ld KiB after 200\n",
                role.c_str(), warm[role], end);
  }
}

}  // namespace
}  // namespace railcosim
