// A node whose participant breaks the protocol on purpose, one way per run,
// for the conformance kit's own test: the built-in model wrapped so that it
//   ignores-restore  takes Restore and does nothing
//   late             answers its fifth macro step after 1.5 s
//   wrong-count      reports one coupling value too few
//   accepts-nan      takes non-finite inputs (as zeros) instead of refusing them
//   slow-working     works 4 s on its macro step 300 (from point 300), showing
//                    progress: one more micro step every 20 ms
//   stuck-progress   on its macro step 300 shows "progress" every 20 ms that
//                    never advances, until its budget ends or it is stopped
//   slow-statics     works 4 s on its first Statics, showing progress: one
//                    more unit of work every 20 ms (frames with step -1)
//   slow-silent      works 3 s on its macro step 300 without showing progress
//   fails-step       gives up on its macro step 10 (STEP_FAILED), its state
//                    as calm as before: a failure, not a divergence
// Usage: broken_node MODE [node options]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <thread>

#include "server.hpp"
#include "subsystem.hpp"
#include "work_budget.hpp"

namespace railcosim {
namespace {

class Broken final : public Participant {
 public:
  Broken(std::string mode, const Scene& scene, const SubsystemConfig& config)
      : mode_(std::move(mode)), inner_(scene, config) {}
  std::string name() const override { return inner_.name() + " (broken: " + mode_ + ")"; }
  Channels channels() const override { return inner_.channels(); }
  CouplingData statics(const CouplingData& in) override {
    if (mode_ == "slow-statics" && !statics_done_) work_long();
    statics_done_ = true;
    return inner_.statics(in);
  }
  StepResult initialize(const CouplingData& in) override { return inner_.initialize(in); }
  void set_inputs(long n, const CouplingData& in) override { inner_.set_inputs(n, clean(in)); }
  void set_inputs(long n, const CouplingData& a, const CouplingData& b) override {
    inner_.set_inputs(n, clean(a), clean(b));
  }
  CouplingData outputs() override { return inner_.outputs(); }
  void start_step(long n) override {
    if (mode_ == "late" && n == 4) std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    if (n == 300 && (mode_ == "slow-working" || mode_ == "stuck-progress")) work_long();
    if (n == 300 && mode_ == "slow-silent") std::this_thread::sleep_for(std::chrono::seconds(3));
    if (n == 10 && mode_ == "fails-step")
      throw StepFailure("the integrator gave up on macro step 10 (a test's broken node)");
    inner_.start_step(n);
  }
  StepResult finish_step() override {
    StepResult r = inner_.finish_step();
    if (mode_ == "wrong-count") r.outputs.front().displacement.pop_back();
    return r;
  }
  ParticipantResults results() override { return inner_.results(); }
  ParticipantState save() override { return inner_.save(); }
  void restore(const ParticipantState& s) override {
    if (mode_ != "ignores-restore") inner_.restore(s);
  }

 private:
  // Works on (sleeps) in slices of 20 ms, as an integrator would, within the
  // node's budget of a step.
  void work_long() const {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(4);
    while (mode_ == "stuck-progress" || std::chrono::steady_clock::now() < until) {
      if (const std::string why = work_budget_exceeded(); !why.empty()) throw StepFailure(why);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      work_progress(mode_ == "stuck-progress" ? 0 : 1);
    }
  }
  CouplingData clean(CouplingData in) const {
    if (mode_ == "accepts-nan")
      for (InterfaceData& d : in)
        for (auto* v : {&d.displacement, &d.velocity, &d.force})
          for (double& x : *v)
            if (!std::isfinite(x)) x = 0.0;
    return in;
  }
  std::string mode_;
  Subsystem inner_;
  bool statics_done_ = false;
};

}  // namespace
}  // namespace railcosim

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: broken_node "
                 "ignores-restore|late|wrong-count|accepts-nan|slow-working|stuck-progress|"
                 "slow-statics|slow-silent|fails-step ...\n");
    return 2;
  }
  const std::string mode = argv[1];
  railcosim::NodeProgram program{
      "broken_node",
      "soil",
      [mode](const railcosim::Scene& s, const railcosim::SubsystemConfig& c) {
        return std::make_unique<railcosim::Broken>(mode, s, c);
      },
      {}};
  argv[1] = argv[0];
  return railcosim::node_main(program, argc - 1, argv + 1);
}
