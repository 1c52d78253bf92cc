// A schedule for inputs that change over the macro step (interpolated or
// extrapolated) and for implicit coupling, where each macro step is repeated
// from a checkpoint until the exchanged values converge. With explicit
// coupling and held inputs the plain JacobiSchedule / GaussSeidelSchedule
// are used instead (schedule.hpp), so the paper's cases are unchanged.
//
// Implicit coupling solves the window's fixed point x = G(x):
//   Jacobi (parallel-implicit): x holds every exchanged value at t_n + H;
//     each iteration every participant steps with inputs from x.
//   Gauss–Seidel (serial-implicit): x holds the values that flow against the
//     load order (from a later participant to an earlier one); each
//     iteration the participants step in order, each with the fresh outputs
//     of those before it and with x for those after it.
// The accelerator proposes the next x from x and G(x).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "coupling_options.hpp"
#include "run_record.hpp"
#include "schedule.hpp"

namespace railcosim {

// What an implicit run's iterations did.
struct ConvergenceLog {
  std::vector<std::string> quantities;    // e.g. "track_to_vehicle_displacement"
  using Row = RunRecord::ConvergenceRow;  // step, iteration, residual per quantity
  std::vector<Row> rows;
  std::vector<int> iterations;  // per macro step
  long not_converged = 0;       // macro steps that hit the iteration limit
  long first_not_converged = -1;
};

class WindowSchedule final : public Schedule {
 public:
  // `roles` name the participants in the convergence log.
  WindowSchedule(std::vector<Participant*> participants, Routing routing,
                 std::vector<std::string> roles, Scheme scheme, const CouplingOptions& options,
                 double macro_step);
  std::vector<StepResult> advance(long n) override;
  const ConvergenceLog& log() const { return log_; }

 private:
  struct Link {  // one routed value: receiver p's interface j from sender q's interface i
    std::size_t p, j, q, i;
  };
  std::vector<StepResult> explicit_pass(long n);
  std::vector<StepResult> implicit_window(long n);
  // Runs every participant over step n once; `end` gives the values at
  // t_n + H for the links in `iterated` (implicit), or is empty (explicit).
  std::vector<StepResult> pass(long n, const std::vector<InterfaceData>& end);
  void set_inputs(std::size_t p, long n, const std::vector<const InterfaceData*>& end);
  bool iterated(const Link& l) const;

  std::vector<std::string> roles_;
  Scheme scheme_;
  CouplingOptions o_;
  double macro_step_;
  std::vector<Link> links_;                      // every routed value
  std::vector<std::size_t> iterated_;            // indices into links_ of x's values
  std::vector<int> position_;                    // per link: its index in x, or -1
  std::vector<std::vector<CouplingData>> past_;  // outputs at t_{n-1}, t_{n-2}
  std::vector<CouplingData> start_;              // outputs at t_n
  std::unique_ptr<Accelerator> accel_;
  std::vector<double> largest_;  // per quantity: the largest norm it has had in the run
  ConvergenceLog log_;
};

// The schedule for a scheme and coupling options: the plain Jacobi or
// Gauss–Seidel schedule for explicit coupling with held inputs, a
// WindowSchedule otherwise. Throws std::invalid_argument for a combination
// that does not exist.
std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        const CouplingOptions& options,
                                        std::vector<Participant*> participants, Routing routing,
                                        std::vector<std::string> roles, double macro_step);

}  // namespace railcosim
