#include "cosim_case.hpp"

#include <stdexcept>

#include "model.hpp"
#include "scene.hpp"

namespace railcosim {

std::string to_string(Coupling c) {
  return c == Coupling::kXX ? "xx" : "xt";
}
std::string to_string(Scheme s) {
  return s == Scheme::kJacobi ? "jacobi" : "gauss-seidel";
}
std::string to_string(Feedthrough f) {
  return f == Feedthrough::kLagged ? "lagged" : "resolved";
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
std::optional<Feedthrough> parse_feedthrough(const std::string& s) {
  if (s == "lagged") return Feedthrough::kLagged;
  if (s == "resolved") return Feedthrough::kResolved;
  return std::nullopt;
}

namespace {

const char* cut_name(const CutChoice& c) {
  return cut_kinds()[static_cast<std::size_t>(c.cut)].name;
}

// Joins one text per cut with '+'.
template <typename F>
std::string join_cuts(const std::vector<CutChoice>& cuts, F text) {
  std::string s;
  for (const CutChoice& c : cuts) {
    if (!s.empty()) s += '+';
    s += text(c);
  }
  return s;
}

}  // namespace

std::string CaseSpec::split_name() const {
  return join_cuts(cuts, [](const CutChoice& c) { return std::string(cut_name(c)); });
}

std::string CaseSpec::coupling_name() const {
  return join_cuts(cuts, [](const CutChoice& c) { return to_string(c.coupling); });
}

std::string CaseSpec::name() const {
  if (monolithic) return "monolithic";
  std::string s = join_cuts(cuts, [](const CutChoice& c) {
    std::string t = cut_name(c);
    t += '-';
    t += to_string(c.coupling);
    return t;
  });
  s += '-';
  s += to_string(scheme);
  return s;
}

bool CaseSpec::has_force_feedthrough() const {
  for (const CutChoice& c : cuts)
    if (c.coupling == Coupling::kXT) return true;
  return false;
}

namespace {

[[noreturn]] void bad_case(const std::string& name, const std::string& why) {
  throw std::invalid_argument("unknown case '" + name + "': " + why +
                              " (a case is 'monolithic' or CUT-TYPE[+CUT-TYPE...]-SCHEME with "
                              "CUT wr, rs or ss, TYPE xx or xt, SCHEME jacobi or gauss-seidel, "
                              "e.g. rs-xx-jacobi or wr-xt+ss-xx-gauss-seidel)");
}

}  // namespace

CaseSpec parse_case(const std::string& name) {
  CaseSpec c;
  if (name == "monolithic") return c;
  c.monolithic = false;
  std::string rest;
  for (Scheme s : {Scheme::kGaussSeidel, Scheme::kJacobi}) {
    std::string suffix(1, '-');
    suffix += to_string(s);
    if (name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      c.scheme = s;
      rest = name.substr(0, name.size() - suffix.size());
      break;
    }
  }
  if (rest.empty()) bad_case(name, "it does not end in a scheme");
  std::size_t pos = 0;
  while (pos <= rest.size()) {
    const std::size_t plus = rest.find('+', pos);
    const std::string part = rest.substr(pos, plus == std::string::npos ? plus : plus - pos);
    const std::size_t dash = part.find('-');
    const int cut = dash == std::string::npos ? -1 : find_cut(part.substr(0, dash));
    const auto coupling =
        dash == std::string::npos ? std::nullopt : parse_coupling(part.substr(dash + 1));
    if (cut < 0 || !coupling) bad_case(name, "'" + part + "' is not CUT-TYPE");
    if (!c.cuts.empty() && cut <= c.cuts.back().cut)
      bad_case(name, "the cuts must be distinct and in load order (" + cut_names() + ")");
    c.cuts.push_back({cut, *coupling});
    if (plus == std::string::npos) break;
    pos = plus + 1;
  }
  return c;
}

std::vector<std::string> paper_case_names() {
  std::vector<std::string> names{"monolithic"};
  for (const char* cut : {"wr", "rs"})
    for (const char* type : {"xx", "xt"})
      for (const char* scheme : {"jacobi", "gauss-seidel"})
        names.push_back(std::string(cut) + "-" + type + "-" + scheme);
  return names;
}

std::vector<std::string> case_names(const Scene& scene) {
  std::vector<std::string> names;
  if (!scene.outside_model()) names.push_back("monolithic");
  std::vector<std::string> cuts;
  if (scene.outside_vehicle() && !scene.outside_soil())
    cuts = {"wr"};
  else if (!scene.outside_soil())
    cuts = {"wr", "rs"};
  if (scene.has_soil()) cuts.push_back("ss");
  const char* types[] = {"xx", "xt"};
  const char* schemes[] = {"jacobi", "gauss-seidel"};
  for (const auto& cut : cuts)
    for (const char* type : types)
      for (const char* scheme : schemes) names.push_back(cut + "-" + type + "-" + scheme);
  if (scene.builtin_soil())
    for (const char* t1 : types)
      for (const char* t2 : types)
        for (const char* scheme : schemes)
          names.push_back(std::string("wr-") + t1 + "+ss-" + t2 + "-" + scheme);
  return names;
}

void check_case_for_scene(const CaseSpec& spec, const Scene& scene) {
  if (spec.monolithic) {
    if (scene.outside_soil())
      throw std::invalid_argument("the scene's soil is a participant of its own (soil.model = \"" +
                                  scene.soil_model +
                                  "\"): there is no monolithic reference, only cases that cut "
                                  "through the ballast (ss)");
    if (scene.outside_vehicle())
      throw std::invalid_argument(
          "the scene's vehicle is an FMU ([vehicle.fmu]): there is no monolithic reference, only "
          "cases that cut at the wheel/rail contact (wr)");
    return;
  }
  partition(scene, spec);  // throws if a cut needs a component the scene lacks
}

}  // namespace railcosim
