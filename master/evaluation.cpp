#include "evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

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

double divergence_bound(const Scene& scene, double largest_static_displacement) {
  return scene.divergence_factor * largest_static_displacement;
}

void judge(RunRecord& run, const RunRecord& reference, const Scene& scene) {
  if (run.status == "diverged" || run.status == "failed") return;
  const DeflectionError e = deflection_error(run.deflection, reference.deflection);
  run.max_abs_error_m = e.max_abs;
  run.rel_l2_error = e.rel_l2;
  // The reference's first row is the static state.
  const double static_wheel = reference.history.empty() ? 0.0 : reference.history.front().wheel;
  run.history_error = history_error(run.history, reference.history, scene.load(), static_wheel);
  if (*run.history_error > scene.amplification_threshold) {
    run.status = "amplified";
    std::ostringstream s;
    s << "history error " << *run.history_error
      << " exceeds cosim.amplification_threshold = " << scene.amplification_threshold;
    run.message = s.str();
  }
}

}  // namespace railcosim
