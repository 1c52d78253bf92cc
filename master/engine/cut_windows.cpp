#include "engine/cut_windows.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace railcosim::engine {

bool is_cut_name(const std::string& cut) {
  return cut == "wr" || cut == "rs" || cut == "ss";
}

namespace {

std::string window_text(double v) {
  std::ostringstream s;
  s.precision(17);
  for (int p = 1; p <= 17; ++p) {
    std::ostringstream t;
    t.precision(p);
    t << v;
    if (std::strtod(t.str().c_str(), nullptr) == v) return t.str();
  }
  s << v;
  return s.str();
}

double window_seconds(const std::string& text, const std::string& value) {
  char* end = nullptr;
  const double h = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(h) || h <= 0)
    throw std::invalid_argument("--macro-step " + value +
                                ": the window must be a positive number of seconds");
  return h;
}

}  // namespace

double read_macro_step(const std::string& value, std::map<std::string, CutWindow>& cuts) {
  const std::size_t eq = value.find('=');
  if (eq == std::string::npos) return window_seconds(value, value);
  const std::string cut = value.substr(0, eq);
  if (!is_cut_name(cut))
    throw std::invalid_argument("--macro-step " + value + ": unknown cut '" + cut +
                                "' (the cuts are wr, rs and ss)");
  if (cuts.count(cut) != 0)
    throw std::invalid_argument("--macro-step " + value + ": cut " + cut + " was already given (" +
                                cuts.at(cut).origin + ")");
  cuts[cut] = {.window = window_seconds(value.substr(eq + 1), value),
               .origin = "--macro-step " + value};
  return 0;
}

std::map<std::string, long> cut_ratios(double finest,
                                       const std::map<std::string, CutWindow>& cuts) {
  std::map<std::string, long> ratios;
  for (const auto& [cut, w] : cuts) {
    const double k = w.window / finest;
    const double near = std::round(k);
    if (!(k <= kMaxCutRatio))
      throw std::invalid_argument(w.origin + ": the window " + window_text(w.window) +
                                  " s of cut " + cut + " is " + window_text(k) +
                                  " times the finest window " + window_text(finest) +
                                  " s; a cut's window is at most " + window_text(kMaxCutRatio) +
                                  " finest windows (and must divide the run's end time)");
    if (near >= 1 && std::abs(k - near) <= 1e-9 * k) {
      ratios[cut] = static_cast<long>(near);
      continue;
    }
    const double below = std::max(1.0, std::floor(k));
    const double above = std::max(1.0, std::ceil(k));
    std::string msg = w.origin + ": the window " + window_text(w.window) + " s of cut " + cut +
                      " is not an integer multiple of the finest window " + window_text(finest) +
                      " s; the nearest multiples are " + window_text(below * finest) + " s";
    if (above != below) msg += " and " + window_text(above * finest) + " s";
    throw std::invalid_argument(msg);
  }
  return ratios;
}

}  // namespace railcosim::engine
