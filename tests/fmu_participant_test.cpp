// An FMU as a participant (fmu_node/fmu_participant), driven in process as
// the master drives any participant: the Dahlquist test FMUs stepped to
// 0.9^100 bit for bit through the interface mapping, a parameter set from
// the configuration, save and restore repeating a step bit for bit, the
// FMU without state save refused as explicit only, and the configuration's
// refusals naming file and key.
#include <gtest/gtest.h>

#include <string>

#include "fmu_participant.hpp"
#include "process_support.hpp"

namespace fmu_participant_test {
using namespace railcosim;

const std::string kFmus = std::string(RAILCOSIM_BIN_DIR) + "/fmus/";

double closed_form(int steps, double factor = 0.9) {
  double x = 1;
  for (int i = 0; i < steps; ++i) x = factor * x;
  return x;
}

// One interface at ss, one point: receives a velocity (the FMU's u), sends
// a displacement (its x); `extra` adds configuration lines.
ParticipantSetup setup_for(const std::string& fmu, const std::string& extra = "",
                           std::vector<Quantity> sends = {Quantity::kDisplacement}) {
  ParticipantSetup s;
  s.participant = "soil";
  Interface itf;
  itf.cut = "ss";
  itf.peer = "track";
  itf.x = {0.0};
  itf.receives = {Quantity::kVelocity};
  itf.sends = std::move(sends);
  s.interfaces = {itf};
  s.run.macro_step = 0.1;
  s.run.end_time = 10;
  s.config = OwnConfig::parse("file = \"" + kFmus + fmu + ".fmu\"\n" +
                                  "ss_in_velocity = \"u\"\nss_out_displacement = \"x\"\n" + extra,
                              "fmu.toml", "fmu");
  return s;
}

const CouplingData kNoInput{InterfaceData{{}, {0.0}, {}}};

double x_of(Participant& p) {
  return p.outputs().at(0).displacement.at(0);
}

class FmuParticipantVersions : public ::testing::TestWithParam<std::string> {};

TEST_P(FmuParticipantVersions, StepsToTheClosedFormThroughTheInterface) {
  FmuParticipant p(setup_for(GetParam()));
  EXPECT_EQ(p.statics(kNoInput).at(0).displacement, std::vector<double>{1.0});
  const StepResult r0 = p.initialize(kNoInput);
  EXPECT_EQ(r0.outputs.at(0).displacement, std::vector<double>{1.0});
  EXPECT_TRUE(r0.outputs.at(0).force.empty());
  StepResult r;
  for (long n = 0; n < 100; ++n) {
    p.set_inputs(n, kNoInput);
    r = p.step(n);
  }
  EXPECT_EQ(r.outputs.at(0).displacement.at(0), closed_form(100));  // bit for bit
  EXPECT_EQ(r.max_abs_displacement, closed_form(100));
  EXPECT_TRUE(r.finite);
  EXPECT_EQ(p.results().micro_steps, 100);
}

TEST_P(FmuParticipantVersions, SetsParametersAndInputs) {
  FmuParticipant p(setup_for(GetParam(), "set_k = 2.0\n"));
  p.initialize(kNoInput);
  p.set_inputs(0, {InterfaceData{{}, {5.0}, {}}});
  p.step(0);
  EXPECT_EQ(x_of(p), (1 - 2 * 0.1) * 1.0 + 0.1 * 5.0);
}

TEST_P(FmuParticipantVersions, RepeatsAStepFromASavedStateBitForBit) {
  FmuParticipant p(setup_for(GetParam()));
  p.initialize(kNoInput);
  for (long n = 0; n < 10; ++n) {
    p.set_inputs(n, kNoInput);
    p.step(n);
  }
  const ParticipantState s = p.save();
  p.set_inputs(10, {InterfaceData{{}, {3.0}, {}}});
  p.step(10);
  const double first = x_of(p);
  p.set_inputs(11, kNoInput);
  p.step(11);
  p.restore(s);
  EXPECT_EQ(x_of(p), closed_form(10));
  p.set_inputs(10, {InterfaceData{{}, {3.0}, {}}});
  p.step(10);
  EXPECT_EQ(x_of(p), first);
  EXPECT_EQ(first, 0.9 * closed_form(10) + 0.1 * 3.0);
}

TEST_P(FmuParticipantVersions, DeclaresTheHistoryAndResultsItsConfigurationNames) {
  FmuParticipant p(setup_for(GetParam(), "peak_history = \"peak_m\"\nresult_final_x = \"x\"\n"));
  EXPECT_EQ(p.channels().history, std::vector<std::string>{"peak_m"});
  EXPECT_EQ(p.channels().results, std::vector<std::string>{"final_x"});
  EXPECT_EQ(p.initialize(kNoInput).history, std::vector<double>{1.0});
  p.set_inputs(0, kNoInput);
  EXPECT_EQ(p.step(0).history, std::vector<double>{0.9});
  EXPECT_EQ(p.results().fields, std::vector<std::vector<double>>{{0.9}});
  try {
    FmuParticipant q(setup_for(GetParam(), "result_y = \"y_{i}\"\n"));
    FAIL() << "a result of no variable was declared";
  } catch (const BadRequestError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'fmu.result_y': the FMU has no real variable 'y_0'"),
              std::string::npos)
        << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(BothVersions, FmuParticipantVersions,
                         ::testing::Values("dahlquist2", "dahlquist3"));

// The message of the BadRequestError that building the participant throws.
std::string refusal(const ParticipantSetup& s) {
  try {
    FmuParticipant p(s);
  } catch (const BadRequestError& e) {
    return e.what();
  }
  ADD_FAILURE() << "not refused";
  return "";
}

TEST(FmuParticipantRefusals, AnFmuWithoutStateSaveIsExplicitOnly) {
  FmuParticipant p(setup_for("dahlquist2_nostate"));
  p.initialize(kNoInput);
  try {
    p.save();
    FAIL() << "a state was saved";
  } catch (const BadRequestError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot save its state"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("explicit coupling only"), std::string::npos);
  }
}

TEST(FmuParticipantRefusals, NamesTheKeyOfAMappingItCannotServe) {
  ParticipantSetup s = setup_for("dahlquist2");
  s.config = OwnConfig::parse("file = \"" + kFmus + "dahlquist2.fmu\"\nss_in_velocity = \"u\"\n",
                              "fmu.toml", "fmu");
  EXPECT_NE(refusal(s).find("fmu.toml: key 'fmu.ss_out_displacement'"), std::string::npos)
      << refusal(s);
  // An interface that sends a force needs its key.
  std::string m = refusal(setup_for("dahlquist2", "", {Quantity::kForce}));
  EXPECT_NE(m.find("fmu.toml: key 'fmu.ss_out_force'"), std::string::npos) << m;
  ParticipantSetup f = setup_for("dahlquist2", "", {Quantity::kForce});
  f.config = OwnConfig::parse(
      "file = \"" + kFmus + "dahlquist2.fmu\"\nss_in_velocity = \"u\"\nss_out_force = \"x\"\n",
      "fmu.toml", "fmu");
  m = refusal(f);
  EXPECT_NE(m.find("variable 'x' is in m, the interface's force in N"), std::string::npos) << m;
  f.config = OwnConfig::parse(
      "file = \"" + kFmus + "dahlquist2.fmu\"\nss_in_velocity = \"u\"\nss_out_force = \"y\"\n",
      "fmu.toml", "fmu");
  EXPECT_NE(refusal(f).find("the FMU has no variable 'y'"), std::string::npos) << refusal(f);
  f.config = OwnConfig::parse(
      "file = \"" + kFmus + "dahlquist2.fmu\"\nss_in_velocity = \"x\"\nss_out_force = \"u\"\n",
      "fmu.toml", "fmu");
  EXPECT_NE(refusal(f).find("variable 'x' is output (Real), not a real input"), std::string::npos)
      << refusal(f);
}

TEST(FmuParticipantRefusals, NamesUnknownKeysParametersAndTheFmuFile) {
  std::string m = refusal(setup_for("dahlquist3", "ss_out_displacment = \"x\"\n"));
  EXPECT_NE(m.find("key 'fmu.ss_out_displacment': not a key of the FMU participant"),
            std::string::npos)
      << m;
  m = refusal(setup_for("dahlquist3", "set_q = 1.0\n"));
  EXPECT_NE(m.find("key 'fmu.set_q': the FMU has no real parameter 'q'"), std::string::npos) << m;
  ParticipantSetup s = setup_for("dahlquist3");
  s.interfaces[0].x = {0.0, 0.6};
  m = refusal(s);
  EXPECT_NE(m.find("\"u\" names one variable for 2 coupling points: put {i}"), std::string::npos)
      << m;
  s = setup_for("missing");
  m = refusal(s);
  EXPECT_NE(m.find("key 'fmu.file': "), std::string::npos) << m;
  EXPECT_NE(m.find("missing.fmu: cannot be read"), std::string::npos) << m;
}

TEST(FmuNode, StartsWithItsConfigurationChecked) {
  const auto dir = test::temp_dir("fmu_node");
  std::ofstream(dir / "fmu.toml") << "[soil]\nfile = \"" << kFmus
                                  << "dahlquist2.fmu\"\nss_in_velocity = \"u\"\n"
                                     "ss_out_displacement = \"x\"\n";
  auto o = test::run_program("fmu_node",
                             "--role soil --config " + (dir / "fmu.toml").string() + " --check");
  EXPECT_EQ(o.status, 0) << o.output;
  o = test::run_program("fmu_node", "--role soil --config " + (dir / "nothing.toml").string());
  EXPECT_NE(o.status, 0) << o.output;
  EXPECT_NE(o.output.find("nothing.toml"), std::string::npos) << o.output;
  std::filesystem::remove_all(dir);
}

}  // namespace fmu_participant_test
