#include "waveform.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace railcosim {

Waveform::Waveform(int degree, std::size_t width) : degree_(degree), width_(width) {
  if (degree < 0 || degree > kMaxDegree)
    throw std::invalid_argument("waveform degree must lie between 0 and " +
                                std::to_string(kMaxDegree) + " (got " + std::to_string(degree) +
                                ")");
}

void Waveform::add(double t, const std::vector<double>& values) {
  if (values.size() != width_)
    throw std::invalid_argument("waveform sample of " + std::to_string(values.size()) +
                                " values where " + std::to_string(width_) + " are expected");
  if (!times_.empty() && !(t > times_.back()))
    throw std::invalid_argument("waveform sample at t = " + std::to_string(t) + " s after one at " +
                                std::to_string(times_.back()) + " s: times must increase");
  times_.push_back(t);
  values_.push_back(values);
}

void Waveform::keep_last() {
  if (times_.size() <= 1) return;
  times_.erase(times_.begin(), times_.end() - 1);
  values_.erase(values_.begin(), values_.end() - 1);
}

int Waveform::effective_degree() const {
  return std::min(degree_, static_cast<int>(times_.size()) - 1);
}

void Waveform::at(double t, std::vector<double>& out) const {
  if (times_.empty()) throw std::logic_error("waveform evaluated before any sample");
  out.assign(width_, 0.0);
  const auto n = times_.size();
  // The interval [times_[j], times_[j + 1]) that holds t, clamped to the ends.
  const auto upper = std::upper_bound(times_.begin(), times_.end(), t);
  std::size_t j =
      upper == times_.begin() ? 0 : static_cast<std::size_t>(upper - times_.begin()) - 1;
  j = std::min(j, n - 1);
  const int p = effective_degree();
  if (p == 0) {
    // Held: the sample at or before t (the first one before the window).
    out = values_[j];
    return;
  }
  // The p + 1 samples around the interval: as many on each side as the ends
  // allow, the stencil sliding inward at either end.
  const auto width = static_cast<std::size_t>(p) + 1;
  const std::size_t left = (static_cast<std::size_t>(p) - 1) / 2;  // samples before j
  std::size_t first = j >= left ? j - left : 0;
  first = std::min(first, n - width);
  for (std::size_t a = first; a < first + width; ++a) {
    double w = 1.0;  // Lagrange basis polynomial of sample a at t
    for (std::size_t b = first; b < first + width; ++b)
      if (b != a) w *= (t - times_[b]) / (times_[a] - times_[b]);
    const std::vector<double>& v = values_[a];
    for (std::size_t k = 0; k < width_; ++k) out[k] += w * v[k];
  }
}

std::vector<double> Waveform::at(double t) const {
  std::vector<double> out;
  at(t, out);
  return out;
}

}  // namespace railcosim
