#include "irregularity.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "scene_checks.hpp"
#include "scene_error.hpp"

namespace railcosim {

double FraPsd::operator()(double omega) const {
  const double w2 = omega * omega, c2 = omega_c * omega_c;
  constexpr double cm2_to_m2 = 1e-4;
  return cm2_to_m2 * k * a_v * c2 / (w2 * (w2 + c2));
}

FraPsd fra_class(int track_class) {
  // A_v (cm^2 rad/m) for classes 1..6; Omega_c = 0.8245 rad/m for all.
  static constexpr double a_v[6] = {1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339};
  if (track_class < 1 || track_class > 6)
    throw std::out_of_range("FRA track class must be 1 to 6 (got " + std::to_string(track_class) +
                            ")");
  return FraPsd{0.25, a_v[track_class - 1], 0.8245};
}

// ---------------------------------------------------------------- random

RandomProfile::RandomProfile(const RandomProfileSpec& s) {
  if (!(s.wavelength_min > 0 && s.wavelength_max > s.wavelength_min))
    throw std::invalid_argument("random profile: need 0 < wavelength_min < wavelength_max");
  if (s.components < 1) throw std::invalid_argument("random profile: components must be >= 1");
  constexpr double two_pi = 2.0 * std::numbers::pi;
  const double lo = two_pi / s.wavelength_max, hi = two_pi / s.wavelength_min;
  const double d_omega = (hi - lo) / s.components;
  SplitMix64 rng(s.seed);
  for (int k = 0; k < s.components; ++k) {
    const double omega = lo + (k + rng.uniform()) * d_omega;
    omega_.push_back(omega);
    amp_.push_back(s.amplitude_scale * std::sqrt(2.0 * s.psd(omega) * d_omega));
    phase_.push_back(two_pi * rng.uniform());
  }
  if (s.x_max > s.x_min) {
    h_ = s.grid_step > 0 ? s.grid_step : s.wavelength_min / 20.0;
    x0_ = s.x_min;
    const auto n = static_cast<std::size_t>(std::ceil((s.x_max - s.x_min) / h_)) + 1;
    r_.assign(n, 0.0);
    dr_.assign(n, 0.0);
    // Each cosine along the grid by complex rotation, z_{j+1} = z_j e^{i Omega h}
    // (a few multiplications instead of a cos and a sin), restarted from the
    // exact value every kRestart points so that round-off cannot build up.
    constexpr std::size_t kRestart = 256;
    for (std::size_t k = 0; k < omega_.size(); ++k) {
      const double c = std::cos(omega_[k] * h_), sn = std::sin(omega_[k] * h_);
      const double a = amp_[k], aw = amp_[k] * omega_[k];
      double re = 0, im = 0;
      for (std::size_t j = 0; j < n; ++j) {
        if (j % kRestart == 0) {
          const double arg = omega_[k] * (x0_ + static_cast<double>(j) * h_) + phase_[k];
          re = std::cos(arg);
          im = std::sin(arg);
        } else {
          const double re1 = re * c - im * sn;
          im = re * sn + im * c;
          re = re1;
        }
        r_[j] += a * re;
        dr_[j] -= aw * im;
      }
    }
  }
}

double RandomProfile::exact_height(double x) const {
  double r = 0;
  for (std::size_t k = 0; k < omega_.size(); ++k)
    r += amp_[k] * std::cos(omega_[k] * x + phase_[k]);
  return r;
}

double RandomProfile::exact_slope(double x) const {
  double d = 0;
  for (std::size_t k = 0; k < omega_.size(); ++k)
    d -= amp_[k] * omega_[k] * std::sin(omega_[k] * x + phase_[k]);
  return d;
}

namespace {
// Cubic Hermite on [x_j, x_j + h] from values and slopes at both ends; t in
// [0, 1]. Returns {value, derivative}.
std::pair<double, double> hermite(double r0, double d0, double r1, double d1, double h, double t) {
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2,
               h11 = t3 - t2;
  const double g00 = 6 * t2 - 6 * t, g10 = 3 * t2 - 4 * t + 1, g01 = -g00, g11 = 3 * t2 - 2 * t;
  return {h00 * r0 + h10 * h * d0 + h01 * r1 + h11 * h * d1,
          (g00 * r0 + g01 * r1) / h + g10 * d0 + g11 * d1};
}
}  // namespace

double RandomProfile::height(double x) const {
  const double u = (x - x0_) / h_;
  if (r_.size() < 2 || !(u >= 0) || u >= static_cast<double>(r_.size() - 1)) return exact_height(x);
  const auto j = static_cast<std::size_t>(u);
  return hermite(r_[j], dr_[j], r_[j + 1], dr_[j + 1], h_, u - static_cast<double>(j)).first;
}

double RandomProfile::slope(double x) const {
  const double u = (x - x0_) / h_;
  if (r_.size() < 2 || !(u >= 0) || u >= static_cast<double>(r_.size() - 1)) return exact_slope(x);
  const auto j = static_cast<std::size_t>(u);
  return hermite(r_[j], dr_[j], r_[j + 1], dr_[j + 1], h_, u - static_cast<double>(j)).second;
}

// ---------------------------------------------------------------- table

TableProfile::TableProfile(std::vector<double> x, std::vector<double> r, std::string source)
    : x_(std::move(x)), r_(std::move(r)), source_(std::move(source)) {
  if (x_.size() != r_.size() || x_.size() < 2)
    throw SceneError(source_ + ": a measured profile needs at least two rows x_m,r_m");
}

std::string read_profile_file(const std::string& path) {
  // A profile is a regular file of bounded size: a device or a pipe (say
  // /dev/zero) would be read without end.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    throw SceneError(path + ": cannot open the profile file (" +
                     (ec ? ec.message() : std::string("no such file")) + ")");
  if (!std::filesystem::is_regular_file(status))
    throw SceneError(path + ": not a regular file (a profile is a CSV file of 'x_m,r_m' rows)");
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > static_cast<std::uintmax_t>(kMaxProfileFileBytes))
    throw SceneError(path + ": " + std::to_string(bytes) + " bytes, more than the " +
                     std::to_string(kMaxProfileFileBytes) + " a profile file may have");
  std::ifstream file(path);
  if (!file) throw SceneError(path + ": cannot open the profile file");
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

TableProfile TableProfile::load_csv(const std::string& path) {
  return parse_csv(read_profile_file(path), path);
}

TableProfile TableProfile::parse_csv(const std::string& text, const std::string& path) {
  if (text.size() > static_cast<std::size_t>(kMaxProfileFileBytes))
    throw SceneError(path + ": " + std::to_string(text.size()) + " bytes, more than the " +
                     std::to_string(kMaxProfileFileBytes) + " a profile file may have");
  std::istringstream in(text);
  std::vector<double> xs, rs;
  std::string line;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    // The messages name the line and what was expected, never its text: a
    // scene may name any readable file (say another user's secrets) as its
    // profile, and the message may travel further than the file.
    const auto where = [&] { return path + ":" + std::to_string(lineno) + ": "; };
    const auto comma = line.find(',');
    if (comma == std::string::npos)
      throw SceneError(where() + "expected 'x_m,r_m', two numbers and a comma; the line (" +
                       std::to_string(line.size()) + " characters, not shown) has no comma");
    const std::string a = line.substr(0, comma), b = line.substr(comma + 1);
    double x = 0, r = 0;
    std::size_t ia = 0, ib = 0;
    try {
      x = std::stod(a, &ia);
      r = std::stod(b, &ib);
    } catch (const std::exception&) {
      if (xs.empty() && lineno == 1) continue;  // a header line
      throw SceneError(where() + "not two numbers 'x_m,r_m' (the line is not shown)");
    }
    if (a.find_first_not_of(" \t", ia) != std::string::npos ||
        b.find_first_not_of(" \t", ib) != std::string::npos || !std::isfinite(x) ||
        !std::isfinite(r))
      throw SceneError(where() + "not two finite numbers 'x_m,r_m' (the line is not shown)");
    if (!xs.empty() && !(x > xs.back()))
      throw SceneError(where() + "x must increase strictly (x = " + a + " after " +
                       std::to_string(xs.back()) + ")");
    xs.push_back(x);
    rs.push_back(r);
  }
  return TableProfile(std::move(xs), std::move(rs), path);
}

double TableProfile::height(double x) const {
  if (x <= x_.front()) return r_.front();
  if (x >= x_.back()) return r_.back();
  const auto j =
      static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
  const double t = (x - x_[j]) / (x_[j + 1] - x_[j]);
  return r_[j] + t * (r_[j + 1] - r_[j]);
}

double TableProfile::slope(double x) const {
  if (x < x_.front() || x >= x_.back()) return 0.0;
  const auto j =
      static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
  return (r_[j + 1] - r_[j]) / (x_[j + 1] - x_[j]);
}

void TableProfile::check_covers(double a, double b) const {
  if (a < x_.front() || b > x_.back()) {
    std::ostringstream s;
    s << source_ << ": the profile covers x in [" << x_.front() << ", " << x_.back()
      << "] m, but the wheels run over [" << a << ", " << b << "] m";
    throw SceneError(s.str());
  }
}

// ---------------------------------------------------------------- joint, sine, sum

DippedJoint::DippedJoint(double position, double length, double depth)
    : xj_(position), len_(length), depth_(depth) {
  if (!(length > 0)) throw std::invalid_argument("dipped joint: length must be positive");
}

double DippedJoint::height(double x) const {
  const double s = x - xj_;
  if (std::abs(s) > 0.5 * len_) return 0.0;
  return 0.5 * depth_ * (1.0 + std::cos(2.0 * std::numbers::pi * s / len_));
}

double DippedJoint::slope(double x) const {
  const double s = x - xj_;
  if (std::abs(s) > 0.5 * len_) return 0.0;
  const double k = 2.0 * std::numbers::pi / len_;
  return -0.5 * depth_ * k * std::sin(k * s);
}

SineProfile::SineProfile(double amplitude, double wavelength, double phase)
    : amp_(amplitude), k_(2.0 * std::numbers::pi / wavelength), phase_(phase) {}

double SineProfile::height(double x) const {
  return amp_ * std::sin(k_ * x + phase_);
}
double SineProfile::slope(double x) const {
  return amp_ * k_ * std::cos(k_ * x + phase_);
}

double SumProfile::height(double x) const {
  double r = 0;
  for (const auto& p : parts_) r += p->height(x);
  return r;
}

double SumProfile::slope(double x) const {
  double d = 0;
  for (const auto& p : parts_) d += p->slope(x);
  return d;
}

std::unique_ptr<RailProfile> make_profile(const IrregularitySpec& spec, double x_min,
                                          double x_max) {
  if (spec.model == "random") {
    RandomProfileSpec r = spec.random;
    r.x_min = x_min;
    r.x_max = x_max;
    return std::make_unique<RandomProfile>(r);
  }
  if (spec.model == "csv") {
    auto t = spec.table_x.empty()
                 ? std::make_unique<TableProfile>(TableProfile::load_csv(spec.csv_path))
                 : std::make_unique<TableProfile>(spec.table_x, spec.table_r, spec.csv_path);
    t->check_covers(x_min, x_max);
    return t;
  }
  if (spec.model == "dipped_joint")
    return std::make_unique<DippedJoint>(spec.position, spec.length, spec.depth);
  if (spec.model == "sine")
    return std::make_unique<SineProfile>(spec.amplitude, spec.wavelength, spec.phase);
  return nullptr;
}

}  // namespace railcosim
