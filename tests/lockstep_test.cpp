// The direct data plane's lock step: the couplings the master decides step
// by step (implicit iterations, inputs that ramp) run with the node serving
// its step requests on its worker thread and keeping its own checkpoints.
// Every such case is bitwise the same on the three planes (in process,
// relayed, direct); the session's side is checked message by message. A
// node killed in the middle of an iteration: direct_plane_test.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "connection.hpp"
#include "cosim_support.hpp"
#include "engine/coupled_statics.hpp"
#include "remote/node_launcher.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene_text.hpp"
#include "server.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

using engine::AcceleratorKind;
using engine::CouplingMethod;
using engine::InputMode;
using engine::zero_inputs;

using std::chrono::milliseconds;

// (Resolved feedthrough exists for explicit coupling with held inputs only.)
// 100 macro steps of 1e-4 s: every kind of message many times over.
Scene short_scene(const char* file) {
  return with_keys(load_scene(test::source_path(file)), {{"simulation.end_time", 0.01}});
}

struct Coupling {
  const char* name;
  CouplingMethod method;
  InputMode inputs;
};

constexpr Coupling kCouplings[] = {
    {"implicit IQN-ILS, linear inputs", CouplingMethod::kImplicit, InputMode::kLinear},
    {"implicit IQN-ILS, held inputs", CouplingMethod::kImplicit, InputMode::kHold},
    {"explicit, linear inputs", CouplingMethod::kExplicit, InputMode::kLinear},
    {"explicit, extrapolated inputs (2nd order)", CouplingMethod::kExplicit,
     InputMode::kExtrapolate2},
};

struct LockStepCase {
  const char* scene;
  const char* name;
  Feedthrough feedthrough;
};

class LockStepPlanes : public ::testing::TestWithParam<LockStepCase> {
 protected:
  static void SetUpTestSuite() { pool_ = std::make_unique<remote::NodePool>(); }
  static void TearDownTestSuite() { pool_.reset(); }
  static inline std::unique_ptr<remote::NodePool> pool_;
};

TEST_P(LockStepPlanes, EveryCouplingIsBitwiseTheSameInProcessRelayedAndDirect) {
  const Scene scene = short_scene(GetParam().scene);
  const CaseSpec spec = parse_case(GetParam().name);
  const remote::SceneTransport tcp = remote::tcp_transport(scene, {}, *pool_);
  for (const Coupling& c : kCouplings) {
    run::RunOptions o;
    o.macro_step = scene.macro_step;
    o.tolerance = scene.tolerance;
    o.feedthrough = GetParam().feedthrough;
    o.coupling.method = c.method;
    o.coupling.inputs = c.inputs;
    o.coupling.accelerator.kind = AcceleratorKind::kIqnIls;
    const run::RunRecord local =
        run::run_cosim(scene, spec, o, remote::inproc_factory(scene), "inproc");
    o.data_plane = remote::DataPlane::kRelay;
    const run::RunRecord relayed = run::run_cosim(scene, spec, o, tcp.factory, "tcp");
    o.data_plane = remote::DataPlane::kDirect;
    const run::RunRecord direct = run::run_cosim(scene, spec, o, tcp.factory, "tcp");
    SCOPED_TRACE(c.name);
    EXPECT_EQ(relayed.data_plane, "relay");
    EXPECT_EQ(relayed.data_plane_mode, "");
    EXPECT_EQ(direct.data_plane, "direct");
    EXPECT_EQ(direct.data_plane_mode, "lock step");
    for (const run::RunRecord* r : {&relayed, &direct}) {
      ASSERT_EQ(r->status, local.status) << r->message;
      EXPECT_EQ(r->macro_steps, local.macro_steps);
      EXPECT_EQ(r->micro_steps, local.micro_steps);
      EXPECT_EQ(r->deflection, local.deflection);  // exact double equality
      EXPECT_EQ(r->soil, local.soil);
      ASSERT_EQ(r->history.size(), local.history.size());
      for (std::size_t i = 0; i < local.history.size(); ++i) {
        ASSERT_EQ(r->history[i].wheel, local.history[i].wheel) << "row " << i;
        ASSERT_EQ(r->history[i].contact_force, local.history[i].contact_force) << "row " << i;
        ASSERT_EQ(r->history[i].extra, local.history[i].extra) << "row " << i;
      }
      ASSERT_EQ(r->convergence.size(), local.convergence.size());
      for (std::size_t i = 0; i < local.convergence.size(); ++i)
        ASSERT_EQ(r->convergence[i].residual, local.convergence[i].residual) << "row " << i;
    }
    if (c.method == CouplingMethod::kImplicit) {
      EXPECT_GT(local.convergence.size(), 100u);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    PaperAndSoilCases, LockStepPlanes,
    ::testing::Values(LockStepCase{"scenes/paper.toml", "wr-xx-jacobi", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "wr-xx-gauss-seidel", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "wr-xt-jacobi", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "wr-xt-gauss-seidel", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "rs-xx-jacobi", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "rs-xx-gauss-seidel", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "rs-xt-jacobi", Feedthrough::kLagged},
                      LockStepCase{"scenes/paper.toml", "rs-xt-gauss-seidel", Feedthrough::kLagged},
                      LockStepCase{"scenes/soil.toml", "wr-xx+ss-xt-jacobi", Feedthrough::kLagged},
                      LockStepCase{"scenes/soil.toml", "wr-xt+ss-xx-gauss-seidel",
                                   Feedthrough::kLagged}),
    [](const auto& param_info) {
      std::string n =
          std::string(param_info.param.name) + "_" + to_string(param_info.param.feedthrough);
      for (char& ch : n)
        if (ch == '-' || ch == '+') ch = '_';
      return n;
    });

// One session with a track node in this process, opened up to initialize.
class LockStepSession : public ::testing::Test {
 protected:
  void SetUp() override {
    NodeOptions o;
    o.role = "track";
    server_ = std::make_unique<NodeServer>(o, Address{"127.0.0.1", 0});
    thread_ = std::thread([this] { server_->run(false); });
    scene_ = test::paper_scene();
    master_ = Connection::connect(server_->local_address(), milliseconds(5000));
    const wire::Envelope hello = ask(hello_envelope("track", scene_fingerprint(scene_)));
    ASSERT_TRUE(hello.has_hello_reply());
    const auto& caps = hello.hello_reply().capabilities();
    EXPECT_NE(std::find(caps.begin(), caps.end(), "lockstep"), caps.end());
    cfg_ = test::config_of(scene_, "rs-xx-jacobi", "track");
    ASSERT_TRUE(ask(configure_envelope(scene_, cfg_)).has_configured());
    inputs_ = zero_inputs(scene_, cfg_.participant);
    inputs_[0].force.assign(inputs_[0].force.size(), 1e3);  // the sleepers pushed down
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }
  wire::Envelope ask(wire::Envelope e) {
    e.set_id(++id_);
    master_->send(e);
    return master_->receive(milliseconds(5000));
  }
  wire::Envelope initialize() {
    wire::Envelope e;
    *e.mutable_initialize()->mutable_inputs() = to_wire(zero_inputs(scene_, cfg_.participant));
    return ask(e);
  }
  wire::Envelope lockstep() {
    wire::Envelope e;
    e.mutable_window()->set_lockstep(true);
    return ask(e);
  }
  wire::Envelope step(long n, bool keep, bool restore) {
    wire::Envelope e;
    auto* s = e.mutable_step();
    s->set_step(n);
    s->set_t(static_cast<double>(n) * cfg_.macro_step);
    s->set_h(cfg_.macro_step);
    *s->mutable_inputs() = to_wire(inputs_);
    s->set_keep_checkpoint(keep);
    s->set_restore_checkpoint(restore);
    return ask(e);
  }

  std::unique_ptr<NodeServer> server_;
  std::thread thread_;
  Scene scene_;
  SubsystemConfig cfg_;
  CouplingData inputs_;
  std::unique_ptr<Connection> master_;
  std::uint64_t id_ = 0;
};

TEST_F(LockStepSession, AKeptCheckpointTakesTheStepBackBitForBit) {
  ASSERT_TRUE(initialize().has_step_report());
  const wire::Envelope ack = lockstep();
  ASSERT_TRUE(ack.has_ack()) << ack.DebugString();
  EXPECT_EQ(ack.id(), id_);
  const wire::Envelope first = step(0, true, false);
  ASSERT_TRUE(first.has_step_report()) << first.DebugString();
  EXPECT_EQ(first.id(), id_);
  // Again from the kept checkpoint, in one message, and as Restore + Step.
  const wire::Envelope again = step(0, false, true);
  ASSERT_TRUE(again.has_step_report()) << again.DebugString();
  EXPECT_EQ(again.step_report().SerializeAsString(), first.step_report().SerializeAsString());
  wire::Envelope restore;
  restore.mutable_restore()->set_kept(true);
  ASSERT_TRUE(ask(restore).has_ack());
  EXPECT_EQ(step(0, false, false).step_report().SerializeAsString(),
            first.step_report().SerializeAsString());
  // A request of another kind ends the lock step and is answered as usual;
  // the relayed requests go on.
  wire::Envelope results;
  results.mutable_get_results();
  ASSERT_TRUE(ask(results).has_results());
  EXPECT_EQ(step(1, false, false).step_report().step(), 2);
}

TEST_F(LockStepSession, RestoringWithNothingKeptIsRefused) {
  ASSERT_TRUE(initialize().has_step_report());
  ASSERT_TRUE(lockstep().has_ack());
  const wire::Envelope e = step(0, false, true);
  ASSERT_TRUE(e.has_error());
  EXPECT_EQ(e.error().code(), wire::Error::OUT_OF_ORDER);
  EXPECT_NE(e.error().message().find("none was kept"), std::string::npos) << e.error().message();
}

TEST_F(LockStepSession, ALockStepBeforeInitializeIsRefused) {
  const wire::Envelope e = lockstep();
  ASSERT_TRUE(e.has_error());
  EXPECT_EQ(e.error().code(), wire::Error::OUT_OF_ORDER);
  EXPECT_NE(e.error().message().find("needs initialize first"), std::string::npos)
      << e.error().message();
}

}  // namespace
}  // namespace railcosim
