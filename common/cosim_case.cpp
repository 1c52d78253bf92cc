#include "cosim_case.hpp"

#include <stdexcept>

namespace railcosim {

std::string to_string(Split s) {
  return s == Split::kWheelRail ? "wr" : "rs";
}
std::string to_string(Coupling c) {
  return c == Coupling::kXX ? "xx" : "xt";
}
std::string to_string(Scheme s) {
  return s == Scheme::kJacobi ? "jacobi" : "gauss-seidel";
}
std::string to_string(Side s) {
  return s == Side::kS1 ? "s1" : "s2";
}
std::string to_string(Feedthrough f) {
  return f == Feedthrough::kLagged ? "lagged" : "resolved";
}

std::optional<Split> parse_split(const std::string& s) {
  if (s == "wr") return Split::kWheelRail;
  if (s == "rs") return Split::kRailSleepers;
  return std::nullopt;
}
std::optional<Coupling> parse_coupling(const std::string& s) {
  if (s == "xx") return Coupling::kXX;
  if (s == "xt") return Coupling::kXT;
  return std::nullopt;
}
std::optional<Scheme> parse_scheme(const std::string& s) {
  if (s == "jacobi") return Scheme::kJacobi;
  if (s == "gauss-seidel") return Scheme::kGaussSeidel;
  return std::nullopt;
}
std::optional<Side> parse_side(const std::string& s) {
  if (s == "s1") return Side::kS1;
  if (s == "s2") return Side::kS2;
  return std::nullopt;
}
std::optional<Feedthrough> parse_feedthrough(const std::string& s) {
  if (s == "lagged") return Feedthrough::kLagged;
  if (s == "resolved") return Feedthrough::kResolved;
  return std::nullopt;
}

std::string CaseSpec::name() const {
  if (monolithic) return "monolithic";
  return to_string(split) + "-" + to_string(coupling) + "-" + to_string(scheme);
}

const char* const* all_case_names() {
  static const char* const names[] = {
      "monolithic",         "wr-xx-jacobi", "wr-xx-gauss-seidel", "wr-xt-jacobi",
      "wr-xt-gauss-seidel", "rs-xx-jacobi", "rs-xx-gauss-seidel", "rs-xt-jacobi",
      "rs-xt-gauss-seidel", nullptr};
  return names;
}

CaseSpec parse_case(const std::string& name) {
  CaseSpec c;
  if (name == "monolithic") return c;
  // SPLIT-TYPE-SCHEME; the scheme may itself contain a dash.
  const auto d1 = name.find('-');
  const auto d2 = d1 == std::string::npos ? d1 : name.find('-', d1 + 1);
  std::optional<Split> split;
  std::optional<Coupling> coupling;
  std::optional<Scheme> scheme;
  if (d2 != std::string::npos) {
    split = parse_split(name.substr(0, d1));
    coupling = parse_coupling(name.substr(d1 + 1, d2 - d1 - 1));
    scheme = parse_scheme(name.substr(d2 + 1));
  }
  if (!split || !coupling || !scheme) {
    std::string valid;
    for (const char* const* n = all_case_names(); *n; ++n)
      valid += std::string(valid.empty() ? "" : ", ") + *n;
    throw std::invalid_argument("unknown case '" + name + "' (valid: " + valid + ")");
  }
  c.monolithic = false;
  c.split = *split;
  c.coupling = *coupling;
  c.scheme = *scheme;
  return c;
}

}  // namespace railcosim
