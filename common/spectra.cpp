#include "spectra.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace railcosim {

void fft(std::vector<std::complex<double>>& x) {
  const std::size_t n = x.size();
  if (n == 0 || (n & (n - 1)) != 0) throw std::invalid_argument("fft: size must be a power of two");
  for (std::size_t i = 1, j = 0; i < n; ++i) {  // bit-reversal permutation
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = -2.0 * std::numbers::pi / static_cast<double>(len);
    for (std::size_t i = 0; i < n; i += len) {
      for (std::size_t k = 0; k < len / 2; ++k) {
        // Twiddle computed directly (no recurrence): accurate for long records.
        const std::complex<double> w = std::polar(1.0, ang * static_cast<double>(k));
        const std::complex<double> u = x[i + k], v = x[i + k + len / 2] * w;
        x[i + k] = u + v;
        x[i + k + len / 2] = u - v;
      }
    }
  }
}

int third_octave_index(double f) {
  return static_cast<int>(std::lround(10.0 * std::log10(f / 1000.0)));
}

double third_octave_centre(int index) {
  return 1000.0 * std::pow(10.0, index / 10.0);
}

std::vector<Band> third_octave_spectrum(const std::vector<double>& signal, double dt, double f_min,
                                        double f_max, double reference) {
  if (signal.size() < 2 || !(dt > 0) || !(f_min > 0) || !(f_max >= f_min) || !(reference > 0))
    throw std::invalid_argument("third_octave_spectrum: bad arguments");
  const std::size_t n = signal.size();
  std::size_t np = 1;
  while (np < n) np <<= 1;
  double mean = 0;
  for (double v : signal) mean += v;
  mean /= static_cast<double>(n);
  std::vector<std::complex<double>> X(np, 0.0);
  for (std::size_t i = 0; i < n; ++i) X[i] = signal[i] - mean;
  fft(X);
  // Mean square of the record = sum_k |X_k|^2 / (Np N) over all k (Parseval
  // on the padded record, whose extra samples are zero). Fold the negative
  // frequencies onto the positive ones.
  const double df = 1.0 / (static_cast<double>(np) * dt);
  const double scale = 1.0 / (static_cast<double>(np) * static_cast<double>(n));
  std::vector<double> power(np / 2 + 1);
  for (std::size_t k = 0; k <= np / 2; ++k) {
    const bool paired = k != 0 && k != np / 2;
    power[k] = (paired ? 2.0 : 1.0) * std::norm(X[k]) * scale;
  }
  const double nyquist = 0.5 / dt;
  std::vector<Band> bands;
  const double edge = std::pow(10.0, 0.05);
  for (int m = third_octave_index(f_min); m <= third_octave_index(f_max); ++m) {
    const double fc = third_octave_centre(m);
    if (fc < f_min / edge || fc > f_max * edge || fc > nyquist) continue;
    Band b{m, fc, fc / edge, fc * edge, 0.0, 0.0};
    double ms = 0;
    const auto k0 = static_cast<std::size_t>(std::ceil(b.lower / df));
    for (std::size_t k = k0; k <= np / 2 && static_cast<double>(k) * df < b.upper; ++k)
      ms += power[k];
    b.rms = std::sqrt(ms);
    b.level_db =
        b.rms > 0 ? 20.0 * std::log10(b.rms / reference) : -std::numeric_limits<double>::infinity();
    bands.push_back(b);
  }
  return bands;
}

}  // namespace railcosim
