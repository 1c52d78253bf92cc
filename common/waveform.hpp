// A coupling quantity over one time window, from the samples its sender took
// at its own substeps: the receiver evaluates it at any time of the window,
// so the window (the macro step) stops setting how finely the exchanged data
// is resolved in time.
//
// Interpolation of degree p (0 to 3) is local: at time t it uses the p + 1
// samples nearest to t (the stencil slides inward at the window's ends) and
// the Lagrange polynomial through them. It is therefore exact for every
// polynomial of degree p or less, and its error on a smooth signal is of
// order h^(p+1) in the spacing h of the samples. Degree 0 holds each sample
// until the next one. With fewer than p + 1 samples the degree falls to the
// number of samples less one (one sample: held).
#pragma once

#include <cstddef>
#include <vector>

namespace railcosim {

class Waveform {
 public:
  static constexpr int kMaxDegree = 3;

  // A waveform of `width` values per sample, interpolated with `degree`.
  Waveform(int degree, std::size_t width);

  // Appends a sample; times must increase strictly, `values` have `width`
  // entries. Throws std::invalid_argument otherwise.
  void add(double t, const std::vector<double>& values);
  // Drops every sample but the last one (the start of the next window).
  void keep_last();
  void clear() { times_.clear(), values_.clear(); }

  int degree() const { return degree_; }
  // The degree used: min(degree, samples - 1).
  int effective_degree() const;
  std::size_t width() const { return width_; }
  std::size_t samples() const { return times_.size(); }
  double first_time() const { return times_.front(); }
  double last_time() const { return times_.back(); }
  double time(std::size_t i) const { return times_[i]; }
  const std::vector<double>& sample(std::size_t i) const { return values_[i]; }

  // The values at time t into `out` (resized to width). Outside the sampled
  // times the end stencil's polynomial extrapolates (degree 0: the nearest
  // sample held). Throws std::logic_error when there is no sample.
  void at(double t, std::vector<double>& out) const;
  std::vector<double> at(double t) const;

 private:
  int degree_;
  std::size_t width_;
  std::vector<double> times_;
  std::vector<std::vector<double>> values_;
};

}  // namespace railcosim
