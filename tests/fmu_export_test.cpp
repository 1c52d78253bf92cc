// The built-in vehicle exported as an FMI 3.0 FMU (fmu_export/), loaded
// back by our own host as a participant (FmuParticipant) and driven beside
// the built-in vehicle Subsystem of the same scene and case with the same
// inputs: statics, every step's outputs and a step repeated from a saved
// state, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cosim_case.hpp"
#include "fmu_participant.hpp"
#include "model.hpp"
#include "process_support.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace fmu_export_test {
using namespace railcosim;

const std::string kFmu = std::string(RAILCOSIM_BIN_DIR) + "/fmus/railcosim_vehicle.fmu";

struct Pair {
  Scene scene = load_scene(std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/paper.toml");
  std::unique_ptr<Subsystem> builtin;
  std::unique_ptr<FmuParticipant> exported;
  std::vector<Quantity> receives;  // what the vehicle's interface receives

  Pair() {
    ParticipantSpec vehicle;
    for (const auto& p : partition(scene, parse_case("wr-xx-jacobi")))
      if (p.role == "vehicle") vehicle = p;
    builtin = std::make_unique<Subsystem>(
        scene, subsystem_config(scene, vehicle, scene.macro_step, scene.tolerance));
    ParticipantSetup s;
    s.participant = "vehicle";
    Interface wr;
    wr.cut = "wr";
    wr.upper = true;
    wr.x = {0.0};
    wr.receives = receives = vehicle.interfaces.at(0).receives();
    wr.sends = vehicle.interfaces.at(0).sends();
    s.interfaces = {wr};
    s.run.macro_step = scene.macro_step;
    std::string config = "file = \"" + kFmu + "\"\n";
    for (Quantity q : wr.receives)
      config += "wr_in_" + to_string(q) + " = \"wr_in_" + to_string(q) + "\"\n";
    for (Quantity q : wr.sends)
      config += "wr_out_" + to_string(q) + " = \"wr_out_" + to_string(q) + "\"\n";
    s.config = OwnConfig::parse(config, "vehicle.toml", "vehicle");
    exported = std::make_unique<FmuParticipant>(s);
  }
};

// The rail under the wheel: displacement (and velocity) at step n.
CouplingData rail(long n, const std::vector<Quantity>& receives) {
  InterfaceData d;
  const double t = static_cast<double>(n) * 1e-4;
  for (Quantity q : receives) {
    if (q == Quantity::kDisplacement) d.displacement = {1e-4 + 2e-5 * std::sin(300 * t)};
    if (q == Quantity::kVelocity) d.velocity = {6e-3 * std::cos(300 * t)};
    if (q == Quantity::kForce) d.force = {1e5 + 1e4 * std::sin(300 * t)};
  }
  return {d};
}

TEST(FmuExport, TheVehicleFmuStepsAsTheBuiltInVehicleBitForBit) {
  Pair p;
  const std::vector<Quantity> in = p.receives;

  EXPECT_EQ(p.exported->statics(rail(0, in)), p.builtin->statics(rail(0, in)));
  EXPECT_EQ(p.exported->initialize(rail(0, in)).outputs,
            p.builtin->initialize(rail(0, in)).outputs);
  ParticipantState saved_builtin, saved_exported;
  CouplingData at_save;
  double low = 1, high = -1;  // the wheel's displacement over the run
  for (long n = 0; n < 300; ++n) {
    p.builtin->set_inputs(n, rail(n, in));
    p.exported->set_inputs(n, rail(n, in));
    const StepResult b = p.builtin->step(n), e = p.exported->step(n);
    ASSERT_EQ(e.outputs, b.outputs) << "macro step " << n;
    low = std::min(low, e.outputs.at(0).displacement.at(0));
    high = std::max(high, e.outputs.at(0).displacement.at(0));
    if (n == 149) {
      saved_builtin = p.builtin->save();
      saved_exported = p.exported->save();
    }
    if (n == 150) at_save = e.outputs;
  }
  EXPECT_GT(high - low, 1e-6) << "the wheel did not move: the comparison shows nothing";
  // A step repeated from the saved state, on both, the same as before.
  p.builtin->restore(saved_builtin);
  p.exported->restore(saved_exported);
  p.builtin->set_inputs(150, rail(150, in));
  p.exported->set_inputs(150, rail(150, in));
  EXPECT_EQ(p.exported->step(150).outputs, at_save);
  EXPECT_EQ(p.builtin->step(150).outputs, at_save);
}

TEST(FmuExport, TheVehicleFmuPassesOurOwnCheck) {
  const auto o = test::run_master("fmu check " + kFmu);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("FMI 3.0 co-simulation, model 'railcosim vehicle'"), std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("default experiment: 0 s to 0.25 s, 2500 steps of 0.0001 s: PASS"),
            std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("state round trip: PASS"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("verdict: explicit and implicit coupling"), std::string::npos)
      << o.output;
}

}  // namespace fmu_export_test
