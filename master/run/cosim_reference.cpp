#include "run/cosim_reference.hpp"

#include <exception>
#include <iomanip>
#include <sstream>

#include "log.hpp"
#include "run/assess.hpp"
#include "run/run_output.hpp"
#include "verdict/evaluation.hpp"

namespace railcosim::run {

namespace {

// The reference's options at macro step H with these inputs.
RunOptions reference_options(const RunOptions& run, double H, engine::InputMode inputs) {
  RunOptions o;
  o.macro_step = H;
  o.tolerance = run.tolerance;
  // Converged implicit coupling has no lag to resolve (and takes only the
  // lagged feedthrough): a resolved run is judged against the same reference.
  o.feedthrough = Feedthrough::kLagged;
  o.coupling.method = engine::CouplingMethod::kImplicit;
  o.coupling.inputs = inputs;
  o.coupling.max_iterations = verdict::kReferenceMaxIterations;
  o.coupling.convergence = verdict::kReferenceConvergence;
  // Substep waveforms travel relayed over TCP; ramps take the run's plane.
  o.data_plane = engine::waveform_degree(inputs) >= 0 ? remote::DataPlane::kRelay : run.data_plane;
  o.direct = run.direct;
  o.stop = run.stop;
  return o;
}

// What one reference needs: the case, its participants, the run's options.
struct ReferenceJob {
  const Scene& scene;
  const CaseSpec& spec;
  const RunOptions& run;
  const remote::ParticipantFactory& make;
  const std::string& transport;
};

// One reference run at H; "" when it can serve, else why not (`threw`
// when the run did not end: a participant refused or a node failed).
std::string reference_run(const ReferenceJob& job, double H, engine::InputMode inputs,
                          RunRecord& out, bool& threw) {
  const RunOptions o = reference_options(job.run, H, inputs);
  std::ostringstream what;
  what << "the reference run (" << o.coupling.label() << ", H = " << H << " s)";
  threw = false;
  try {
    out = run_cosim(job.scene, job.spec, o, job.make, job.transport);
  } catch (const std::exception& e) {
    threw = true;
    return what.str() + " failed: " + e.what();
  }
  if (out.status != "ok") return what.str() + " ended " + out.status + ": " + out.message;
  return "";
}

// The two reference runs, at H_ref and 2 H_ref: with substep waveforms,
// else linear inputs where a participant takes no waveforms, else held
// inputs where it takes no ramps either (an FMU that does not interpolate
// its inputs). "" or why not; `order` the order of the inputs taken.
std::string reference_runs(const ReferenceJob& job, double H_ref, RunRecord& fine,
                           RunRecord& coarse, std::string& note, int& order) {
  auto log = logger("master");
  log->info("{}: computing the co-simulation reference (implicit, H = {} s and {} s)",
            job.spec.name(), H_ref, 2 * H_ref);
  const std::pair<engine::InputMode, const char*> tries[] = {
      {engine::InputMode::kWaveform3, ""},
      {engine::InputMode::kLinear, "the reference takes linear inputs instead"},
      {engine::InputMode::kHold, "the reference takes held inputs instead (first order)"}};
  engine::InputMode inputs = tries[0].first;
  std::string why;
  for (const auto& [mode, instead] : tries) {
    if (*instead) {
      note += (note.empty() ? "" : "; ") + why + "; " + instead;
      log->info("{}: {}", job.spec.name(), note);
    }
    inputs = mode;
    bool threw = false;
    why = reference_run(job, H_ref, inputs, fine, threw);
    if (!threw) break;  // a participant may take no substep waveforms, no ramps
  }
  if (!why.empty()) return why;
  order = inputs == engine::InputMode::kHold ? 1 : verdict::kReferenceOrder;
  bool threw = false;
  return reference_run(job, 2 * H_ref, inputs, coarse, threw);
}

// Writes the finer reference run as a run folder below ROOT; its folder
// relative to ROOT, or "" (logged) when it cannot be written.
std::string write_reference(const std::filesystem::path& root, const CaseSpec& jacobi, double H_ref,
                            const RunRecord& fine) {
  std::string cuts = jacobi.name();
  cuts = cuts.substr(0, cuts.size() - std::string("-jacobi").size());
  std::ostringstream rel;
  rel << "references/H_" << H_ref << "/" << cuts;
  try {
    RunWriter w(root / std::filesystem::path(rel.str()).parent_path(), cuts);
    w.channels(fine.extra_channels);
    for (const HistoryRow& row : fine.history) w.row(row);
    w.finish(fine);
  } catch (const std::exception& e) {
    logger("master")->error("{}: the co-simulation reference is not written: {}", rel.str(),
                            e.what());
    return "";
  }
  return rel.str();
}

}  // namespace

void assess_against_cosim(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                          const RunOptions& options, const remote::ParticipantFactory& make,
                          const std::string& transport, double reference_step,
                          verdict::CosimReferences* shared) {
  CaseSpec jacobi = spec;  // the reference of every schedule of the cut set
  jacobi.scheme = Scheme::kJacobi;
  verdict::ReferenceMaker maker;
  maker.key = [&](double H_ref) {
    std::ostringstream key;
    key << std::setprecision(17) << scene.source << "|" << jacobi.name() << "|" << H_ref << "|"
        << options.tolerance << "|" << transport << "|" << static_cast<int>(options.data_plane);
    return key.str();
  };
  maker.make = [&](double H_ref) {
    verdict::CosimReferences::Made m;
    m.why_not = reference_runs({scene, jacobi, options, make, transport}, H_ref, m.fine, m.coarse,
                               m.note, m.order);
    if (m.why_not.empty() && shared && !shared->root().empty())
      m.folder = write_reference(shared->root(), jacobi, H_ref, m.fine);
    return m;
  };
  verdict::assess_against_reference(run, scene, options.macro_step, reference_step, maker, shared);
}

}  // namespace railcosim::run
