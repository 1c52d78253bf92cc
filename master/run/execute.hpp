// One run, whoever asked for it: `master run` and every run of a study go
// through execute(), so that a run is made, judged and written one way.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "cosim_case.hpp"
#include "remote/transport.hpp"
#include "run/cosim_reference.hpp"
#include "run/runner.hpp"
#include "scene.hpp"

namespace railcosim::run {

struct RunJob {
  const Scene* scene = nullptr;
  CaseSpec spec;
  RunOptions options;            // its stop flag is kept; its callbacks are execute()'s
  std::string transport;         // a name of the transport table
  remote::TransportSetup nodes;  // the nodes given, the pool, the secret
  std::filesystem::path out;     // the run writes OUT/FOLDER/
  std::string folder;            // the case name for `master run`
  // The monolithic reference a co-simulation is judged against (not called
  // for the monolithic case, nor for a soil outside the master's models).
  std::function<const RunRecord&()> reference;
  // Where the monolithic reference cannot be built (a participant on a node
  // given by address, an external soil): the co-simulation reference's
  // macro step (verdict/reference.hpp; 0: half the run's).
  double reference_step = 0;
  // Reference runs shared with other runs (a study's); null: made for this one.
  verdict::CosimReferences* cosim_references = nullptr;
  // Called with the run's folder once it exists, before the run starts.
  std::function<void(const std::filesystem::path&)> on_folder;
  // Called after every macro step with the steps done and the total.
  std::function<void(long done, long total)> on_progress;
};

struct RunOutcome {
  RunRecord record;           // finished, or failed with the history it had
  std::filesystem::path dir;  // where it was written ("" if nowhere)
  std::string error;          // why the run failed; "" when it finished
  // Why the run failed: `error`, or the record's message when its status is
  // `failed` (a participant that gave up on a step without a divergence to
  // show for it: no result either); "" for a result.
  const std::string& failure() const {
    return error.empty() && record.status == "failed" ? record.message : error;
  }
};

// Runs the job and writes its folder (history.csv, deflection.csv,
// summary.json). A run that fails leaves a failed summary with the macro
// steps it made; execute() does not throw for it but says why in `error`.
RunOutcome execute(const RunJob& job);

}  // namespace railcosim::run
