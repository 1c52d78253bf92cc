#include "cli/fmu_check.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "fmu.hpp"
#include "fmu_error.hpp"

namespace railcosim::cli {
namespace {

using fmu::Fmu;
using fmu::FmuError;
using fmu::Variable;

// A default experiment of more steps than this is refused rather than run.
constexpr long kMaxSteps = 10'000'000;

void plan_experiment(FmuCheckReport& r) {
  const fmu::DefaultExperiment& e = r.description.default_experiment;
  r.start = e.start_time.value_or(0.0);
  r.stop = e.stop_time.value_or(r.start + 1.0);
  if (!(r.stop > r.start))
    throw FmuError(r.file + ": <DefaultExperiment> stopTime is not after startTime");
  r.step = e.step_size.value_or(
      r.description.capabilities.fixed_internal_step.value_or((r.stop - r.start) / 100));
  const double n = std::round((r.stop - r.start) / r.step);
  if (!(r.step > 0) || !(n >= 1) || n > kMaxSteps)
    throw FmuError(r.file + ": the default experiment's step (" + std::to_string(r.step) +
                   " s) does not give 1 to " + std::to_string(kMaxSteps) + " steps");
  r.steps = static_cast<long>(n);
}

std::vector<std::uint32_t> references(const std::vector<const Variable*>& vars) {
  std::vector<std::uint32_t> out;
  for (const Variable* v : vars) out.push_back(v->value_reference);
  return out;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// At step n: save, step, restore, step again; every real variable compared.
void round_trip(FmuCheckReport& r, Fmu& f, double t, const std::vector<std::uint32_t>& all) {
  const std::vector<double> before = f.get_real(all);
  fmu::FmuState saved = f.get_state();
  f.do_step(t, r.step);
  const std::vector<double> first = f.get_real(all);
  f.set_state(saved);
  const std::vector<double> restored = f.get_real(all);
  f.do_step(t, r.step);
  const std::vector<double> again = f.get_real(all);
  char at[64];
  std::snprintf(at, sizeof at, "the step from t = %.9g s", t);
  if (!same_bits(before, restored)) {
    r.round_trip = FmuCheckReport::RoundTrip::kFail;
    r.round_trip_detail =
        std::string("after the restore before ") + at + " the variables differ from those saved";
  } else if (!same_bits(first, again)) {
    r.round_trip = FmuCheckReport::RoundTrip::kFail;
    r.round_trip_detail = std::string(at) + " taken again from the saved state differs";
  } else {
    r.round_trip = FmuCheckReport::RoundTrip::kPass;
    r.round_trip_detail = std::string(at) +
                          " repeated from a saved state: " + std::to_string(all.size()) +
                          " variables equal bit for bit";
  }
}

// The recorded values at point n, where the reference wants them.
void record_point(ReferenceRecorder* rec, Fmu& f, long n) {
  if (rec == nullptr || !rec->wants(n)) return;
  std::vector<std::vector<double>> values;
  for (const Variable* v : rec->variables()) values.push_back(f.get_values(*v));
  rec->record(n, std::move(values));
}

void run_experiment(FmuCheckReport& r, Fmu& f, ReferenceRecorder* rec) {
  std::vector<const Variable*> outputs, reals;
  for (const Variable& v : r.description.variables) {
    if (v.causality == "output" && Fmu::readable(r.description.version, v.type))
      outputs.push_back(&v);
    if (v.is_real()) reals.push_back(&v);
  }
  const bool state = r.description.capabilities.can_get_and_set_state;
  if (!state) r.round_trip_detail = "the FMU cannot save its state";
  try {
    f.instantiate("fmu_check");
    f.setup(r.start, r.stop, r.description.default_experiment.tolerance);
    f.enter_initialization();
    f.exit_initialization();
    const std::vector<std::uint32_t> all = references(reals);
    record_point(rec, f, 0);
    for (long n = 0; n < r.steps; ++n) {
      const double t = r.start + static_cast<double>(n) * r.step;
      try {
        if (state && n == r.steps / 2)
          round_trip(r, f, t, all);
        else
          f.do_step(t, r.step);
      } catch (const fmu::FmuTerminated& e) {  // its values stand at the time it reached
        r.ended_at = e.time;
        const double k = std::round((e.time - r.start) / r.step);
        if (std::abs(r.start + k * r.step - e.time) <= 1e-6 * r.step)
          record_point(rec, f, static_cast<long>(k));
        break;
      }
      record_point(rec, f, n + 1);
    }
    for (const Variable* v : outputs) {
      const std::vector<double> values = f.get_values(*v);
      for (std::size_t i = 0; i < values.size(); ++i)  // an array's as NAME[i]
        r.final_outputs.emplace_back(
            v->dimensions.empty() ? v->name : v->name + "[" + std::to_string(i) + "]", values[i]);
    }
    f.terminate();
    r.ran = true;
  } catch (const FmuError& e) {
    r.run_error = e.what();
    if (state && r.round_trip == FmuCheckReport::RoundTrip::kNotOffered) {
      r.round_trip = FmuCheckReport::RoundTrip::kFail;
      r.round_trip_detail = "not reached: the run stopped";
    }
  }
}

void judge_couplings(FmuCheckReport& r) {
  const fmu::Capabilities& c = r.description.capabilities;
  auto& out = r.couplings;
  out.emplace_back("explicit, held inputs (Jacobi, Gauss-Seidel)", "yes");
  out.emplace_back("explicit, ramped or extrapolated inputs",
                   c.can_interpolate_inputs
                       ? "yes: the FMU interpolates its inputs (FMI 2 input derivatives, degree 1)"
                       : "no: held inputs only (degree 0): the FMU does not interpolate its "
                         "inputs");
  const bool state = r.round_trip == FmuCheckReport::RoundTrip::kPass;
  const std::string why = !c.can_get_and_set_state ? "the FMU cannot save its state"
                          : state                  ? ""
                                                   : "its state round trip failed";
  out.emplace_back("implicit (Aitken, IQN-ILS), steps repeated from a checkpoint",
                   state ? "yes" : "no: " + why);
  out.emplace_back("judged (stability measure, co-simulation reference)",
                   state ? "yes" : "not judged: " + why);
  out.emplace_back("multirate at its own window", "yes (a fixed communication step)");
  out.emplace_back("variable communication steps",
                   c.can_handle_variable_step
                       ? "yes"
                       : "no: canHandleVariableCommunicationStepSize is not true");
  r.explicit_only = !state;
}

void print_reference(const ReferenceComparison& c) {
  std::printf(
      "reference %s: %ld rows, %ld at communication points, %ld between them and %ld after "
      "the stop time (not compared)\n",
      c.file.c_str(), c.rows, c.on_grid, c.between, c.after_stop);
  long compared = 0;
  for (const ReferenceColumn& col : c.columns) {
    if (!col.skipped.empty()) {
      std::printf("  %-24s not compared: %s\n", col.name.c_str(), col.skipped.c_str());
      continue;
    }
    ++compared;
    if (!std::isfinite(col.worst)) {
      std::printf("  %-24s FAIL: %s\n", col.name.c_str(), col.mismatch.c_str());
      continue;
    }
    std::printf(
        "  %-24s %ld points, worst |difference| %.3g at t = %.9g s, tolerance %.3g "
        "(rtol %.3g x max |reference| %.6g): %s\n",
        col.name.c_str(), col.compared, col.worst, col.worst_t, c.rtol * col.scale, c.rtol,
        col.scale, col.pass ? "PASS" : "FAIL");
  }
  std::printf("reference: %s (%ld of %zu columns compared)\n", c.pass() ? "PASS" : "FAIL", compared,
              c.columns.size());
}

}  // namespace

FmuCheckReport check_fmu(const std::string& file, const FmuCheckOptions& options) {
  Fmu f(file);
  FmuCheckReport r;
  r.file = file;
  r.description = f.description();
  plan_experiment(r);
  std::optional<ReferenceRecorder> rec;
  // The given record, else the one the FMU carries (FMI layered standard for reference results).
  std::string reference = options.reference;
  std::string shown = reference;
  if (reference.empty() && options.embedded_reference)
    if (const auto own = fmu::reference_result(f.root())) {
      reference = own->string();
      shown = "extra/org.fmi-standard.fmi-ls-ref/" + own->filename().string() + " (the FMU's own)";
    }
  if (!reference.empty()) {
    ReferenceTable table = read_reference_csv(reference);
    table.file = shown;
    rec.emplace(std::move(table), r.description, r.start, r.step, r.steps);
  }
  run_experiment(r, f, rec ? &*rec : nullptr);
  if (rec && r.ran) r.reference = rec->compare(options.rtol);
  judge_couplings(r);
  return r;
}

int print_fmu_check(const FmuCheckReport& r) {
  const fmu::ModelDescription& d = r.description;
  const fmu::Capabilities& c = d.capabilities;
  std::printf("FMU %s: FMI %s co-simulation, model '%s', identifier %s\n", r.file.c_str(),
              fmu::version_name(d.version), d.model_name.c_str(), d.model_identifier.c_str());
  std::printf("variables (%zu):\n", d.variables.size());
  for (const Variable& v : d.variables) {
    std::printf("  %-24s vr %-6u %-10s %-11s %-8s", v.name.c_str(), v.value_reference,
                v.causality.c_str(), v.variability.c_str(), v.type.c_str());
    if (v.start) std::printf(" start %.17g", *v.start);
    if (!v.unit.empty()) std::printf(" [%s]", v.unit.c_str());
    std::printf("\n");
  }
  std::printf(
      "capabilities: state save %s, variable communication step %s, interpolates "
      "inputs %s, output derivatives up to order %d, directional derivatives %s\n",
      c.can_get_and_set_state ? "yes" : "no", c.can_handle_variable_step ? "yes" : "no",
      c.can_interpolate_inputs ? "yes" : "no", c.max_output_derivative_order,
      c.provides_directional_derivatives ? "yes" : "no");
  std::string ended;
  if (r.ended_at) {
    char at[96];
    std::snprintf(at, sizeof at, " (the FMU ended the simulation at t = %.9g s)", *r.ended_at);
    ended = at;
  }
  std::printf("default experiment: %.9g s to %.9g s, %ld steps of %.9g s: %s%s\n", r.start, r.stop,
              r.steps, r.step, r.ran ? "PASS" : ("FAIL: " + r.run_error).c_str(), ended.c_str());
  for (const auto& [name, value] : r.final_outputs)
    std::printf("  %s = %.17g at t = %.9g s\n", name.c_str(), value, r.ended_at.value_or(r.stop));
  const char* trip = r.round_trip == FmuCheckReport::RoundTrip::kPass   ? "PASS"
                     : r.round_trip == FmuCheckReport::RoundTrip::kFail ? "FAIL"
                                                                        : "SKIP";
  std::printf("state round trip: %s: %s\n", trip, r.round_trip_detail.c_str());
  std::printf("couplings (what its capabilities allow):\n");
  for (const auto& [coupling, verdict] : r.couplings)
    std::printf("  %-62s %s\n", coupling.c_str(), verdict.c_str());
  std::printf("verdict: %s\n",
              r.explicit_only ? "explicit coupling only" : "explicit and implicit coupling");
  if (r.reference) print_reference(*r.reference);
  return r.ran && r.round_trip != FmuCheckReport::RoundTrip::kFail &&
                 (!r.reference || r.reference->pass())
             ? 0
             : 1;
}

}  // namespace railcosim::cli
