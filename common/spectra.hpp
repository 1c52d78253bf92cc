// One-third-octave band spectra of a sampled time series (the contact force,
// the forces into the ballast).
//
// Bands follow IEC 61260-1 base-10: centre f_m = 1000 * 10^(m/10) Hz (the
// exact centres; the nominal labels 1.25, 1.6, 2, ... Hz are their rounded
// names), edges f_m * 10^(-1/20) and f_m * 10^(1/20). Each band's value is
// its RMS: the square root of the signal's mean square carried by the
// discrete Fourier components whose frequency lies in [lower, upper) edge
// (rectangular window over the whole record, so that by Parseval the bands
// together with the mean and the components outside the bands add up to the
// signal's mean square). The level in dB is 20 log10(rms / reference).
#pragma once

#include <complex>
#include <vector>

namespace railcosim {

struct Band {
  int index;        // m: centre 1000 * 10^(m/10) Hz
  double centre;    // Hz
  double lower;     // Hz
  double upper;     // Hz
  double rms;       // same unit as the signal
  double level_db;  // 20 log10(rms / reference); -inf for a silent band
};

// In-place radix-2 FFT (size a power of two), forward: X_k = sum x_n e^{-2 pi i k n / N}.
void fft(std::vector<std::complex<double>>& x);

// The bands that hold frequencies from f_min to f_max (those whose centre is
// below the Nyquist frequency); dt the sample interval. The mean is removed first (a constant
// carries no vibration). The record is zero-padded to a power of two, which
// refines the frequency grid without changing the mean square.
std::vector<Band> third_octave_spectrum(const std::vector<double>& signal, double dt, double f_min,
                                        double f_max, double reference = 1.0);

// The band holding frequency f: round(10 log10(f / 1000)).
int third_octave_index(double f);
double third_octave_centre(int index);

}  // namespace railcosim
