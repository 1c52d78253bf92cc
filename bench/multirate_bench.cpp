// What a multirate window costs on the direct data plane over the same
// span of single-rate windows, in raw socket round trips measured in the
// same run.
//
//   multirate_bench [REPEATS] [M] [SCENE]   (default: 3, 10, scenes/soil.toml)
//
// On wr-xx+ss-xt-jacobi (explicit, held inputs) at H = 1e-4 s, over TCP on
// the direct plane: the single-rate run (every cut at H: the nodes exchange
// in windows, data_plane_mode "windows") and the multirate run with the
// soil's cut at M H (lock step: the master steps the fast group M times and
// the soil once per slow window). Each is also run in process, which has no
// network at all; the network's cost of a run is its TCP time less its
// in-process time (the physics, which multirate changes: the soil steps M
// times fewer), counted per slow window (M fine windows) and divided by the
// raw round trip of plain loopback sockets with the case's frame sizes.
// The answer is the difference: what the multirate window costs on the
// wire over M single-rate windows. Every number is the best of REPEATS,
// interleaved. Prints a Markdown table; progress goes to stderr.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "raw_pingpong.hpp"
#include "remote/transport.hpp"
#include "run/runner.hpp"
#include "scene.hpp"

namespace railcosim::multirate_bench {
namespace {

using remote::DataPlane;
using remote::ParticipantFactory;

const char* const kCase = "wr-xx+ss-xt-jacobi";

struct Timed {
  double wall_per_window = 1e30;  // s per slow window (M fine windows), the best
  std::string mode;               // data_plane_mode of the TCP run
};

// One run; its wall time per span of M fine windows.
double run_once(const Scene& scene, const CaseSpec& spec, const ParticipantFactory& f,
                const std::string& transport, long M, bool multirate, std::string* mode) {
  run::RunOptions o;
  o.macro_step = kMacroStep;
  o.tolerance = scene.tolerance;
  o.data_plane = DataPlane::kDirect;
  if (multirate) o.cut_windows["ss"] = M;
  const run::RunRecord r = run::run_cosim(scene, spec, o, f, transport);
  require_ran("multirate_bench", r, spec, transport, DataPlane::kDirect);
  if (mode) *mode = r.data_plane_mode;
  std::fprintf(stderr, "  %s %s: %ld macro steps, %.4f s, %s\n", transport.c_str(),
               multirate ? "multirate" : "single rate", r.macro_steps, r.wall_s,
               r.data_plane_mode.c_str());
  return r.wall_s / static_cast<double>(r.macro_steps) * static_cast<double>(M);
}

struct Measured {
  Timed tcp[2], inproc[2];  // [0]: single rate, [1]: multirate
  std::vector<RawRoundTrip> raw;
  std::vector<double> tcp_runs[2];  // per repeat, for the raw round trip next to the best
};

void print(const Measured& m, long M, int repeats, std::size_t request, std::size_t reply) {
  // The raw round trip of the repeat with the fastest multirate TCP run.
  const std::vector<double>& t = m.tcp_runs[1];
  const auto k = static_cast<std::size_t>(std::min_element(t.begin(), t.end()) - t.begin());
  const RawRoundTrip raw = m.raw[k];
  const double rtt = raw.median_us * 1e-6;
  std::printf(
      "| run | data plane | in-process ms / slow window | TCP ms / slow window | "
      "network (RTT / slow window) |\n|---|---|---|---|---|\n");
  double net[2];
  for (int r = 0; r < 2; ++r) {
    net[r] = (m.tcp[r].wall_per_window - m.inproc[r].wall_per_window) / rtt;
    std::printf("| %s | direct, %s | %.3f | %.3f | %.2f |\n",
                r == 0 ? "single rate (every cut at H), M windows" : "multirate (ss at M H)",
                m.tcp[r].mode.c_str(), m.inproc[r].wall_per_window * 1e3,
                m.tcp[r].wall_per_window * 1e3, net[r]);
  }
  std::printf(
      "\n%s on scenes/soil.toml, H = %g s, M = %ld (a slow window: %g s). Raw RTT %.1f µs "
      "(p10–p90 %.1f–%.1f; frames %zu / %zu bytes; the lowest of %d medians of %d round trips, "
      "in the repeat of the fastest multirate run). The multirate window costs %.2f raw round "
      "trips over %ld single-rate windows (%.2f per fine window). Best of %d.\n",
      kCase, kMacroStep, M, kMacroStep * static_cast<double>(M), raw.median_us, raw.p10_us,
      raw.p90_us, request, reply, kRawForks, kRawSamples, net[1] - net[0], M,
      (net[1] - net[0]) / static_cast<double>(M), repeats);
}

}  // namespace
}  // namespace railcosim::multirate_bench

int main(int argc, char** argv) {
  using namespace railcosim;
  using namespace railcosim::multirate_bench;
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const long M = argc > 2 ? std::max(2L, std::atol(argv[2])) : 10;
  const std::string path =
      argc > 3 ? argv[3] : std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/soil.toml";
  const Scene scene = load_scene(path);
  const CaseSpec spec = parse_case(kCase);
  remote::NodePool pool;  // one node process per participant role, kept for every run
  const ParticipantFactory tcp = remote::tcp_transport(scene, {}, pool).factory;
  const ParticipantFactory inproc = remote::inproc_factory(scene);
  const auto [request, reply] = step_frame_bytes(scene, spec, kMacroStep);
  Measured m;
  for (int k = 0; k < repeats; ++k) {
    std::fprintf(stderr, "multirate_bench: repeat %d of %d\n", k + 1, repeats);
    m.raw.push_back(raw_baseline(request, reply));
    for (int r = 0; r < 2; ++r) {
      const bool multi = r == 1;
      m.inproc[r].wall_per_window = std::min(
          m.inproc[r].wall_per_window, run_once(scene, spec, inproc, "inproc", M, multi, nullptr));
      std::string mode;
      const double t = run_once(scene, spec, tcp, "tcp", M, multi, &mode);
      m.tcp_runs[r].push_back(t);
      if (t < m.tcp[r].wall_per_window) m.tcp[r] = {.wall_per_window = t, .mode = mode};
    }
  }
  print(m, M, repeats, request, reply);
  return 0;
}
