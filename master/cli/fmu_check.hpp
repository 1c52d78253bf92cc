// `master fmu check FILE.fmu`, the FMU counterpart of `master conform`: the
// FMU's variables and capabilities, a run of its default experiment, a step
// repeated from a saved state bit for bit, and the couplings it can take
// part in. The check itself (check_fmu) and its printout.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/fmu_reference.hpp"
#include "description.hpp"

namespace CLI {
class App;
}

namespace railcosim::cli {

struct FmuArgs {
  CLI::App* command = nullptr;        // master fmu
  CLI::App* check_command = nullptr;  // master fmu check
  std::string file;
  bool check = false;     // --check: the archive and description read, no code of the FMU run
  std::string reference;  // --reference REF.csv
  double rtol = 1e-5;     // --rtol
};

struct FmuCheckOptions {
  std::string reference;  // a record of its outputs to hold the run against ("": none)
  double rtol = 1e-5;     // of each column's largest |value|
  // Without `reference`: the record the FMU carries, if any (fmu::reference_result).
  bool embedded_reference = true;
};

// Adds `fmu check FILE.fmu` to the master's command line, filling `a`.
void add_fmu_command(CLI::App& app, FmuArgs& a);
// Runs it: the exit status (2 when the FMU is refused).
int do_fmu(const FmuArgs& a);

struct FmuCheckReport {
  std::string file;
  fmu::ModelDescription description;

  // The default experiment (start 0, stop start + 1 and 100 steps where
  // the description gives none), run from start to stop.
  double start = 0, stop = 0, step = 0;
  long steps = 0;
  bool ran = false;
  std::string run_error;  // why the run stopped, when it did
  // Where the FMU ended the simulation itself (fmu::FmuTerminated), before the stop time.
  std::optional<double> ended_at;
  // Every output the host can read (Fmu::readable) at the end of the run, by name.
  std::vector<std::pair<std::string, double>> final_outputs;
  // The run against --reference, where one was given.
  std::optional<ReferenceComparison> reference;

  // The step at the run's middle, taken, undone by restoring the state
  // saved before it, and taken again: every Real/Float64 variable the same
  // bit for bit. Not checked when the FMU cannot save its state.
  enum class RoundTrip { kPass, kFail, kNotOffered };
  RoundTrip round_trip = RoundTrip::kNotOffered;
  std::string round_trip_detail;

  // Each coupling and whether the FMU can take part ("yes ..." or "no: ...").
  std::vector<std::pair<std::string, std::string>> couplings;
  bool explicit_only = true;  // no implicit coupling, no judgement through state save
};

// Checks the FMU at `file`. Throws fmu::FmuError when it is refused
// (archive, description, platform binary); a failure of the run or of the
// round trip is in the report.
FmuCheckReport check_fmu(const std::string& file, const FmuCheckOptions& options = {});

// Prints the report on stdout; 0 when the run, the round trip (where
// offered) and the reference (where given) pass, 1 otherwise.
int print_fmu_check(const FmuCheckReport& r);

}  // namespace railcosim::cli
