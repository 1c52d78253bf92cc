// Names of the co-simulation cases: where the model is cut, what each side
// receives, in which order the participants step, and when a force output is
// read.
//
// A case is `monolithic` or CUTS-SCHEME, where CUTS is one or more
// CUT-TYPE joined by '+' in load order (CUT: wr, rs, ss; TYPE: xx, xt) and
// SCHEME is jacobi or gauss-seidel: `rs-xx-jacobi`, `wr-xt+ss-xx-gauss-seidel`.
// k cuts make k + 1 participants (see model.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace railcosim {

struct Scene;

enum class Coupling { kXX, kXT };               // "xx", "xt"
enum class Scheme { kJacobi, kGaussSeidel };    // "jacobi", "gauss-seidel"
enum class Feedthrough { kLagged, kResolved };  // see docs/model.md

std::string to_string(Coupling c);
std::string to_string(Scheme s);
std::string to_string(Feedthrough f);

std::optional<Coupling> parse_coupling(const std::string& s);
std::optional<Scheme> parse_scheme(const std::string& s);
std::optional<Feedthrough> parse_feedthrough(const std::string& s);

// One cut of a case: an elastic layer (index into cut_kinds()) and what its
// lower side receives.
struct CutChoice {
  int cut = 0;
  Coupling coupling = Coupling::kXX;
  bool operator==(const CutChoice&) const = default;
};

// A run: the monolithic reference, or one co-simulation case.
struct CaseSpec {
  bool monolithic = true;
  std::vector<CutChoice> cuts;  // in load order (top to bottom)
  Scheme scheme = Scheme::kJacobi;

  std::string name() const;           // "monolithic", "wr-xt-jacobi", "wr-xx+ss-xt-jacobi"
  std::string split_name() const;     // "wr", "wr+ss"
  std::string coupling_name() const;  // "xx", "xx+xt"
  // True if some participant sends a force it computes from a received
  // displacement: only then do lagged and resolved feedthrough differ.
  bool has_force_feedthrough() const;
};

// Parses a case name; throws std::invalid_argument listing the valid forms.
CaseSpec parse_case(const std::string& name);

// The cases a scene can run, monolithic first (when the scene has one): every
// cut its components allow, alone, with both coupling types and schemes; and
// for a scene with a soil, the three-participant cases wr + ss.
std::vector<std::string> case_names(const Scene& scene);
// The paper's cases (the scene with a fixed soil), monolithic first.
std::vector<std::string> paper_case_names();

// Checks that a scene can run a case (an ss cut needs a soil; an external soil
// needs an ss cut and has no monolithic run); throws std::invalid_argument.
void check_case_for_scene(const CaseSpec& spec, const Scene& scene);

}  // namespace railcosim
