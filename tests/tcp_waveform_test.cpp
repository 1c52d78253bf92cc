// Substep waveforms (--inputs waveform1, waveform3) over real TCP node
// processes, on both data planes (relayed, and direct in lock step): the
// senders' micro-step samples and the receivers' input waveforms cross the
// wire, and every run is bitwise equal to its in-process twin, explicit and
// implicit (IQN-ILS). A node whose participant
// takes no waveforms ends the run with an error naming it and the option.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <thread>

#include "cosim_support.hpp"
#include "remote/remote_participant.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "server.hpp"
#include "subsystem.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using engine::AcceleratorKind;
using engine::CouplingMethod;
using engine::InputMode;
using engine::zero_inputs;

using remote::DataPlane;
using remote::inproc_factory;
using remote::NodePool;
using remote::RemoteParticipant;
using remote::SceneTransport;
using remote::tcp_transport;

// 300 macro steps of the paper scene. A tolerance 100 times tighter than
// the scene's makes every participant take several adaptive micro steps,
// at times that differ between them: a receiver evaluates its waveforms
// between the sender's samples, where the degree counts.
Scene short_paper() {
  const Scene paper = test::paper_scene();
  const Scene s = with_keys(
      paper, {{"simulation.end_time", 300 * paper.macro_step}, {"simulation.tolerance", 1e-9}});
  return s;
}

run::RunOptions waveform_run(const Scene& scene, InputMode inputs, CouplingMethod method,
                             Feedthrough feedthrough) {
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  o.feedthrough = feedthrough;
  o.coupling.method = method;
  o.coupling.inputs = inputs;
  o.coupling.accelerator.kind = AcceleratorKind::kIqnIls;
  o.coupling.convergence = 1e-10;
  o.coupling.max_iterations = 60;
  return o;
}

void expect_tcp_equals_inproc(const Scene& scene, const char* name, run::RunOptions o,
                              NodePool& pool) {
  const CaseSpec spec = parse_case(name);
  const run::RunRecord local = run::run_cosim(scene, spec, o, inproc_factory(scene), "inproc");
  ASSERT_EQ(local.status, "ok") << name << ": " << local.message;
  for (DataPlane plane : {DataPlane::kRelay, DataPlane::kDirect}) {
    o.data_plane = plane;
    const run::RunRecord remote =
        run::run_cosim(scene, spec, o, tcp_transport(scene, {}, pool).factory, "tcp");
    const std::string what = std::string(name) + " " + o.coupling.label() + " " + to_string(plane);
    ASSERT_EQ(remote.status, "ok") << what << ": " << remote.message;
    EXPECT_EQ(remote.data_plane, to_string(plane)) << what;
    EXPECT_EQ(remote.data_plane_mode, plane == DataPlane::kDirect ? "lock step" : "") << what;
    EXPECT_EQ(remote.inputs, to_string(o.coupling.inputs)) << what;
    EXPECT_EQ(remote.macro_steps, scene.macro_steps()) << what;
    EXPECT_EQ(remote.micro_steps, local.micro_steps) << what;
    EXPECT_EQ(remote.deflection, local.deflection) << what;  // exact double equality
    EXPECT_EQ(remote.extra_channels, local.extra_channels) << what;
    ASSERT_EQ(remote.history.size(), local.history.size()) << what;
    for (std::size_t i = 0; i < local.history.size(); ++i) {
      EXPECT_EQ(remote.history[i].t, local.history[i].t) << what << " row " << i;
      EXPECT_EQ(remote.history[i].wheel, local.history[i].wheel) << what << " row " << i;
      EXPECT_EQ(remote.history[i].contact_force, local.history[i].contact_force)
          << what << " row " << i;
      EXPECT_EQ(remote.history[i].extra, local.history[i].extra) << what << " row " << i;
    }
    ASSERT_EQ(remote.convergence.size(), local.convergence.size()) << what;
    for (std::size_t i = 0; i < local.convergence.size(); ++i) {
      EXPECT_EQ(remote.convergence[i].step, local.convergence[i].step) << what;
      EXPECT_EQ(remote.convergence[i].iteration, local.convergence[i].iteration) << what;
      EXPECT_EQ(remote.convergence[i].residual, local.convergence[i].residual) << what;
    }
    if (o.coupling.method == CouplingMethod::kImplicit) {
      ASSERT_TRUE(local.iterations_mean.has_value()) << what;
      EXPECT_GT(*local.iterations_mean, 1.0) << what;  // the iterations ran over the wire
    }
  }
}

class TcpWaveform : public ::testing::TestWithParam<CouplingMethod> {
 protected:
  static void SetUpTestSuite() { pool_ = std::make_unique<NodePool>(); }
  static void TearDownTestSuite() { pool_.reset(); }
  static inline std::unique_ptr<NodePool> pool_;
};

// Gauss-Seidel: the later participant takes the earlier one's fresh samples.
TEST_P(TcpWaveform, GaussSeidelBitwiseEqualToInProcess) {
  const Scene scene = short_paper();
  for (InputMode m : {InputMode::kWaveform1, InputMode::kWaveform3})
    expect_tcp_equals_inproc(scene, "rs-xx-gauss-seidel",
                             waveform_run(scene, m, GetParam(), Feedthrough::kLagged), *pool_);
}

// Jacobi: each participant takes the other's samples of the last iteration
// (implicit) or its held value (explicit).
TEST_P(TcpWaveform, JacobiBitwiseEqualToInProcess) {
  const Scene scene = short_paper();
  for (InputMode m : {InputMode::kWaveform1, InputMode::kWaveform3})
    expect_tcp_equals_inproc(scene, "wr-xt-jacobi",
                             waveform_run(scene, m, GetParam(), Feedthrough::kLagged), *pool_);
}

INSTANTIATE_TEST_SUITE_P(Methods, TcpWaveform,
                         ::testing::Values(CouplingMethod::kExplicit, CouplingMethod::kImplicit),
                         [](const auto& p) {
                           return p.param == CouplingMethod::kExplicit ? std::string("explicit")
                                                                       : std::string("implicit");
                         });

// One participant driven by hand: waveforms in a SetInputs (flushed before
// get_outputs) and with a Step, and the samples of its step reports, equal
// bit for bit to the same calls on a Subsystem in process.
TEST(TcpWaveformProxy, SetInputsAndStepCarryWaveformsBitwise) {
  const Scene scene = short_paper();
  const SubsystemConfig cfg = test::config_of(scene, "rs-xx-gauss-seidel", "track");
  NodePool pool;
  RemoteParticipant remote(pool.address("track"), scene, cfg);
  Subsystem local(scene, cfg);
  const CouplingData zero = zero_inputs(scene, cfg.participant);
  ASSERT_EQ(remote.initialize(zero).outputs, local.initialize(zero).outputs);
  remote.record_samples(true);
  local.record_samples(true);
  EXPECT_TRUE(remote.step_samples().empty());
  const std::size_t width = pack_values(zero[0]).size();
  for (long n = 0; n < 3; ++n) {
    Waveform w(3, width);
    for (int k = 0; k <= 4; ++k) {
      const double t = (static_cast<double>(n) + k / 4.0) * scene.macro_step;
      std::vector<double> v(width);
      for (std::size_t c = 0; c < width; ++c) v[c] = 1e-6 * std::sin(1e3 * t + 0.1 * c);
      w.add(t, v);
    }
    remote.set_input_waveforms(n, {w});
    local.set_input_waveforms(n, {w});
    if (n == 1) {
      EXPECT_EQ(remote.outputs(), local.outputs()) << n;  // via SetInputs
    }
    const StepResult a = remote.step(n), b = local.step(n);
    EXPECT_EQ(a.outputs, b.outputs) << n;
    const OutputSamples sa = remote.step_samples(), sb = local.step_samples();
    ASSERT_EQ(sa.size(), sb.size()) << n;
    ASSERT_GE(sa.size(), 2u) << n;
    for (std::size_t i = 0; i < sa.size(); ++i) {
      EXPECT_EQ(sa[i].t, sb[i].t) << n << " " << i;
      EXPECT_EQ(sa[i].outputs, sb[i].outputs) << n << " " << i;
    }
  }
}

// The built-in subsystem without its waveform calls: held and ramped inputs only.
class HeldOnly final : public Participant {
 public:
  HeldOnly(const Scene& scene, const SubsystemConfig& c) : s_(scene, c) {}
  std::string name() const override { return "held-only " + s_.name(); }
  Channels channels() const override { return s_.channels(); }
  CouplingData statics(const CouplingData& in) override { return s_.statics(in); }
  StepResult initialize(const CouplingData& in) override { return s_.initialize(in); }
  void set_inputs(long n, const CouplingData& in) override { s_.set_inputs(n, in); }
  void set_inputs(long n, const CouplingData& a, const CouplingData& b) override {
    s_.set_inputs(n, a, b);
  }
  CouplingData outputs() override { return s_.outputs(); }
  void start_step(long n) override { s_.start_step(n); }
  StepResult finish_step() override { return s_.finish_step(); }
  ParticipantResults results() override { return s_.results(); }
  ParticipantState save() override { return s_.save(); }
  void restore(const ParticipantState& st) override { s_.restore(st); }

 private:
  Subsystem s_;
};

TEST(TcpWaveformRefused, ANodeThatTakesNoWaveformsIsNamed) {
  NodeOptions no;
  no.role = "track";
  no.make_participant = [](const Scene& scene, const SubsystemConfig& c) {
    return std::make_unique<HeldOnly>(scene, c);
  };
  NodeServer server(no, Address{"127.0.0.1", 0}, ServerLimits{});
  std::thread serving([&] { server.run(false); });
  const std::string address = server.local_address().str();
  const Scene scene = short_paper();
  NodePool pool;
  const SceneTransport tcp = tcp_transport(scene, {{"track", server.local_address()}}, pool);
  const run::RunOptions o =
      waveform_run(scene, InputMode::kWaveform1, CouplingMethod::kExplicit, Feedthrough::kLagged);
  std::string what;
  try {
    run::run_cosim(scene, parse_case("rs-xx-gauss-seidel"), o, tcp.factory, tcp.name);
  } catch (const std::exception& e) {
    what = e.what();
  }
  server.stop();
  serving.join();
  EXPECT_EQ(
      what,
      "track node at " + address +
          ": record_samples failed: BAD_REQUEST: participant track takes no substep "
          "waveforms (held-only track (rs-xx lower): record_samples() rejected: this participant "
          "records no samples): run it with --inputs hold or linear, not waveform0 "
          "to waveform3 before the run");
}

}  // namespace
}  // namespace railcosim
