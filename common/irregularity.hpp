// Vertical rail profiles r(x): the rail top's vertical position before any
// load, positive DOWN like every displacement here (a dip in the rail is
// r > 0). The contact penetration of a wheel at x_c with displacement q over
// a rail that has deflected by w_c there is
//
//   delta = q - w_c - r(x_c)
//
// so a positive r moves the rail top away from the wheel and unloads it.
//
// Sources:
//  - RandomProfile: a stationary random profile from the one-sided FRA
//    vertical-profile PSD, a sum of cosines with seeded random phases;
//  - TableProfile: a measured profile from a CSV file (x_m,r_m);
//  - DippedJoint: an isolated cosine dip;
//  - SineProfile: one harmonic (a test and tuning aid).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace railcosim {

// The penetration of a wheel at displacement q (down) over a rail deflected
// by w_c, with rail profile r and the wheel's flat loss f (both >= 0 unload).
inline double contact_penetration(double q, double w_c, double r, double flat_loss = 0.0) {
  return q - w_c - r - flat_loss;
}

class RailProfile {
 public:
  virtual ~RailProfile() = default;
  virtual double height(double x) const = 0;  // r(x), m, positive down
  virtual double slope(double x) const = 0;   // dr/dx
};

// Small, fully specified generator (Steele, Lea & Flood's SplitMix64): the
// same seed gives the same numbers on every platform and compiler, which
// std::uniform_real_distribution does not promise.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

// The FRA one-sided vertical-profile PSD (Hamid & Yang 1981, "Analytical
// descriptions of track geometry variations", FRA; the form and class table
// as reproduced in Zhai's vehicle-track coupled dynamics):
//
//   S(Omega) = k A_v Omega_c^2 / (Omega^2 (Omega^2 + Omega_c^2))  [cm^2/(rad/m)]
//
// with Omega the spatial angular frequency in rad/m, A_v in cm^2 rad/m,
// Omega_c in rad/m and k = 0.25. Valid for wavelengths 1.524 m to 304.8 m.
struct FraPsd {
  double k = 0.25;
  double a_v = 0;      // cm^2 rad/m
  double omega_c = 0;  // rad/m
  // S(Omega) in SI: m^2 / (rad/m).
  double operator()(double omega) const;
  bool operator==(const FraPsd&) const = default;
};
// FRA track classes 1 (worst) to 6 (best). Throws std::out_of_range.
FraPsd fra_class(int track_class);

struct RandomProfileSpec {
  FraPsd psd;
  double wavelength_min = 1.524;  // m
  double wavelength_max = 304.8;  // m
  std::uint64_t seed = 1;
  double amplitude_scale = 1.0;  // multiplies every amplitude
  int components = 2048;         // cosines, evenly spread in Omega
  double x_min = 0, x_max = 0;   // where the profile is tabulated, m
  double grid_step = 0;          // m; 0 = wavelength_min / 20

  bool operator==(const RandomProfileSpec&) const = default;
};

// r(x) = scale * sum_k a_k cos(Omega_k x + phi_k): Omega_k drawn uniformly
// inside the k-th of `components` equal slices of [2 pi/lambda_max,
// 2 pi/lambda_min] (so the profile does not repeat), a_k = sqrt(2 S(Omega_k)
// dOmega) (each cosine carries the PSD's variance of its slice), phi_k
// uniform in [0, 2 pi). Tabulated with exact values and slopes on a grid
// over [x_min, x_max], evaluated between grid points by cubic Hermite
// interpolation; outside the grid by the direct sum.
class RandomProfile : public RailProfile {
 public:
  explicit RandomProfile(const RandomProfileSpec& spec);
  double height(double x) const override;
  double slope(double x) const override;
  // The direct sum (slow), for checks.
  double exact_height(double x) const;
  double exact_slope(double x) const;
  const std::vector<double>& wavenumbers() const { return omega_; }
  const std::vector<double>& amplitudes() const { return amp_; }
  const std::vector<double>& phases() const { return phase_; }

 private:
  std::vector<double> omega_, amp_, phase_;
  double x0_ = 0, h_ = 0;
  std::vector<double> r_, dr_;
};

// A measured profile: rows "x_m,r_m" (an optional header line, '#'
// comments), x strictly increasing, linear interpolation; constant beyond
// the ends (check_covers says whether a run stays inside).
class TableProfile : public RailProfile {
 public:
  TableProfile(std::vector<double> x, std::vector<double> r, std::string source);
  // Throws SceneError naming the file and line of a bad row.
  static TableProfile load_csv(const std::string& path);
  // The same from the file's text (`path` names it in messages).
  static TableProfile parse_csv(const std::string& text, const std::string& path);
  double height(double x) const override;
  double slope(double x) const override;
  // Throws SceneError (naming the file) unless [a, b] lies inside the table.
  void check_covers(double a, double b) const;
  const std::vector<double>& xs() const { return x_; }
  const std::vector<double>& heights() const { return r_; }

 private:
  std::vector<double> x_, r_;
  std::string source_;
};

// A dipped joint as a cosine dip of depth d and length L centred at x_j:
// r = d/2 (1 + cos(2 pi (x - x_j) / L)) for |x - x_j| <= L/2, else 0. r > 0:
// the rail top is lower than the track around it.
class DippedJoint : public RailProfile {
 public:
  DippedJoint(double position, double length, double depth);
  double height(double x) const override;
  double slope(double x) const override;

 private:
  double xj_, len_, depth_;
};

// r = A sin(2 pi x / lambda + phase).
class SineProfile : public RailProfile {
 public:
  SineProfile(double amplitude, double wavelength, double phase);
  double height(double x) const override;
  double slope(double x) const override;

 private:
  double amp_, k_, phase_;
};

// The sum of several sources (e.g. a random profile and a joint).
class SumProfile : public RailProfile {
 public:
  void add(std::unique_ptr<RailProfile> p) { parts_.push_back(std::move(p)); }
  double height(double x) const override;
  double slope(double x) const override;

 private:
  std::vector<std::unique_ptr<RailProfile>> parts_;
};

// A profile file's text: a regular file of bounded size (SceneError naming
// it otherwise).
std::string read_profile_file(const std::string& path);

// What a scene's [irregularity] table asks for; make_profile builds it once
// the track is sized.
struct IrregularitySpec {
  std::string model = "none";            // none | random | csv | dipped_joint | sine
  RandomProfileSpec random;              // random (x_min, x_max, grid_step set by make_profile)
  std::string csv_path;                  // csv, resolved against the scene file's folder
  std::vector<double> table_x, table_r;  // csv: its rows, read when the scene is read
  double position = 0, length = 0, depth = 0;       // dipped_joint, m
  double amplitude = 0, wavelength = 0, phase = 0;  // sine: m, m, rad

  bool operator==(const IrregularitySpec&) const = default;
};

// The profile over [x_min, x_max] (m, the scene's frame); nullptr for
// model = "none". A csv profile must cover that range (SceneError otherwise).
std::unique_ptr<RailProfile> make_profile(const IrregularitySpec& spec, double x_min, double x_max);

}  // namespace railcosim
