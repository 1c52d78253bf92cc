// What an implicit coupling iteration costs over the network, in units of a
// raw socket round trip measured in the same run with the same frame sizes.
//
//   implicit_bench [REPEATS] [END_TIME]   (default: 3, 0.05 s of the paper scene)
//
// For every single-cut case of the paper scene at H = 1e-4 s, implicit
// coupling with IQN-ILS and linear inputs (convergence 1e-8): the iterations
// per macro step (the same on every plane, bit for bit), the in-process wall
// time per step (the physics and the accelerator: no network at all), the
// TCP wall time per step on each data plane (relayed; direct, which runs
// these couplings in lock step), and the overhead per iteration,
// (TCP - in-process) / iterations / raw round trip. The floor of the lock
// step is one round trip per iteration for Jacobi (both nodes step at once)
// and one per participant for Gauss-Seidel (each steps after the other's
// report reaches the master); the target is 1.2. Every number is the best
// of REPEATS. Prints a Markdown table; progress goes to stderr.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "raw_pingpong.hpp"
#include "scene_text.hpp"

namespace railcosim {
namespace {

using remote::DataPlane;
using remote::inproc_factory;
using remote::NodePool;
using remote::ParticipantFactory;
using remote::tcp_transport;

constexpr double kTarget = 1.2;  // overhead per iteration, raw round trips

struct Timed {
  double per_step = 0;    // wall time per macro step, s
  double iterations = 0;  // per macro step
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
  require_ran("implicit_bench", r, spec, transport, plane);
  const double steps = static_cast<double>(r.macro_steps);
  return {r.wall_s / steps, static_cast<double>(r.convergence.size()) / steps};
}

struct Row {
  std::string name;
  Scheme scheme = Scheme::kJacobi;
  std::size_t request = 0, reply = 0;
  double iterations = 0;
  double inproc = 1e30;
  std::vector<RawRoundTrip> raw;                 // per repeat
  std::map<DataPlane, std::vector<double>> tcp;  // per plane, per repeat
  // The fastest TCP run of a plane and the raw round trip of its repeat.
  std::pair<double, RawRoundTrip> best(DataPlane d) const {
    const std::vector<double>& t = tcp.at(d);
    const auto k = static_cast<std::size_t>(std::min_element(t.begin(), t.end()) - t.begin());
    return {t[k], raw[k]};
  }
  double overhead(DataPlane d) const {
    const auto [t, rtt] = best(d);
    return (t - inproc) / iterations / (rtt.median_us * 1e-6);
  }
};

void print_table(const std::vector<Row>& rows, int repeats, double end_time) {
  std::printf(
      "| case | iterations per step | frame bytes (step / report) | raw RTT µs (p10–p90) | "
      "in-process µs/step | relay µs/step | relay overhead per iteration (RTT) | direct "
      "(lock step) µs/step | direct overhead per iteration (RTT) | direct floor (RTT) | "
      "direct vs target (%.1f) |\n",
      kTarget);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const RawRoundTrip raw = r.best(DataPlane::kDirect).second;
    const double direct = r.overhead(DataPlane::kDirect);
    char verdict[64];
    if (direct <= kTarget)
      std::snprintf(verdict, sizeof verdict, "met");
    else
      std::snprintf(verdict, sizeof verdict, "not met: +%.2f", direct - kTarget);
    std::printf(
        "| %s | %.2f | %zu / %zu | %.1f (%.1f–%.1f) | %.1f | %.1f | %.2f | %.1f | %.2f | "
        "%d | %s |\n",
        r.name.c_str(), r.iterations, r.request, r.reply, raw.median_us, raw.p10_us, raw.p90_us,
        r.inproc * 1e6, r.best(DataPlane::kRelay).first * 1e6, r.overhead(DataPlane::kRelay),
        r.best(DataPlane::kDirect).first * 1e6, direct, r.scheme == Scheme::kJacobi ? 1 : 2,
        verdict);
  }
  std::printf(
      "\nPaper scene, %g s, H = %g s, IQN-ILS, linear inputs; best of %d; raw RTT: the lowest of "
      "%d medians of %d round trips of plain loopback TCP sockets (TCP_NODELAY) with the case's "
      "largest step frame out and step report back, in the repeat of the fastest direct run; "
      "overhead per iteration = (TCP − in-process) / iterations / raw RTT.\n",
      end_time, kMacroStep, repeats, kRawForks, kRawSamples);
}

}  // namespace
}  // namespace railcosim

int main(int argc, char** argv) {
  using namespace railcosim;
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const double end_time = argc > 2 ? std::atof(argv[2]) : 0.05;
  const Scene scene =
      with_keys(load_scene(std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/paper.toml"),
                {{"simulation.end_time", end_time}});
  NodePool pool;  // one node process per participant role, kept for every run
  const ParticipantFactory tcp = tcp_transport(scene, {}, pool).factory;
  const ParticipantFactory inproc = inproc_factory(scene);
  std::vector<Row> rows;
  for (const char* cut : {"wr", "rs"})
    for (const char* type : {"xx", "xt"})
      for (const char* scheme : {"jacobi", "gauss-seidel"}) {
        const CaseSpec spec = parse_case(std::string(cut) + "-" + type + "-" + scheme);
        Row row;
        row.name = spec.name();
        row.scheme = spec.scheme;
        std::tie(row.request, row.reply) = step_frame_bytes(scene, spec, kMacroStep, true);
        for (int k = 0; k < repeats; ++k) {
          std::fprintf(stderr, "%s: repeat %d of %d\n", row.name.c_str(), k + 1, repeats);
          row.raw.push_back(raw_baseline(row.request, row.reply));
          const Timed local = timed_run(scene, spec, inproc, "inproc", DataPlane::kRelay);
          row.inproc = std::min(row.inproc, local.per_step);
          row.iterations = local.iterations;
          for (DataPlane d : {DataPlane::kRelay, DataPlane::kDirect})
            row.tcp[d].push_back(timed_run(scene, spec, tcp, "tcp", d).per_step);
        }
        rows.push_back(row);
      }
  print_table(rows, repeats, end_time);
  return 0;
}
