#include "verdict/evaluation.hpp"

#include <cctype>
#include <map>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "verdict/map_measure.hpp"
#include "verdict/stability.hpp"

namespace railcosim::verdict {

DeflectionError deflection_error(const std::vector<double>& w, const std::vector<double>& ref) {
  DeflectionError e;
  double num = 0, den = 0;
  for (std::size_t k = 0; k < std::min(w.size(), ref.size()); ++k) {
    const double d = w[k] - ref[k];
    e.max_abs = std::max(e.max_abs, std::abs(d));
    num += d * d;
    den += ref[k] * ref[k];
  }
  e.rel_l2 = den > 0 ? std::sqrt(num / den) : 0.0;
  return e;
}

double history_error(const std::vector<HistoryRow>& h, const std::vector<HistoryRow>& ref,
                     double static_load, double static_wheel) {
  const std::size_t n = std::min(h.size(), ref.size());
  if (n == 0) return 0.0;
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double df = (h[i].contact_force - ref[i].contact_force) / static_load;
    const double dq = (h[i].wheel - ref[i].wheel) / static_wheel;
    sum += df * df + dq * dq;
  }
  return std::sqrt(sum / static_cast<double>(n));
}

double coupling_history_error(const RunRecord& run, const RunRecord& ref) {
  const std::size_t n = std::min(run.history.size(), ref.history.size());
  if (n == 0) return 0.0;
  // Scaled error series: each quantity against the largest magnitude it has
  // in the reference run (its static value for the loads the vehicle
  // carries; for a sleeper far from the vehicle, whose static force is
  // nearly zero, the load it takes when the vehicle passes).
  std::vector<std::vector<double>> series;
  auto add = [&](auto run_of, auto ref_of, double scale = 0.0) {
    for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(ref_of(i)));
    if (!(scale > 0)) return;
    std::vector<double> e(n);
    for (std::size_t i = 0; i < n; ++i) e[i] = (run_of(i) - ref_of(i)) / scale;
    series.push_back(std::move(e));
  };
  add([&](std::size_t i) { return run.history[i].contact_force; },
      [&](std::size_t i) { return ref.history[i].contact_force; });
  add([&](std::size_t i) { return run.history[i].wheel; },
      [&](std::size_t i) { return ref.history[i].wheel; });
  // Channels of one family (the same name but for the numbers in it: one per
  // wheel, one per sleeper) share the family's largest magnitude, so that a
  // sleeper the vehicle has not reached yet is measured against the load a
  // sleeper takes, not against its own near-zero values.
  auto family = [](const std::string& name) {
    std::string f;
    for (char ch : name)
      if (!std::isdigit(static_cast<unsigned char>(ch)) || f.empty() || f.back() != '#')
        f += std::isdigit(static_cast<unsigned char>(ch)) ? '#' : ch;
    return f;
  };
  std::map<std::string, double> family_scale;
  for (std::size_t d = 0; d < ref.extra_channels.size(); ++d) {
    double& m = family_scale[family(ref.extra_channels[d])];
    for (std::size_t i = 0; i < n; ++i) m = std::max(m, std::abs(ref.history[i].extra.at(d)));
  }
  for (std::size_t c = 0; c < run.extra_channels.size(); ++c)
    for (std::size_t d = 0; d < ref.extra_channels.size(); ++d)
      if (run.extra_channels[c] == ref.extra_channels[d])
        add([&](std::size_t i) { return run.history[i].extra.at(c); },
            [&](std::size_t i) { return ref.history[i].extra.at(d); },
            family_scale[family(ref.extra_channels[d])]);
  for (const auto& entry : run.coupling_history) {
    const auto it = ref.coupling_history.find(entry.first);
    const std::vector<double>& got = entry.second;
    if (it == ref.coupling_history.end() || it->second.size() < n || got.size() < n) continue;
    const std::vector<double>& want = it->second;
    add([&](std::size_t i) { return got[i]; }, [&](std::size_t i) { return want[i]; });
  }
  // The worst quantity decides: the RMS of each series on its own, except
  // the contact force and the wheel (the first two), judged together as the
  // paper's two channels always were. A mean over all series would hide one
  // that runs away among many that do not, and a sum would grow with the
  // number of sleepers.
  auto rms = [&](std::size_t first, std::size_t count) {
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = first; k < first + count && k < series.size(); ++k)
        sum += series[k][i] * series[k][i];
    return std::sqrt(sum / static_cast<double>(n));
  };
  double worst = rms(0, 2);
  for (std::size_t k = 2; k < series.size(); ++k) worst = std::max(worst, rms(k, 1));
  return worst;
}

double divergence_bound(const Scene& scene, double largest_static_displacement) {
  return scene.divergence_factor * largest_static_displacement;
}

// rho with three digits in its distance from 1 (at least four in all).
std::string rho_words(double rho) {
  const double off = std::abs(rho - 1);
  const int digits = off > 0 ? std::max(4, 3 + static_cast<int>(std::ceil(-std::log10(off)))) : 4;
  std::ostringstream s;
  s << std::setprecision(std::min(digits, 12)) << rho;
  return s.str();
}

namespace {

// A time as a person reads it: ms below a second, three digits.
std::string duration_words(double seconds) {
  char buf[32];
  if (seconds < 1)
    std::snprintf(buf, sizeof buf, "%.3g ms", seconds * 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.3g s", seconds);
  return buf;
}

// The map's words: rho, the e-folding time, and which micro steps it takes.
void map_words(std::ostream& s, const RunRecord& run) {
  const bool growing = *run.spectral_rate > 0 && run.stability == "unstable";
  // A multirate run's map steps one slow window (several macro steps).
  double window = run.macro_step;
  for (const auto& [cut, w] : run.windows) window = std::max(window, w);
  std::ostringstream per;
  if (window > run.macro_step * (1 + 1e-9))
    per << " per slow window (" << window << " s)";
  else
    per << " per macro step";
  s << (growing ? "at rest: " : "") << "ρ = " << rho_words(*run.spectral_radius) << per.str()
    << (growing ? "" : " at rest");
  if (*run.spectral_rate > 0)
    s << ", e-folds every " << duration_words(1 / *run.spectral_rate) << " ("
      << std::setprecision(3) << *run.spectral_rate << " 1/s; the run lasts "
      << duration_words(run.t_end) << ")";
  if (run.stability_basis == "matrix-free")
    s << ", measured through the participants (matrix-free, " << run.matrix_free_steps.value_or(0)
      << " macro steps parked)";
  if (run.stability_basis == "map" && run.method == "implicit")
    s << " (the map of the step converged to " << kMapConvergence << ")";
  if (run.method == "implicit" && run.not_converged_steps.value_or(0) > 0)
    s << "; " << *run.not_converged_steps
      << " of the run's own macro steps did not converge, and it is not that coupling";
  if (!run.map_micro_steps) return;
  double most = 0;  // the moving run's micro steps per macro step, on average
  for (const auto& [who, count] : run.micro_steps)
    if (run.macro_steps > 0)
      most = std::max(most, static_cast<double>(count) / static_cast<double>(run.macro_steps));
  if (most > 1.05 * static_cast<double>(*run.map_micro_steps))
    s << std::setprecision(3) << "; this is the parked coupling's map, with "
      << *run.map_micro_steps << " micro step(s) per macro step; the moving run took " << most
      << " on average, and its map differs";
}

// What the stability verdict rests on, in words ("" when nothing was judged).
std::string growth_words(const RunRecord& run) {
  std::ostringstream s;
  if ((run.stability_basis == "map" || run.stability_basis == "matrix-free") &&
      run.spectral_radius && run.spectral_rate) {
    map_words(s, run);
  } else if (run.error_growth && run.probe_time) {  // the probe's
    s << "a perturbation of the static state grew " << *run.error_growth << " times in "
      << *run.probe_time << " s (rate " << run.error_growth_rate.value_or(0) << " 1/s)";
  }
  if (run.defect_growth && (run.defect_grows || run.stability == "unstable")) {
    s << (s.str().empty() ? "" : "; ") << std::setprecision(3);
    if (run.defect_grows)
      s << "along the moving run the coupling's defect grew " << *run.defect_growth
        << " times over its last eighth (" << run.defect_rate.value_or(0)
        << " 1/s): the run diverges if it goes on";
    else
      s << "along the moving run the coupling's defect did not grow (" << *run.defect_growth
        << " times over its last eighth)";
  }
  return s.str();
}

}  // namespace

void judge(RunRecord& run, const RunRecord& reference, const Scene& scene) {
  if (run.status == "diverged" || run.status == "failed") return;
  const DeflectionError e = deflection_error(run.deflection, reference.deflection);
  run.max_abs_error_m = e.max_abs;
  run.rel_l2_error = e.rel_l2;
  run.history_error = coupling_history_error(run, reference);
  std::ostringstream size;
  if (*run.history_error > scene.amplification_threshold)
    size << "history error " << *run.history_error
         << " exceeds cosim.amplification_threshold = " << scene.amplification_threshold;
  if (e.rel_l2 > kMaxDeflectionError)
    size << (size.str().empty() ? "" : "; ") << "rel. L2 deflection error " << e.rel_l2
         << " exceeds " << kMaxDeflectionError;
  std::ostringstream why;
  const std::string growth = growth_words(run);
  if (*run.history_error > kGrossHistoryError && run.stability != "unstable") {
    why << "unstable at finite amplitude: the history error " << *run.history_error << " is over "
        << kGrossHistoryError << " (errors as large as the static quantities themselves)";
    if (!growth.empty()) why << ", although at rest " << growth;
    run.stability = "unstable";
  } else if (run.stability == "unstable") {
    why << "unstable";
    if (!growth.empty()) why << (growth.rfind("at rest", 0) == 0 ? " " : ": ") << growth;
    if (!size.str().empty()) why << "; " << size.str();
  } else if (!size.str().empty()) {
    why << size.str();
    if (!growth.empty()) why << " (stable: " << growth << ")";
  }
  // The measure of the map ran out of its budget: the errors were measured,
  // the stability was not, and the status claims no more.
  const bool unmeasured = run.stability == kNotJudged && run.stability_basis == "map";
  if (unmeasured && run.status == "ok") {
    run.status = size.str().empty() ? "not_judged" : "inaccurate";
    run.message = (size.str().empty() ? std::string("errors within their bounds") : size.str()) +
                  "; stability not judged: " + run.spectral_note;
    return;
  }
  if (why.str().empty()) return;
  if (run.status == "not_converged") {  // that stays the verdict; the rest is said
    run.message += "; " + why.str();
  } else {
    run.status = run.stability == "unstable" ? "amplified" : "inaccurate";
    run.message = why.str();
  }
}

void judge_unmeasured(RunRecord& run, const std::string& why) {
  if (run.status == "diverged" || run.status == "failed") return;
  const std::string growth = growth_words(run);
  if (run.stability == "unstable") {
    run.status = "amplified";
    run.message = "unstable: " + growth + "; errors not judged: " + why;
  } else if (run.status == "not_converged") {
    run.message += "; errors not judged: " + why;
  } else {
    run.status = "not_judged";
    run.message = "not judged: " + why;
    if (run.stability == "stable" && !growth.empty()) run.message += "; stable: " + growth;
  }
}

}  // namespace railcosim::verdict
