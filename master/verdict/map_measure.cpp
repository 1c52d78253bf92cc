#include "verdict/map_measure.hpp"

#include <algorithm>
#include <cmath>

namespace railcosim::verdict {

Spectrum measure_map(const LinearOperator& a, const MapSettings& settings) {
  const bool dense = settings.method == MapMethod::kDense ||
                     (settings.method == MapMethod::kAuto && a.dimension <= kDenseMapLimit);
  Budget whole;  // the dense map: no bound of products, the stop kept
  whole.stop = settings.budget.stop;
  return dense ? dense_spectrum(a, settings.method == MapMethod::kDense ? settings.budget : whole)
               : dominant_spectrum(a, settings.budget, settings.krylov);
}

MapSpectrum map_spectrum(const Spectrum& m, double window, const std::string& refused) {
  MapSpectrum s;
  s.dimension = m.dimension;
  s.products = m.products;
  s.method = m.method;
  s.solver = m.solver;
  if (!refused.empty()) {
    s.why_not = refused;
    return s;
  }
  if (!m.converged) {
    s.why_not = m.why_not;
    return s;
  }
  s.rho = m.rho;
  s.leading = m.leading;
  s.frequency_hz = std::abs(std::arg(m.dominant)) / (2 * M_PI * window);
  s.rate_per_s = std::log(std::max(s.rho, 1e-300)) / window;
  s.computed = true;
  return s;
}

}  // namespace railcosim::verdict
