// What an implicit coupling iteration costs a participant on the Python SDK
// over the network, beside the built-in node serving the same soil, in
// units of a raw socket round trip measured in the same run.
//
//   sdk_lockstep_bench [REPEATS] [END_TIME]   (default: 3, 0.05 s of scenes/soil.toml)
//
// The soil of scenes/soil.toml with 10 fixed micro steps per macro step,
// served by the built-in soil node and by the soil of examples/python_soil
// on the Python SDK (bench/python_soil_timed.py: the example with its
// physics timed), which matches the built-in one to rounding, so that the
// iterations are the same. Cases ss-xx-jacobi and ss-xx-gauss-seidel,
// implicit IQN-ILS with linear inputs, H = 1e-4 s. Per macro step: the
// iterations, the in-process time (all C++) and, per data plane (relayed;
// direct, in lock step), the time over TCP. The overhead per iteration is
// (TCP - baseline) / iterations / raw round trip, where the baseline is the
// in-process time with the soil's physics swapped for the serving one's:
// for the built-in node the in-process time itself (as implicit_bench
// counts it); for the SDK soil the in-process time - the C++ soil's physics
// (timed in process around its steps) + the Python soil's (timed by the
// Python process around its advance() calls, in that very run). Every
// number is the best of REPEATS. Prints a Markdown table; progress on stderr.
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "raw_pingpong.hpp"
#include "remote/node_launcher.hpp"
#include "scene_text.hpp"

namespace railcosim {
namespace {

using remote::DataPlane;
using remote::ParticipantFactory;

// A participant whose steps are timed (the in-process soil's physics).
class TimedSteps final : public Participant {
 public:
  TimedSteps(std::unique_ptr<Participant> p, double* seconds) : p_(std::move(p)), s_(seconds) {}
  std::string name() const override { return p_->name(); }
  Channels channels() const override { return p_->channels(); }
  CouplingData statics(const CouplingData& in) override { return p_->statics(in); }
  StepResult initialize(const CouplingData& in) override { return p_->initialize(in); }
  void set_inputs(long n, const CouplingData& in) override { p_->set_inputs(n, in); }
  void set_inputs(long n, const CouplingData& a, const CouplingData& b) override {
    p_->set_inputs(n, a, b);
  }
  CouplingData outputs() override { return p_->outputs(); }
  void start_step(long n) override {
    timed([&] { p_->start_step(n); });
  }
  StepResult finish_step() override {
    StepResult r;
    timed([&] { r = p_->finish_step(); });
    return r;
  }
  ParticipantResults results() override { return p_->results(); }
  ParticipantState save() override { return p_->save(); }
  void restore(const ParticipantState& s) override { p_->restore(s); }

 private:
  template <class F>
  void timed(F f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    *s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::unique_ptr<Participant> p_;
  double* s_;
};

struct Timed {
  double per_step = 0;    // wall time per macro step, s
  double iterations = 0;  // per macro step
  long steps = 0;
};

Timed timed_run(const Scene& scene, const CaseSpec& spec, const ParticipantFactory& f,
                const std::string& transport, DataPlane plane) {
  run::RunOptions o;
  o.macro_step = kMacroStep;
  o.tolerance = scene.tolerance;
  o.data_plane = plane;
  o.coupling.method = engine::CouplingMethod::kImplicit;
  o.coupling.inputs = engine::InputMode::kLinear;
  o.coupling.accelerator.kind = engine::AcceleratorKind::kIqnIls;
  const run::RunRecord r = run::run_cosim(scene, spec, o, f, transport);
  require_ran("sdk_lockstep_bench", r, spec, transport, plane);
  const double steps = static_cast<double>(r.macro_steps);
  return {r.wall_s / steps, static_cast<double>(r.convergence.size()) / steps, r.macro_steps};
}

// The Python soil's physics in its last run, s per macro step.
double python_physics(const std::string& file, long steps) {
  std::ifstream in(file);
  double seconds = -1;
  long calls = 0;
  if (!(in >> seconds >> calls) || calls <= 0) {
    std::fprintf(stderr, "sdk_lockstep_bench: %s holds no physics time\n", file.c_str());
    std::exit(1);
  }
  return seconds / static_cast<double>(steps);
}

struct Row {
  std::string name, soil;
  double iterations = 0, inproc = 1e30;
  RawRoundTrip raw;
  // Per plane (relay, direct): the fastest run, its baseline, iterations and
  // the soil's physics (s per macro step).
  double tcp[2] = {1e30, 1e30}, baseline[2] = {0, 0}, iters[2] = {1, 1}, physics[2] = {0, 0};
  double overhead(int k) const {
    return (tcp[k] - baseline[k]) / iters[k] / (raw.median_us * 1e-6);
  }
};

// Keeps the run of plane p with the lowest time beyond its baseline.
void keep_fastest(Row& row, int p, const Timed& t, double baseline, double physics) {
  if (t.per_step - baseline >= row.tcp[p] - row.baseline[p]) return;
  row.tcp[p] = t.per_step;
  row.baseline[p] = baseline;
  row.iters[p] = t.iterations;
  row.physics[p] = physics;
}

// The SDK soil's time per iteration beyond the built-in node's on plane p,
// its physics' difference taken out, in raw round trips: both runs have the
// same processes, so a loaded machine's share of the cores cancels.
double beyond_node(const Row& sdk, const Row& node, int p) {
  const double extra = (sdk.tcp[p] - node.tcp[p]) - (sdk.physics[p] - node.physics[p]);
  return extra / sdk.iters[p] / (sdk.raw.median_us * 1e-6);
}

void print_table(const std::vector<Row>& rows, int repeats, double end_time) {
  std::printf(
      "| case | soil | iterations per step | raw RTT µs (p10–p90) | in-process µs/step | relay "
      "µs/step | relay overhead per iteration (RTT) | direct (lock step) µs/step | direct "
      "overhead per iteration (RTT) | soil physics µs/step (direct) | SDK beyond the node per "
      "iteration, relay / direct (RTT) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& r = rows[k];
    char beyond[64] = "—";
    if (k % 2 == 1)
      std::snprintf(beyond, sizeof beyond, "%.2f / %.2f", beyond_node(r, rows[k - 1], 0),
                    beyond_node(r, rows[k - 1], 1));
    std::printf(
        "| %s | %s | %.2f | %.1f (%.1f–%.1f) | %.1f | %.1f | %.2f | %.1f | %.2f | %.1f | %s |\n",
        r.name.c_str(), r.soil.c_str(), r.iterations, r.raw.median_us, r.raw.p10_us, r.raw.p90_us,
        r.inproc * 1e6, r.tcp[0] * 1e6, r.overhead(0), r.tcp[1] * 1e6, r.overhead(1),
        r.physics[1] * 1e6, beyond);
  }
  std::printf(
      "\nscenes/soil.toml, %g s, H = %g s, 10 micro steps, IQN-ILS, linear inputs; best of %d; "
      "raw RTT: the lowest of %d medians of %d round trips of plain loopback TCP sockets with "
      "the case's largest step frame out and step report back; overhead per iteration = (TCP "
      "− baseline) / iterations / raw RTT, the baseline being the in-process time with the "
      "soil's physics swapped for the serving soil's; SDK beyond the node = (SDK soil's TCP "
      "time − the node's − (Python physics − C++ physics)) / iterations / raw RTT.\n",
      end_time, kMacroStep, repeats, kRawForks, kRawSamples);
}

}  // namespace
}  // namespace railcosim

int main(int argc, char** argv) {
  using namespace railcosim;
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const double end_time = argc > 2 ? std::atof(argv[2]) : 0.05;
  const std::string src = RAILCOSIM_SOURCE_DIR;
  const Scene scene =
      with_keys(load_scene(src + "/scenes/soil.toml"),
                {{"simulation.end_time", end_time}, {"simulation.micro_steps", std::int64_t{10}}});
  const std::string physics_file =
      "/tmp/sdk_lockstep_bench." + std::to_string(::getpid()) + ".physics";
  remote::LaunchedNode python(
      remote::LaunchCommand{
          "the Python SDK soil",
          {"/usr/bin/python3", src + "/bench/python_soil_timed.py", "--physics-file", physics_file,
           "--config", src + "/scenes/soil.toml", "--listen", "127.0.0.1:0"},
          {}},
      std::chrono::milliseconds(30000));
  remote::NodePool pool;  // the built-in nodes, kept for every run
  const ParticipantFactory builtin = remote::tcp_transport(scene, {}, pool).factory;
  const ParticipantFactory sdk =
      remote::tcp_transport(scene, {{"soil", python.address()}}, pool).factory;
  double soil_physics = 0;  // the in-process soil's, s
  const ParticipantFactory inproc = [&, f = remote::inproc_factory(scene)](
                                        const SubsystemConfig& c) -> std::unique_ptr<Participant> {
    if (c.participant.role != "soil") return f(c);
    return std::make_unique<TimedSteps>(f(c), &soil_physics);
  };
  std::vector<Row> rows;
  for (const char* name : {"ss-xx-jacobi", "ss-xx-gauss-seidel"}) {
    const CaseSpec spec = parse_case(name);
    Row cpp, py;
    cpp.name = py.name = name;
    cpp.soil = "built-in node";
    py.soil = "Python SDK";
    const auto [request, reply] = step_frame_bytes(scene, spec, kMacroStep, true);
    for (int k = 0; k < repeats; ++k) {
      std::fprintf(stderr, "%s: repeat %d of %d\n", name, k + 1, repeats);
      const RawRoundTrip raw = raw_baseline(request, reply);
      if (k == 0 || raw.median_us < cpp.raw.median_us) cpp.raw = py.raw = raw;
      // The in-process run is short: the best of three against the load.
      Timed local;
      double cpp_soil = 0;
      for (int j = 0; j < 3; ++j) {
        soil_physics = 0;
        const Timed t = timed_run(scene, spec, inproc, "inproc", DataPlane::kRelay);
        if (j == 0 || t.per_step < local.per_step) {
          local = t;
          cpp_soil = soil_physics / static_cast<double>(t.steps);
        }
      }
      cpp.inproc = py.inproc = std::min(cpp.inproc, local.per_step);
      cpp.iterations = py.iterations = local.iterations;
      for (int p = 0; p < 2; ++p) {
        const DataPlane plane = p == 0 ? DataPlane::kRelay : DataPlane::kDirect;
        const Timed c = timed_run(scene, spec, builtin, "tcp", plane);
        keep_fastest(cpp, p, c, cpp.inproc, cpp_soil);
        const Timed t = timed_run(scene, spec, sdk, "tcp", plane);
        const double py_soil = python_physics(physics_file, t.steps);
        keep_fastest(py, p, t, local.per_step - cpp_soil + py_soil, py_soil);
      }
    }
    rows.push_back(cpp);
    rows.push_back(py);
  }
  std::remove(physics_file.c_str());
  print_table(rows, repeats, end_time);
  return 0;
}
