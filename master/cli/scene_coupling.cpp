#include "cli/scene_coupling.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "model.hpp"

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
          taken("step_budget", "--step-budget", c.step_budget),
          taken("step_deadline_floor", "--step-deadline-floor", c.step_deadline_floor),
          taken("judge", "--judge", c.judge),
          taken("judge_budget", "--judge-budget", c.judge_budget),
          taken("wr_macro_step", "--macro-step", c.wr_macro_step),
          taken("rs_macro_step", "--macro-step", c.rs_macro_step),
          taken("ss_macro_step", "--macro-step", c.ss_macro_step)};
}

std::string cut_name_of(const CutChoice& c) {
  return cut_kinds()[static_cast<std::size_t>(c.cut)].name;
}

// The cut windows of the command line, then the scene's for the other cuts.
std::map<std::string, engine::CutWindow> given_cut_windows(const RunArgs& a, const Scene& scene) {
  std::map<std::string, engine::CutWindow> w = a.cut_windows;
  const SceneCoupling& c = scene.coupling;
  const std::pair<const char*, const std::optional<double>*> keys[] = {
      {"wr", &c.wr_macro_step}, {"rs", &c.rs_macro_step}, {"ss", &c.ss_macro_step}};
  for (const auto& [cut, value] : keys)
    if (value->has_value() && w.count(cut) == 0)
      w[cut] = {.window = **value,
                .origin = "[coupling] " + std::string(cut) + "_macro_step in " + scene.source};
  return w;
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
  take("--step-deadline-floor", c.step_deadline_floor, r.step_deadline_floor);
  take("--judge", c.judge, r.judge);
  take("--judge-budget", c.judge_budget, r.judge_budget);
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

std::map<std::string, long> check_cut_windows(const RunArgs& a, const Scene& scene,
                                              const CaseSpec& spec, double finest) {
  auto in_case = [&spec](const std::string& cut) {
    return std::any_of(spec.cuts.begin(), spec.cuts.end(),
                       [&cut](const CutChoice& c) { return cut_name_of(c) == cut; });
  };
  for (const auto& [cut, w] : a.cut_windows)
    if (!in_case(cut))
      throw std::invalid_argument(w.origin + ": case " + spec.name() + " has no cut " + cut);
  std::map<std::string, long> ratios = engine::cut_ratios(finest, a.cut_windows);
  // The scene's windows are defaults: each applies to a case with its cut
  // where it is an integer multiple of H over one.
  std::map<std::string, long> from_scene;
  for (const auto& [cut, w] : given_cut_windows(a, scene)) {
    if (ratios.count(cut) != 0 || !in_case(cut)) continue;
    const double k = w.window / finest, near = std::round(k);
    if (near >= 2 && std::abs(k - near) <= 1e-9 * k) from_scene[cut] = static_cast<long>(near);
  }
  ratios.insert(from_scene.begin(), from_scene.end());
  for (const CutChoice& c : spec.cuts) ratios.emplace(cut_name_of(c), 1);
  return ratios;
}

// --macro-step H (the finest window) and --macro-step CUT=H_cut, repeatable.
void add_macro_step_option(CLI::App& run_command, RunArgs& a) {
  CLI::App* run = &run_command;
  run->add_option_function<std::vector<std::string>>(
         "--macro-step",
         [&a](const std::vector<std::string>& values) {
           try {
             for (const std::string& v : values) {
               const double h = engine::read_macro_step(v, a.cut_windows);
               if (h > 0) a.macro_step = h;
             }
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError(e.what());
           }
         },
         "Macro step H in seconds, the finest window (default: simulation.macro_step of the "
         "scene); repeatable as CUT=H_cut to give cut wr, rs or ss its own window, an integer "
         "multiple of H (default: [coupling] CUT_macro_step of the scene, else H)")
      ->allow_extra_args(false);
}

std::string cut_windows_note(const RunArgs& a, const Scene& scene) {
  std::string s;
  for (const auto& [cut, w] : given_cut_windows(a, scene)) s += (s.empty() ? "" : ", ") + w.origin;
  return s.empty() ? "the cuts' windows" : s;
}

std::string scene_coupling_help() {
  std::string s =
      "A scene's [coupling] table (docs/scene-keys.md) stands in for the flags of its keys; a "
      "flag given wins:";
  for (const Taken& t : keys_of(SceneCoupling{})) {
    const std::string flag = t.flag;
    const std::string key = t.key;
    const bool per_cut = key.size() > 11 && key.compare(key.size() - 11, 11, "_macro_step") == 0;
    s += "\n  " + key + " = " + (per_cut ? flag + " " + key.substr(0, 2) + "=H_cut" : flag);
    if (key == "implicit") s += " implicit (true) or explicit (false)";
  }
  return s;
}

}  // namespace railcosim::cli
