// What the C++ participant package costs per macro step for a participant
// that computes nothing: the counterpart of bench/python_sdk_overhead.py's
// "physics that computes nothing, relayed" line, measured the same way.
//
//   cpp_sdk_overhead [STEPS]   (default 3000; the best of 3)
//   cpp_sdk_overhead --serve [NODE OPTIONS]   (serves that participant over
//       TCP as node_main does, for a master run to time it end to end)
//
// A NodeSession (node/session.hpp, what node_main serves) with a
// participant built from its ParticipantSetup, as an outside C++
// participant is (docs/participant-guide-cpp.md): one ss interface of 50
// points receiving and sending displacement and velocity, 10 fixed micro
// steps, Configure.progress_ms = 100 as the master sends it. Its
// advance computes nothing: the outputs are the held inputs, their peak the
// largest magnitude, as the Python bench's soil reports. Per macro step, in
// CPU time of the process: a Step frame's bytes -> Envelope -> handle() ->
// the StepReport's bytes; and the baseline, the frame's bytes -> Envelope
// and a StepReport of the same shape -> bytes with nothing in between.
// The socket calls are in neither, as in the Python bench.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "participant.hpp"
#include "participant_setup.hpp"
#include "server.hpp"
#include "session.hpp"
#include "wire.hpp"

namespace railcosim {
namespace {

constexpr int kPoints = 50;
constexpr double kH = 1e-4;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The participant that computes nothing: it keeps its inputs and reports
// the same outputs at every step (a soil that stays where it is, as the
// Python bench's soil does once its advance() computes nothing).
class Empty final : public Participant {
 public:
  explicit Empty(const ParticipantSetup& setup) : n_(setup.interfaces.at(0).n()) {
    out_.assign(1, InterfaceData{std::vector<double>(n_), std::vector<double>(n_), {}});
  }
  std::string name() const override { return "empty"; }
  Channels channels() const override { return {{"soil_peak_m"}, {}}; }
  CouplingData statics(const CouplingData& in) override {
    held_ = in;
    return out_;
  }
  StepResult initialize(const CouplingData& in) override {
    held_ = in;
    return report();
  }
  void set_inputs(long, const CouplingData& in) override { held_ = in; }
  CouplingData outputs() override { return out_; }
  void start_step(long) override {}
  StepResult finish_step() override { return report(); }
  ParticipantResults results() override { return {}; }
  ParticipantState save() override { return {}; }
  void restore(const ParticipantState&) override {}

 private:
  StepResult report() const {
    double peak = 0;
    for (double u : out_.at(0).displacement) peak = std::max(peak, std::abs(u));
    return {out_, peak, std::isfinite(peak), {peak}};
  }
  std::size_t n_;
  CouplingData held_, out_;
};

wire::CouplingData inputs(long n) {
  wire::CouplingData d;
  wire::InterfaceData* i = d.add_interfaces();
  for (int k = 0; k < kPoints; ++k) {
    const double v = 1e-3 * std::fmod(0.618 * static_cast<double>(n * kPoints + k), 1.0);
    i->add_displacement(v);
    i->add_velocity(v);
  }
  return d;
}

std::string frame(const wire::Envelope& e) {
  std::string body = e.SerializeAsString();
  const auto n = static_cast<std::uint32_t>(body.size());
  std::string out{static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8),
                  static_cast<char>(n)};
  return out + body;
}

wire::Envelope parsed(const std::string& f) {
  wire::Envelope e;
  if (!e.ParseFromArray(f.data() + 4, static_cast<int>(f.size() - 4))) std::abort();
  return e;
}

std::unique_ptr<NodeSession> session(const NodeOptions& options) {
  auto s = std::make_unique<NodeSession>(options);
  bool close = false;
  wire::Envelope e;
  e.set_id(1);
  e.mutable_hello()->set_protocol_version(kProtocolVersion);
  e.mutable_hello()->set_role("master");
  e.mutable_hello()->set_participant("soil");
  s->handle(e, close);
  e.Clear();
  e.set_id(2);
  wire::Configure* c = e.mutable_configure();
  c->set_participant("soil");
  c->set_macro_step(kH);
  c->set_end_time(1.0);
  c->set_micro_steps(10);
  c->set_progress_ms(100);
  wire::Interface* i = c->add_interfaces();
  i->set_cut("ss");
  i->set_peer("track");
  i->set_stiffness(25.5e6);
  i->set_damping(4e4);
  for (int k = 0; k < kPoints; ++k) {
    i->add_x((k + 0.5) * 0.6);
    wire::Footprint* f = i->add_footprints();
    f->set_x((k + 0.5) * 0.6);
    f->set_length(0.6);
    f->set_width(2.6);
  }
  for (auto q : {wire::DISPLACEMENT, wire::VELOCITY}) {
    i->add_receives(q);
    i->add_sends(q);
  }
  const wire::Envelope configured = s->handle(e, close);
  if (configured.has_error()) {
    std::fprintf(stderr, "configure refused: %s\n", configured.error().message().c_str());
    std::exit(1);
  }
  e.Clear();
  e.set_id(3);
  *e.mutable_initialize()->mutable_inputs() = inputs(0);
  s->handle(e, close);
  return s;
}

std::vector<std::string> step_frames(long steps) {
  std::vector<std::string> frames;
  for (long n = 0; n < steps; ++n) {
    wire::Envelope e;
    e.set_id(static_cast<std::uint64_t>(10 + n));
    wire::Step* st = e.mutable_step();
    st->set_step(n);
    st->set_t(static_cast<double>(n) * kH);
    st->set_h(kH);
    *st->mutable_inputs() = inputs(n);
    frames.push_back(frame(e));
  }
  return frames;
}

// Per macro step: frame -> Envelope -> handle() -> the reply's bytes.
double relayed(const NodeOptions& options, long steps) {
  auto s = session(options);
  const std::vector<std::string> frames = step_frames(steps);
  std::size_t bytes = 0;
  bool close = false;
  const double t0 = cpu_seconds();
  for (const std::string& f : frames) {
    const wire::Envelope reply = s->handle(parsed(f), close);
    if (!reply.has_step_report() || reply.step_report().outputs().interfaces_size() != 1) {
      std::fprintf(stderr, "not a step report: %s\n", reply.ShortDebugString().c_str());
      std::exit(1);
    }
    bytes += frame(reply).size();
  }
  const double t = (cpu_seconds() - t0) / static_cast<double>(steps);
  if (bytes == 0 || close) std::abort();
  return t;
}

// The protobuf work any participant does: frame -> Envelope, and a
// StepReport of the same shape -> bytes.
double baseline(const NodeOptions& options, long steps) {
  auto s = session(options);
  bool close = false;
  wire::Envelope report = s->handle(parsed(step_frames(1)[0]), close);
  const std::vector<std::string> frames = step_frames(steps);
  std::size_t bytes = 0;
  const double t0 = cpu_seconds();
  for (const std::string& f : frames) {
    report.set_id(parsed(f).id());
    bytes += frame(report).size();
  }
  const double t = (cpu_seconds() - t0) / static_cast<double>(steps);
  if (bytes == 0) std::abort();
  return t;
}

}  // namespace
}  // namespace railcosim

int main(int argc, char** argv) {
  using namespace railcosim;
  if (argc > 1 && std::string(argv[1]) == "--serve") {
    NodeProgram program;
    program.name = "cpp_sdk_overhead";
    program.default_role = "soil";
    program.configure = [](const ParticipantSetup& setup) {
      return std::make_unique<Empty>(setup);
    };
    argv[1] = argv[0];
    return node_main(program, argc - 1, argv + 1);
  }
  const long steps = argc > 1 ? std::max(1L, std::atol(argv[1])) : 3000;
  NodeOptions options;
  options.role = "soil";
  options.name = "cpp_sdk_overhead";
  options.configure = [](const ParticipantSetup& setup) { return std::make_unique<Empty>(setup); };
  double best = 1e9, floor = 1e9;
  for (int k = 0; k < 3; ++k) {
    best = std::min(best, relayed(options, steps));
    floor = std::min(floor, baseline(options, steps));
  }
  std::printf(
      "C++ package, a physics that computes nothing, relayed: %.2f us per macro step (best of 3 x "
      "%ld); baseline (frame -> Envelope, StepReport -> bytes): %.2f us; %.2f baselines\n",
      best * 1e6, steps, floor * 1e6, best / floor);
  return 0;
}
