// The judgement's parts of summary.json (run_output.hpp: judgement_json):
// what the verdict (verdict/) found, as the run writes it.
#include <optional>
#include <sstream>
#include <string>

#include "run/run_output.hpp"
#include "verdict/reference.hpp"

namespace railcosim::run {

std::string stability_json(const RunRecord& r) {
  std::ostringstream s;
  auto opt = [](const std::optional<double>& v) { return v ? format_double(*v) : "null"; };
  s << "\"stability\": {\"verdict\": " << json_quoted(r.stability)
    << ", \"basis\": " << json_quoted(r.stability_basis) << ", \"rho\": " << opt(r.spectral_radius)
    << ", \"rho_rate_per_s\": " << opt(r.spectral_rate)
    << ", \"map_dimension\": " << (r.map_dimension ? std::to_string(*r.map_dimension) : "null")
    << ", \"map_s\": " << opt(r.map_seconds)
    << ", \"map_method\": " << (r.map_method.empty() ? "null" : json_quoted(r.map_method))
    << ", \"map_solver\": " << (r.map_solver.empty() ? "null" : json_quoted(r.map_solver))
    << ", \"map_products\": " << (r.map_products ? std::to_string(*r.map_products) : "null");
  if (!r.spectral_note.empty()) s << ", \"rho_not_judged\": " << json_quoted(r.spectral_note);
  if (r.matrix_free_steps)
    s << ", \"rho_matrix_free\": " << opt(r.matrix_free_rho)
      << ", \"rho_matrix_free_rate_per_s\": " << opt(r.matrix_free_rate)
      << ", \"matrix_free_steps\": " << *r.matrix_free_steps;
  s << ", \"growth\": " << opt(r.error_growth) << ", \"rate_per_s\": " << opt(r.error_growth_rate)
    << ", \"probe_s\": " << opt(r.probe_time) << ", \"defect_growth\": " << opt(r.defect_growth)
    << ", \"defect_rate_per_s\": " << opt(r.defect_rate)
    << ", \"defect_grows\": " << (r.defect_grows ? "true" : "false") << "}";
  return s.str();
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
    << (cosim ? std::to_string(r.reference_order.value_or(verdict::kReferenceOrder)) : "null")
    << ", \"note\": " << json_quoted(r.reference_note)
    << ", \"folder\": " << (r.reference_folder.empty() ? "null" : json_quoted(r.reference_folder))
    << "},\n";
  return s.str();
}

}  // namespace railcosim::run
