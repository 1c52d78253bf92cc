#include "run/step_loop.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <string>

#include "engine/convergence.hpp"
#include "log.hpp"
#include "newmark.hpp"

namespace railcosim::run {

void check_stop(const RunOptions& o, long n) {
  if (o.stop && o.stop->load() != 0) {
    std::ostringstream s;
    s << "interrupted by signal " << o.stop->load() << " at macro step " << n
      << " (t = " << static_cast<double>(n) * o.macro_step << " s)";
    throw std::runtime_error(s.str());
  }
}

namespace {

// Marks the run diverged (or another status: stopped) at macro step n + 1
// for `why`.
void diverged(RunRecord& r, const RunOptions& o, long n, const std::string& why,
              const std::string& status = "diverged") {
  std::ostringstream s;
  s << (status == "diverged" ? "diverged" : "stopped") << " at macro step " << n + 1
    << " (t = " << static_cast<double>(n + 1) * o.macro_step << " s): " << why;
  r.status = status;
  r.message = s.str();
  logger("master")->warn("{}: {}", r.case_name, r.message);
}

// A participant's integrator gave up on macro step n (its word: a node's
// STEP_FAILED, or the master's own integrator): the run diverged if what the
// participants reported until then shows it (a value not finite, or a
// displacement over kGrowthEvidence x the largest static one); otherwise it
// failed there, and whether it diverged is not judged.
constexpr double kGrowthEvidence = 2.0;
void gave_up(RunRecord& r, const RunOptions& o, long n, const std::string& what,
             const std::vector<StepResult>& last, double static_max) {
  bool finite = true;
  double umax = 0;
  for (const StepResult& x : last) {
    finite = finite && x.finite;
    umax = std::max(umax, x.max_abs_displacement);
  }
  if (!finite || umax > kGrowthEvidence * static_max) return diverged(r, o, n, what);
  std::ostringstream s;
  s << what << "; not judged diverged: the displacements reported until then show no growth "
    << "(largest |u| " << umax << " m, " << umax / static_max
    << " x the largest static displacement; a divergence needs a value that is not finite or over "
    << kGrowthEvidence << " x)";
  diverged(r, o, n, s.str(), "failed");
}

// The stepping loop: macro steps 0 .. N - 1, each recorded, until the end
// or a divergence; returns the macro steps done.
}  // namespace

long step_through(RunRecord& r, engine::MacroSteps& steps, const Scene& scene, const RunOptions& o,
                  long N, double bound,
                  const std::function<void(long, const std::vector<StepResult>&)>& record_row,
                  std::vector<StepResult> last) {
  for (long n = 0; n < N; ++n) {
    check_stop(o, n);
    std::vector<StepResult> m;
    try {
      m = steps.advance(n);
    } catch (const StepFailure& e) {
      gave_up(r, o, n, e.what(), last, bound / scene.divergence_factor);
      return n + 1;
    } catch (const engine::IterationBudgetSpent& e) {
      std::ostringstream why;
      why << e.what() << " before it converged to a relative residual of " << o.coupling.convergence
          << ": loosen --convergence ([coupling] convergence) or raise --iteration-budget";
      diverged(r, o, n, why.str(), "not_converged");
      return n;
    }
    record_row(n + 1, m);
    last = m;
    if (o.on_progress) o.on_progress(n + 1, N);
    bool finite = true;
    double umax = 0;
    for (const StepResult& x : m) {
      finite = finite && x.finite;
      umax = std::max(umax, x.max_abs_displacement);
    }
    if (!finite || umax > bound) {
      std::ostringstream s;
      if (!finite)
        s << "a state value is not finite";
      else
        s << "|u| = " << umax << " m exceeds " << scene.divergence_factor
          << " x the largest static displacement (" << bound << " m)";
      diverged(r, o, n, s.str());
      return n + 1;
    }
  }
  return N;
}

}  // namespace railcosim::run
