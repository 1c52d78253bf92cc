#include "verdict/reference.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "verdict/evaluation.hpp"
#include "verdict/stability.hpp"

namespace railcosim::verdict {

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

void assess_against_reference(RunRecord& run, const Scene& scene, double H, double reference_step,
                              const ReferenceMaker& maker, CosimReferences* shared) {
  // The map and the probe would build the scene's own participants, not
  // those behind a given address: the defect along the run is its own.
  judge_without_model(run, H);
  run.reference_kind = "none";
  if (run.status != "ok" && run.status != "not_converged") {
    run.reference_note = "the run did not reach its end";
    return;
  }
  const long k = reference_step > 0 ? std::max(1L, std::lround(H / reference_step)) : 2L;
  const double H_ref = H / static_cast<double>(k);
  auto made_here = [&] { return maker.make(H_ref); };
  CosimReferences::Made own;
  const CosimReferences::Made& m =
      shared ? shared->get(maker.key(H_ref), made_here) : (own = made_here());
  const RunRecord &fine = m.fine, &coarse = m.coarse;
  if (!m.why_not.empty()) {
    run.reference_note = m.why_not;
    judge_unmeasured(run, "no co-simulation reference: " + m.why_not);
    return;
  }
  run.reference_kind = "co-simulation";
  run.reference_folder = m.folder;
  run.reference_macro_step = H_ref;
  run.reference_coupling = fine.method + "-" + fine.inputs + "-" + fine.accelerator.value_or("");
  run.reference_note = m.note;
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

}  // namespace railcosim::verdict
