// A macro step per cut: `--macro-step CUT=H_cut` and the scene's
// [coupling] wr_macro_step / rs_macro_step / ss_macro_step give a cut a
// window that is an integer multiple of the finest window H (the plain
// `--macro-step H`, or simulation.macro_step). These functions read and check
// them; the windows are the plan's to order (engine/step_plan.hpp).
#pragma once

#include <map>
#include <string>

namespace railcosim::engine {

// One cut's window as it was given, with where it came from for messages
// ("--macro-step ss=0.001", "[coupling] ss_macro_step in scenes/soil.toml").
struct CutWindow {
  double window = 0;   // s
  std::string origin;  // the option or key that gave it
};

// Reads one value of --macro-step: "H" (the finest window; returned) or
// "CUT=H_cut" (stored in `cuts`, CUT one of wr, rs, ss; returns 0). Throws
// std::invalid_argument naming the value when it is neither, when H is not a
// positive number, or when CUT was given twice.
double read_macro_step(const std::string& value, std::map<std::string, CutWindow>& cuts);

// The window of each cut in `cuts` as a count of finest windows `finest`.
// Throws std::invalid_argument naming the option or key, both values and the
// nearest multiples of `finest` when a window is not an integer multiple of
// it (relative tolerance 1e-9), or is finer than it, or more than
// kMaxCutRatio times it.
inline constexpr double kMaxCutRatio = 1e9;
std::map<std::string, long> cut_ratios(double finest, const std::map<std::string, CutWindow>& cuts);

// The cut names a window can be given for.
bool is_cut_name(const std::string& cut);

}  // namespace railcosim::engine
