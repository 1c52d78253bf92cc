#include "run/cosim_reference.hpp"

#include <cmath>
#include <exception>
#include <iomanip>
#include <sstream>
#include <type_traits>

#include "log.hpp"
#include "run/evaluation.hpp"
#include "run/run_output.hpp"
#include "run/stability.hpp"

namespace railcosim::run {

RunRecord every_kth_row(const RunRecord& fine, long k) {
  RunRecord r = fine;
  if (k <= 1) return r;
  const auto step = static_cast<std::size_t>(k);
  auto thin = [step](const auto& all) {
    std::remove_cvref_t<decltype(all)> kept;
    for (std::size_t i = 0; i < all.size(); i += step) kept.push_back(all[i]);
    return kept;
  };
  r.history = thin(fine.history);
  for (auto& entry : r.coupling_history) entry.second = thin(entry.second);
  r.macro_step = fine.macro_step * static_cast<double>(k);
  r.history_rows.reset();
  return r;
}

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
  o.coupling.max_iterations = kReferenceMaxIterations;
  o.coupling.convergence = kReferenceConvergence;
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
  order = inputs == engine::InputMode::kHold ? 1 : kReferenceOrder;
  bool threw = false;
  return reference_run(job, 2 * H_ref, inputs, coarse, threw);
}

// The bounds a run is judged by, and the reference's estimated errors.
std::string too_coarse(const RunRecord& run, const Scene& scene) {
  std::ostringstream s;
  const double history_bound = scene.amplification_threshold;
  if (*run.reference_history_error > kReferenceErrorShare * history_bound)
    s << "the co-simulation reference's own history error (Richardson estimate "
      << *run.reference_history_error << ") is over " << kReferenceErrorShare
      << " x cosim.amplification_threshold = " << history_bound;
  if (*run.reference_rel_l2_error > kReferenceErrorShare * kMaxDeflectionError)
    s << (s.str().empty() ? "" : "; ") << "the co-simulation reference's own deflection error "
      << "(Richardson estimate " << *run.reference_rel_l2_error << ") is over "
      << kReferenceErrorShare << " x " << kMaxDeflectionError;
  if (!s.str().empty()) s << ": give a finer --reference-step";
  return s.str();
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

const CosimReferences::Made& CosimReferences::get(const std::string& key,
                                                  const std::function<Made()>& make) {
  Entry* e = nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto& slot = entries_[key];
    if (!slot) slot = std::make_unique<Entry>();
    e = slot.get();
  }
  std::call_once(e->once, [e, &make] { e->made = make(); });
  return e->made;
}

void assess_against_cosim(RunRecord& run, const Scene& scene, const CaseSpec& spec,
                          const RunOptions& options, const remote::ParticipantFactory& make,
                          const std::string& transport, double reference_step,
                          CosimReferences* shared) {
  // The map and the probe would build the scene's own participants, not
  // those behind a given address: the defect along the run is its own.
  assess_growth(run, scene, spec, options, false);
  run.reference_kind = "none";
  if (run.status != "ok" && run.status != "not_converged") {
    run.reference_note = "the run did not reach its end";
    return;
  }
  const double H = options.macro_step;
  const long k = reference_step > 0 ? std::max(1L, std::lround(H / reference_step)) : 2L;
  const double H_ref = H / static_cast<double>(k);
  CaseSpec jacobi = spec;  // the reference of every schedule of the cut set
  jacobi.scheme = Scheme::kJacobi;
  auto made_here = [&] {
    CosimReferences::Made m;
    m.why_not = reference_runs({scene, jacobi, options, make, transport}, H_ref, m.fine, m.coarse,
                               m.note, m.order);
    if (m.why_not.empty() && shared && !shared->root().empty())
      m.folder = write_reference(shared->root(), jacobi, H_ref, m.fine);
    return m;
  };
  std::ostringstream key;
  key << std::setprecision(17) << scene.source << "|" << jacobi.name() << "|" << H_ref << "|"
      << options.tolerance << "|" << transport << "|" << static_cast<int>(options.data_plane);
  CosimReferences::Made own;
  const CosimReferences::Made& m = shared ? shared->get(key.str(), made_here) : (own = made_here());
  const RunRecord &fine = m.fine, &coarse = m.coarse;
  const std::string &note = m.note, &why = m.why_not;
  if (!why.empty()) {
    run.reference_note = why;
    judge_unmeasured(run, "no co-simulation reference: " + why);
    return;
  }
  run.reference_kind = "co-simulation";
  run.reference_folder = m.folder;
  run.reference_macro_step = H_ref;
  run.reference_coupling = fine.method + "-" + fine.inputs + "-" + fine.accelerator.value_or("");
  run.reference_note = note;
  // Richardson: the finer run's error is about the difference over 2^p - 1.
  run.reference_order = m.order;
  const double richardson = std::pow(2.0, m.order) - 1;
  const RunRecord fine_at_coarse = every_kth_row(fine, 2);
  run.reference_history_error = coupling_history_error(coarse, fine_at_coarse) / richardson;
  run.reference_rel_l2_error =
      deflection_error(coarse.deflection, fine.deflection).rel_l2 / richardson;
  if (const std::string coarse_words = too_coarse(run, scene); !coarse_words.empty()) {
    judge_unmeasured(run, coarse_words);
    return;
  }
  judge(run, every_kth_row(fine, k), scene);
  if (run.status == "inaccurate" || run.status == "ok") {
    std::ostringstream s;
    s << (run.message.empty() ? "" : "; ") << "judged against the co-simulation reference ("
      << run.reference_coupling << ", H = " << H_ref << " s)";
    run.message += s.str();
  }
}

std::string judgement_json(const RunRecord& r) {
  std::ostringstream s;
  if (!r.stability.empty()) s << "  " << stability_json(r) << ",\n";
  if (r.reference_kind.empty()) return s.str();
  auto opt = [](const std::optional<double>& v) { return v ? format_double(*v) : "null"; };
  const bool cosim = r.reference_kind == "co-simulation";
  s << "  \"reference\": {\"kind\": " << json_quoted(r.reference_kind)
    << ", \"macro_step_s\": " << opt(r.reference_macro_step) << ", \"coupling\": "
    << (r.reference_coupling.empty() ? "null" : json_quoted(r.reference_coupling))
    << ", \"history_error_estimate\": " << opt(r.reference_history_error)
    << ", \"rel_l2_error_estimate\": " << opt(r.reference_rel_l2_error) << ", \"estimate_order\": "
    << (cosim ? std::to_string(r.reference_order.value_or(kReferenceOrder)) : "null")
    << ", \"note\": " << json_quoted(r.reference_note)
    << ", \"folder\": " << (r.reference_folder.empty() ? "null" : json_quoted(r.reference_folder))
    << "},\n";
  return s.str();
}

}  // namespace railcosim::run
