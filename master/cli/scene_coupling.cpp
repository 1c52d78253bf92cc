#include "cli/scene_coupling.hpp"

#include <CLI/CLI.hpp>
#include <optional>
#include <sstream>
#include <vector>

namespace railcosim::cli {
namespace {

bool flag_given(const RunArgs& a, const char* flag) {
  return a.command != nullptr && a.command->count(flag) > 0;
}

// One key of [coupling]: its flag, and what taking it does to the arguments.
struct Taken {
  const char* key;
  const char* flag;
  bool set;          // the scene sets the key
  std::string text;  // its value as the scene wrote it
};

template <class T>
std::string shown(const std::optional<T>& v) {
  std::ostringstream s;
  if constexpr (std::is_same_v<T, std::string>)
    s << '"' << *v << '"';
  else if constexpr (std::is_same_v<T, bool>)
    s << (*v ? "true" : "false");
  else
    s << *v;
  return s.str();
}

template <class T>
Taken taken(const char* key, const char* flag, const std::optional<T>& v) {
  return {key, flag, v.has_value(), v ? shown(v) : ""};
}

std::vector<Taken> keys_of(const SceneCoupling& c) {
  return {taken("implicit", "--coupling", c.implicit),
          taken("inputs", "--inputs", c.inputs),
          taken("accelerator", "--accelerator", c.accelerator),
          taken("relaxation", "--relaxation", c.relaxation),
          taken("max_iterations", "--max-iterations", c.max_iterations),
          taken("iteration_budget", "--iteration-budget", c.iteration_budget),
          taken("convergence", "--convergence", c.convergence),
          taken("reused_windows", "--reused-windows", c.reused_windows),
          taken("feedthrough", "--feedthrough", c.feedthrough),
          taken("data_plane", "--data-plane", c.data_plane),
          taken("window_steps", "--window-steps", c.window_steps),
          taken("step_budget", "--step-budget", c.step_budget)};
}

}  // namespace

RunArgs with_scene_coupling(const RunArgs& a, const Scene& scene) {
  RunArgs r = a;
  const SceneCoupling& c = scene.coupling;
  auto take = [&](const char* flag, const auto& value, auto& into) {
    if (value && !flag_given(a, flag)) into = *value;
  };
  if (c.implicit && !flag_given(a, "--coupling"))
    r.coupling = *c.implicit ? "implicit" : "explicit";
  take("--inputs", c.inputs, r.inputs);
  take("--accelerator", c.accelerator, r.accelerator);
  take("--relaxation", c.relaxation, r.c.accelerator.relaxation);
  take("--max-iterations", c.max_iterations, r.c.max_iterations);
  take("--iteration-budget", c.iteration_budget, r.c.iteration_budget);
  take("--convergence", c.convergence, r.c.convergence);
  take("--reused-windows", c.reused_windows, r.c.accelerator.windows_reused);
  take("--feedthrough", c.feedthrough, r.feedthrough);
  take("--data-plane", c.data_plane, r.data_plane);
  take("--window-steps", c.window_steps, r.window_steps);
  take("--step-budget", c.step_budget, r.step_budget);
  return r;
}

std::string scene_coupling_note(const RunArgs& a, const Scene& scene) {
  std::string set;
  for (const Taken& t : keys_of(scene.coupling)) {
    if (!t.set || flag_given(a, t.flag)) continue;
    set += set.empty() ? "" : ", ";
    set += t.key;
    set += " = ";
    set += t.text;
  }
  if (set.empty()) return "";
  return "; the scene's [coupling] (" + scene.source + ") set: " + set;
}

}  // namespace railcosim::cli
