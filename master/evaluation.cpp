#include "evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "monolithic.hpp"
#include "track_model.hpp"

namespace railcosim {

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

double coupling_history_error(const RunRecord& run, const RunRecord& ref, double static_load) {
  const std::size_t n = std::min(run.history.size(), ref.history.size());
  if (n == 0) return 0.0;
  // Scaled error series: each quantity against its static (first-row) value.
  std::vector<std::vector<double>> series;
  auto add = [&](auto value_of, double scale) {
    if (!(std::abs(scale) > 0)) return;
    std::vector<double> e(n);
    for (std::size_t i = 0; i < n; ++i) e[i] = value_of(i) / scale;
    series.push_back(std::move(e));
  };
  add([&](std::size_t i) { return run.history[i].contact_force - ref.history[i].contact_force; },
      static_load);
  add([&](std::size_t i) { return run.history[i].wheel - ref.history[i].wheel; },
      ref.history.front().wheel);
  for (std::size_t c = 0; c < run.extra_channels.size(); ++c)
    for (std::size_t d = 0; d < ref.extra_channels.size(); ++d)
      if (run.extra_channels[c] == ref.extra_channels[d])
        add([&](std::size_t i) { return run.history[i].extra.at(c) - ref.history[i].extra.at(d); },
            ref.history.front().extra.at(d));
  for (const auto& [cut, values] : run.coupling_history) {
    const auto it = ref.coupling_history.find(cut);
    if (it == ref.coupling_history.end() || it->second.size() < n || values.size() < n) continue;
    add([&](std::size_t i) { return values[i] - it->second[i]; }, it->second.front());
  }
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& e : series) sum += e[i] * e[i];
  return std::sqrt(sum / static_cast<double>(n));
}

void record_coupling(RunRecord& run, const std::vector<ParticipantSpec>& participants,
                     const std::vector<StepResult>& outputs) {
  for (std::size_t p = 0; p < participants.size() && p < outputs.size(); ++p) {
    const auto& interfaces = participants[p].interfaces;
    for (std::size_t i = 0; i < interfaces.size() && i < outputs[p].outputs.size(); ++i) {
      const InterfaceSpec& spec = interfaces[i];
      if (spec.kind().moving || spec.side != CutSide::kLower) continue;
      double largest = 0;
      for (double u : outputs[p].outputs[i].displacement) largest = std::max(largest, std::abs(u));
      run.coupling_history[spec.kind().name].push_back(largest);
    }
  }
}

void record_coupling(RunRecord& run, const MonolithicModel& model) {
  const DofLayout& layout = model.structure().layout;
  const auto& u = model.integrator().state().u;
  for (const char* cut : {"rs", "ss"}) {
    if (std::string(cut) == "ss" && layout.soil.empty()) continue;
    double largest = 0;
    for (int d : layer_dofs(layout, find_cut(cut), CutSide::kLower))
      largest = std::max(largest, std::abs(u[d]));
    run.coupling_history[cut].push_back(largest);
  }
}

double divergence_bound(const Scene& scene, double largest_static_displacement) {
  return scene.divergence_factor * largest_static_displacement;
}

void judge(RunRecord& run, const RunRecord& reference, const Scene& scene) {
  if (run.status == "diverged" || run.status == "failed") return;
  const DeflectionError e = deflection_error(run.deflection, reference.deflection);
  run.max_abs_error_m = e.max_abs;
  run.rel_l2_error = e.rel_l2;
  run.history_error = coupling_history_error(run, reference, scene.load());
  std::ostringstream s;
  if (*run.history_error > scene.amplification_threshold)
    s << "history error " << *run.history_error
      << " exceeds cosim.amplification_threshold = " << scene.amplification_threshold;
  if (e.rel_l2 > kMaxDeflectionError)
    s << (s.str().empty() ? "" : "; ") << "rel. L2 deflection error " << e.rel_l2 << " exceeds "
      << kMaxDeflectionError;
  if (!s.str().empty()) {
    run.status = "amplified";
    run.message = s.str();
  }
}

}  // namespace railcosim
