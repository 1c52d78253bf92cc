// What the automatic track length saves: a monolithic run on a 300 m track
// (500 sleepers, the wheel starting 20 m in) against the same run on a track
// sized from the run, for a short and a long run. Wall time (best of 3),
// DOFs, and the change of the deflection under the wheel at t_end.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "monolithic.hpp"
#include "scene.hpp"

namespace {

struct Outcome {
  double wall = 1e30;
  double under_wheel = 0;
  int dofs = 0;
};

Outcome run(const railcosim::Scene& s) {
  Outcome o;
  for (int i = 0; i < 3; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    railcosim::MonolithicModel m(s, s.macro_step, s.tolerance);
    const long N = s.macro_steps();
    for (long n = 0; n < N; ++n) m.advance(n);
    o.under_wheel = m.rail_under_wheel(static_cast<double>(N) * s.macro_step);
    o.wall = std::min(o.wall,
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    o.dofs = m.structure().layout.size;
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  using railcosim::Scene;
  const std::string path =
      argc > 1 ? argv[1] : std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/paper.toml";
  std::printf("%-8s %-22s %7s %10s %16s %14s\n", "t_end", "track", "DOFs", "wall ms",
              "under wheel mm", "rel. change");
  for (double t_end : {0.05, 0.25}) {
    Scene full = railcosim::load_scene(path);
    full.sleeper_count = 500;
    full.initial_position = 20.0;
    full.end_time = t_end;
    full.validate();
    Scene sized = full;
    sized.auto_length = true;
    sized.size_track(20.0);
    sized.validate();
    const Outcome a = run(full), b = run(sized);
    std::printf("%-8g %-22s %7d %10.1f %16.6f %14s\n", t_end, "500 sleepers (300 m)", a.dofs,
                a.wall * 1e3, a.under_wheel * 1e3, "");
    char label[64];
    std::snprintf(label, sizeof label, "auto: %d sleepers", sized.sleeper_count);
    std::printf("%-8g %-22s %7d %10.1f %16.6f %14.2e\n", t_end, label, b.dofs, b.wall * 1e3,
                b.under_wheel * 1e3,
                std::abs(b.under_wheel - a.under_wheel) / std::abs(a.under_wheel));
  }
  return 0;
}
