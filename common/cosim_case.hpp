// Names of the co-simulation cases: where the model is cut, what each side
// receives, in which order the sides step, and when a force output is read.
#pragma once

#include <optional>
#include <string>

namespace railcosim {

enum class Split { kWheelRail, kRailSleepers };  // "wr", "rs"
enum class Coupling { kXX, kXT };                // "xx", "xt"
enum class Scheme { kJacobi, kGaussSeidel };     // "jacobi", "gauss-seidel"
enum class Side { kS1, kS2 };                    // S1 holds the wheel, S2 the sleepers
enum class Feedthrough { kLagged, kResolved };   // see shared model, "Outputs"

std::string to_string(Split s);
std::string to_string(Coupling c);
std::string to_string(Scheme s);
std::string to_string(Side s);
std::string to_string(Feedthrough f);

std::optional<Split> parse_split(const std::string& s);
std::optional<Coupling> parse_coupling(const std::string& s);
std::optional<Scheme> parse_scheme(const std::string& s);
std::optional<Side> parse_side(const std::string& s);
std::optional<Feedthrough> parse_feedthrough(const std::string& s);

// A run: the monolithic reference, or one co-simulation case.
struct CaseSpec {
  bool monolithic = true;
  Split split = Split::kWheelRail;
  Coupling coupling = Coupling::kXX;
  Scheme scheme = Scheme::kJacobi;

  std::string name() const;  // "monolithic" or "wr-xt-jacobi", ...
};

// Parses a case name; throws std::invalid_argument listing the valid names.
CaseSpec parse_case(const std::string& name);
// Every case name, monolithic first.
const char* const* all_case_names();

}  // namespace railcosim
