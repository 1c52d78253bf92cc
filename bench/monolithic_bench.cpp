// Wall time and step count of the monolithic run of the paper scene, and of
// the same run on a track ten times longer (500 sleepers), to show how the
// cost grows with the track length.
#include <benchmark/benchmark.h>

#include <cmath>

#include "run/runner.hpp"
#include "scene.hpp"

namespace railcosim {
namespace {

Scene scene_with(int sleepers, double tolerance) {
  Scene s = load_scene(std::string(RAILCOSIM_SOURCE_DIR) + "/scenes/paper.toml");
  s.sleeper_count = sleepers;
  if (tolerance > 0) s.tolerance = tolerance;
  s.validate();
  return s;
}

// Arguments: sleepers, tolerance exponent (0: the scene's own tolerance).
void BM_Monolithic(benchmark::State& state) {
  const int sleepers = static_cast<int>(state.range(0));
  const double tol =
      state.range(1) == 0 ? 0.0 : std::pow(10.0, -static_cast<double>(state.range(1)));
  const Scene scene = scene_with(sleepers, tol);
  run::RunOptions o;
  o.macro_step = scene.macro_step;
  o.tolerance = scene.tolerance;
  long micro = 0;
  double wall = 0;
  for (auto _ : state) {
    const run::RunRecord r = run::run_monolithic(scene, o);
    micro = r.micro_steps.at("monolithic");
    wall += r.wall_s;
    benchmark::DoNotOptimize(r.deflection.data());
  }
  state.counters["dofs"] = 1 + 2 * scene.rail_nodes() + sleepers;
  state.counters["micro_steps"] = static_cast<double>(micro);
  // Microseconds per accepted micro step (a plain number, not a rate).
  state.counters["us_per_step"] =
      1e6 * wall / (static_cast<double>(state.iterations()) * static_cast<double>(micro));
}

BENCHMARK(BM_Monolithic)
    ->ArgNames({"sleepers", "tol_exp"})
    ->Args({50, 0})
    ->Args({500, 0})
    ->Args({50, 6})
    ->Args({500, 6})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace railcosim

BENCHMARK_MAIN();
