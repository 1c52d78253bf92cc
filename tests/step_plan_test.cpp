// The step plan: the one place that decides the participants' order,
// printed for the paper's cases and for three participants and compared
// with plans written out by hand.
#include "engine/step_plan.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "scene.hpp"

namespace railcosim {
namespace {

// The plan of a case on the fixed soil (`soil`: the lumped one), a
// participant sending a force where its spec's exchange types say so.
std::string plan_of(const std::string& name, Feedthrough feedthrough = Feedthrough::kLagged,
                    bool implicit = false, bool soil = false) {
  Scene scene;
  if (soil) scene.soil_model = "lumped";
  const CaseSpec spec = parse_case(name);
  const std::vector<ParticipantSpec> specs = partition(scene, spec);
  std::vector<bool> force;
  std::vector<std::string> roles;
  for (const ParticipantSpec& p : specs) {
    bool f = false;
    for (const InterfaceSpec& i : p.interfaces) f = f || i.sends_force();
    force.push_back(f);
    roles.push_back(p.role);
  }
  const engine::StepPlan plan =
      engine::plan_steps(engine::make_routing(specs), {spec.scheme, feedthrough, implicit}, force);
  return plan.describe(roles);
}

const char* const kJacobi =
    "stage 1: vehicle track\n"
    "vehicle.0 <- track.0: point n\n"
    "track.0 <- vehicle.0: point n\n";
const char* const kGaussSeidel =
    "stage 1: vehicle\n"
    "stage 2: track\n"
    "vehicle.0 <- track.0: point n\n"
    "track.0 <- vehicle.0: point n+1\n";

TEST(StepPlan, ThePapersCasesStepTogetherOrInLoadOrder) {
  for (const char* cut : {"wr", "rs"})
    for (const char* type : {"xx", "xt"}) {
      const std::string c = std::string(cut) + "-" + type;
      EXPECT_EQ(plan_of(c + "-jacobi"), kJacobi) << c;
      EXPECT_EQ(plan_of(c + "-gauss-seidel"), kGaussSeidel) << c;
    }
}

TEST(StepPlan, ResolvedFeedthroughRefreshesTheSenderOfTheForce) {
  const char* const resolved =
      "stage 1: vehicle (refreshed) track\n"
      "vehicle.0 <- track.0: point n\n"
      "track.0 <- vehicle.0: point n, refreshed\n";
  EXPECT_EQ(plan_of("wr-xt-jacobi", Feedthrough::kResolved), resolved);
  EXPECT_EQ(plan_of("rs-xt-jacobi", Feedthrough::kResolved), resolved);
  // Nothing to refresh where no force is sent.
  EXPECT_EQ(plan_of("rs-xx-jacobi", Feedthrough::kResolved), kJacobi);
  EXPECT_THROW(plan_of("wr-xt-gauss-seidel", Feedthrough::kResolved), std::invalid_argument);
}

TEST(StepPlan, ImplicitCouplingIteratesWhatIsNotKnownWhenTheReceiverSteps) {
  EXPECT_EQ(plan_of("wr-xt-jacobi", Feedthrough::kLagged, true),
            "stage 1: vehicle track\n"
            "vehicle.0 <- track.0: point n, iterated\n"
            "track.0 <- vehicle.0: point n, iterated\n");
  EXPECT_EQ(plan_of("rs-xx-gauss-seidel", Feedthrough::kLagged, true),
            "stage 1: vehicle\n"
            "stage 2: track\n"
            "vehicle.0 <- track.0: point n, iterated\n"
            "track.0 <- vehicle.0: point n+1\n");
}

TEST(StepPlan, ThreeParticipants) {
  EXPECT_EQ(plan_of("wr-xx+ss-xt-gauss-seidel", Feedthrough::kLagged, false, true),
            "stage 1: vehicle\n"
            "stage 2: track\n"
            "stage 3: soil\n"
            "vehicle.0 <- track.0: point n\n"
            "track.0 <- vehicle.0: point n+1\n"
            "track.1 <- soil.0: point n\n"
            "soil.0 <- track.1: point n+1\n");
  // The track sends the ballast's force to the soil: every receiver of the
  // track's outputs takes them refreshed, the vehicle too.
  EXPECT_EQ(plan_of("wr-xx+ss-xt-jacobi", Feedthrough::kResolved, false, true),
            "stage 1: vehicle track (refreshed) soil\n"
            "vehicle.0 <- track.0: point n, refreshed\n"
            "track.0 <- vehicle.0: point n\n"
            "track.1 <- soil.0: point n\n"
            "soil.0 <- track.1: point n, refreshed\n");
  EXPECT_EQ(plan_of("wr-xt+rs-xx+ss-xt-gauss-seidel", Feedthrough::kLagged, true, true),
            "stage 1: vehicle\n"
            "stage 2: rail\n"
            "stage 3: track\n"
            "stage 4: soil\n"
            "vehicle.0 <- rail.0: point n, iterated\n"
            "rail.0 <- vehicle.0: point n+1\n"
            "rail.1 <- track.0: point n, iterated\n"
            "track.0 <- rail.1: point n+1\n"
            "track.1 <- soil.0: point n, iterated\n"
            "soil.0 <- track.1: point n+1\n");
}

}  // namespace
}  // namespace railcosim
