// One-third-octave band spectra: band centres and edges of IEC 61260-1
// (base 10), band RMS by Parseval.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "spectra.hpp"

namespace railcosim {
namespace {

std::vector<double> sine(double amplitude, double f, double dt, std::size_t n, double offset = 0) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = offset + amplitude * std::sin(2 * std::numbers::pi * f * static_cast<double>(i) * dt);
  return x;
}

TEST(ThirdOctave, BandCentresAreTheBase10Series) {
  EXPECT_DOUBLE_EQ(third_octave_centre(0), 1000.0);
  EXPECT_NEAR(third_octave_centre(-10), 100.0, 1e-12);
  EXPECT_NEAR(third_octave_centre(-9), 125.89254117941672, 1e-9);  // nominal 125 Hz
  EXPECT_EQ(third_octave_index(63.0), -12);
  EXPECT_EQ(third_octave_index(1000.0), 0);
  // Adjacent bands share their edges.
  const auto bands = third_octave_spectrum(sine(1, 100, 1e-4, 1000), 1e-4, 10, 1000);
  for (std::size_t k = 1; k < bands.size(); ++k)
    EXPECT_NEAR(bands[k].lower, bands[k - 1].upper, 1e-9 * bands[k].lower);
}

// A sine of amplitude A that fits the record a whole number of times puts all
// its mean square A^2 / 2 into its band: band RMS A / sqrt(2), the others
// silent (to round-off); the mean (offset) is not vibration.
TEST(ThirdOctave, ASineHasItsRmsInItsBandAlone) {
  const double dt = 1.0 / 4096, A = 3.0;
  const std::size_t n = 4096;  // 1 s: a power of two, so no padding
  for (double f : {31.0, 100.0, 250.0}) {
    const auto bands = third_octave_spectrum(sine(A, f, dt, n, 7.0), dt, 10, 1000);
    for (const Band& b : bands) {
      if (b.index == third_octave_index(f))
        EXPECT_NEAR(b.rms, A / std::sqrt(2.0), 1e-12 * A) << f;
      else
        EXPECT_LT(b.rms, 1e-10 * A) << f << " Hz leaks into " << b.centre;
    }
  }
}

// A record that is not a whole number of periods, zero-padded: the sine's
// band still holds nearly all of its mean square (leakage through the
// rectangular window's side lobes stays a few per cent at 40 periods).
TEST(ThirdOctave, AnUnevenRecordStillPutsTheSineInItsBand) {
  const double dt = 1e-4, A = 2.0, f = 97.3;
  const auto bands = third_octave_spectrum(sine(A, f, dt, 4123), dt, 10, 2000);
  double total = 0, in_band = 0;
  for (const Band& b : bands) {
    total += b.rms * b.rms;
    if (b.index == third_octave_index(f)) in_band = b.rms;
  }
  EXPECT_NEAR(in_band, A / std::sqrt(2.0), 0.05 * A / std::sqrt(2.0));
  EXPECT_GT(in_band * in_band, 0.95 * total);
}

TEST(ThirdOctave, RejectsBadArguments) {
  EXPECT_THROW(third_octave_spectrum({1.0}, 1e-3, 10, 100), std::invalid_argument);
  EXPECT_THROW(third_octave_spectrum({1.0, 2.0}, 0.0, 10, 100), std::invalid_argument);
}

}  // namespace
}  // namespace railcosim
