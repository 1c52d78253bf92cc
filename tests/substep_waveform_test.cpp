// Substep waveforms in the coupling (--inputs waveform0..3): a participant
// records its outputs at its micro steps and takes its inputs as waveforms of
// its peers' samples; with implicit coupling the error against the
// monolithic run falls with the waveform's degree; they run in process and
// over TCP (relayed), no other transport.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim {
namespace {

using engine::CouplingMethod;
using engine::CouplingOptions;
using engine::InputMode;
using engine::parse_input_mode;
using engine::waveform_degree;
using engine::zero_inputs;

CouplingOptions coupling(CouplingMethod method, InputMode inputs, double convergence = 1e-10) {
  CouplingOptions c;
  c.method = method;
  c.inputs = inputs;
  c.convergence = convergence;
  c.max_iterations = 60;
  return c;
}

using test::judged;

Scene paper(double end_time, int micro_steps = 0, double tolerance = 0) {
  const Scene s = test::paper_scene();
  std::vector<SceneEdit> edits = {{"simulation.end_time", end_time}};
  if (micro_steps > 0) edits.push_back({"simulation.micro_steps", micro_steps});
  if (tolerance > 0) edits.push_back({"simulation.tolerance", tolerance});
  return with_keys(s, edits);
}

TEST(SubstepWaveform, ModesParseAndNameTheirDegree) {
  for (int d = 0; d <= 3; ++d) {
    const InputMode m = parse_input_mode("waveform" + std::to_string(d), "--inputs");
    EXPECT_EQ(waveform_degree(m), d);
    EXPECT_EQ(to_string(m), "waveform" + std::to_string(d));
  }
  EXPECT_EQ(waveform_degree(InputMode::kLinear), -1);
  EXPECT_THROW(parse_input_mode("waveform4", "--inputs"), std::invalid_argument);
}

TEST(SubstepWaveform, ASubsystemRecordsItsOutputsAtEveryMicroStep) {
  const Scene scene = paper(0.01);
  const std::vector<ParticipantSpec> specs = partition(scene, parse_case("rs-xx-jacobi"));
  SubsystemConfig c;
  c.participant = specs[1];
  c.macro_step = 1e-3;
  c.tolerance = scene.tolerance;
  c.micro_steps = 4;
  Subsystem s(scene, c);
  const CouplingData zero = zero_inputs(scene, specs[1]);
  s.initialize(zero);
  s.record_samples(true);
  s.set_inputs(0, zero);
  const StepResult r = s.step(0);
  const OutputSamples samples = s.step_samples();
  ASSERT_EQ(samples.size(), 5u);  // the start and 4 micro steps
  EXPECT_EQ(samples.front().t, 0.0);
  EXPECT_EQ(samples.back().t, 1e-3);
  EXPECT_EQ(samples.back().outputs, r.outputs);
  // The default Participant takes no waveforms and records nothing.
  struct Plain : Participant {
    std::string name() const override { return "plain"; }
    Channels channels() const override { return {}; }
    CouplingData statics(const CouplingData& in) override { return in; }
    StepResult initialize(const CouplingData&) override { return {}; }
    void set_inputs(long, const CouplingData&) override {}
    CouplingData outputs() override { return {}; }
    void start_step(long) override {}
    StepResult finish_step() override { return {}; }
    ParticipantResults results() override { return {}; }
    ParticipantState save() override { return {}; }
    void restore(const ParticipantState&) override {}
  } plain;
  EXPECT_THROW(plain.set_input_waveforms(0, {}), CallOrderError);
  EXPECT_THROW(plain.record_samples(true), CallOrderError);
}

TEST(SubstepWaveform, WithTheSameMicroStepsImplicitCouplingIsTheMonolithicRun) {
  // Every participant steps at the monolithic run's times, so the receivers
  // evaluate the waveforms at the senders' sample times: converged, the
  // coupling is the monolithic run, whatever the degree.
  const Scene scene = paper(0.02, 4);
  for (const char* name : {"rs-xx-gauss-seidel", "wr-xx-gauss-seidel", "wr-xt-gauss-seidel",
                           "rs-xx-jacobi", "wr-xt-jacobi"}) {
    const run::RunRecord r =
        judged(scene, name, 1e-3, coupling(CouplingMethod::kImplicit, InputMode::kWaveform1));
    ASSERT_EQ(r.status, "ok") << name << ": " << r.message;
    EXPECT_LT(*r.rel_l2_error, 1e-8) << name;
  }
}

TEST(SubstepWaveform, ImplicitErrorFallsWithTheDegree) {
  // Adaptive micro steps: the participants' steps differ, and the waveform
  // interpolates between the sender's samples. A tight tolerance keeps the
  // integrators' own difference (~2e-5 at the scene's 1e-7 m) below the
  // coupling error.
  const Scene scene = paper(0.05, 0, 1e-9);
  const run::RunRecord lin = judged(scene, "rs-xx-gauss-seidel", 1e-3,
                                    coupling(CouplingMethod::kImplicit, InputMode::kLinear, 1e-8));
  std::vector<double> errs;
  for (InputMode m : {InputMode::kWaveform0, InputMode::kWaveform1, InputMode::kWaveform3}) {
    const run::RunRecord r =
        judged(scene, "rs-xx-gauss-seidel", 1e-3, coupling(CouplingMethod::kImplicit, m, 1e-8));
    // Held samples are first order in the micro step and converge slowly.
    if (m != InputMode::kWaveform0) {
      ASSERT_EQ(r.status, "ok") << to_string(m) << ": " << r.message;
    }
    errs.push_back(*r.rel_l2_error);
  }
  std::printf("rs-xx-gauss-seidel, H = 1e-3 s: linear %.2e, waveform0 %.2e, 1 %.2e, 3 %.2e\n",
              *lin.rel_l2_error, errs[0], errs[1], errs[2]);
  EXPECT_LT(errs[1], errs[0]);
  EXPECT_LT(errs[2], errs[1]);
  EXPECT_LT(errs[2], 0.1 * *lin.rel_l2_error) << errs[2] << " " << *lin.rel_l2_error;
}

TEST(SubstepWaveform, ExplicitGaussSeidelTakesTheFreshSamples) {
  const Scene scene = paper(0.05);
  const run::RunRecord hold = judged(scene, "rs-xx-gauss-seidel", 1e-3,
                                     coupling(CouplingMethod::kExplicit, InputMode::kLinear));
  const run::RunRecord wave = judged(scene, "rs-xx-gauss-seidel", 1e-3,
                                     coupling(CouplingMethod::kExplicit, InputMode::kWaveform3));
  ASSERT_EQ(wave.status, "ok") << wave.message;
  EXPECT_LT(*wave.rel_l2_error, *hold.rel_l2_error);
}

TEST(SubstepWaveform, TheModesRunInProcessAndOverTcpOnly) {
  // Over tcp the runner relays them (tcp_waveform_test.cpp runs them there).
  CouplingOptions c = coupling(CouplingMethod::kImplicit, InputMode::kWaveform3);
  EXPECT_NO_THROW(remote::check_transport(c, "inproc"));
  EXPECT_NO_THROW(remote::check_transport(c, "tcp"));
  try {
    remote::check_transport(c, "carrier-pigeon");
    FAIL() << "a waveform coupling on an unknown transport";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "--inputs waveform3: substep waveforms travel in process or over tcp (relayed data "
              "plane), not over the carrier-pigeon transport (use --transport inproc or tcp)");
  }
  c.inputs = InputMode::kLinear;
  EXPECT_NO_THROW(remote::check_transport(c, "carrier-pigeon"));
}

}  // namespace
}  // namespace railcosim
