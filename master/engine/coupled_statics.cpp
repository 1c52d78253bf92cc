#include "engine/coupled_statics.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/interface_values.hpp"
#include "engine/step_plan.hpp"
#include "subsystem.hpp"

namespace railcosim::engine {

CouplingData zero_inputs(const Scene& scene, const ParticipantSpec& participant) {
  CouplingData in;
  for (const InterfaceSpec& i : participant.interfaces) {
    InterfaceData d;
    const auto n = static_cast<std::size_t>(interface_points(scene, i));
    for (Quantity q : i.receives()) {
      if (q == Quantity::kDisplacement) d.displacement.assign(n, 0.0);
      if (q == Quantity::kVelocity) d.velocity.assign(n, 0.0);
      if (q == Quantity::kForce) d.force.assign(n, 0.0);
    }
    in.push_back(std::move(d));
  }
  return in;
}

namespace {

// The values of the given links' receivers, from `data` (per participant).
std::vector<InterfaceData> held(const StepPlan& plan, const std::vector<std::size_t>& links,
                                const std::vector<CouplingData>& data) {
  std::vector<InterfaceData> v;
  for (std::size_t k : links) v.push_back(data[plan.links[k].p][plan.links[k].j]);
  return v;
}

// Which quantity each flattened entry is (0 displacement, 1 velocity, 2 force).
std::vector<int> kinds(const std::vector<InterfaceData>& v) {
  std::vector<int> q;
  for (const InterfaceData& d : v) {
    const auto a = arrays(d);
    for (int k = 0; k < 3; ++k) q.insert(q.end(), a[static_cast<std::size_t>(k)]->size(), k);
  }
  return q;
}

double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double s = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

StaticsOutcome find_static_state(const std::vector<Participant*>& ps, const Routing& routing,
                                 std::vector<CouplingData> inputs, const StaticsOptions& o) {
  const std::size_t P = ps.size();
  // The sweep of a serial plan: in load order, each participant takes the
  // fresh outputs of those before it; the values from those after it (up
  // the load path) are the iterated unknowns.
  const StepPlan plan = plan_steps(routing, {Scheme::kGaussSeidel, Feedthrough::kLagged, true},
                                   std::vector<bool>(P, false));
  std::vector<std::size_t> up;
  for (std::size_t k = 0; k < plan.links.size(); ++k)
    if (plan.links[k].iterated) up.push_back(k);

  std::vector<CouplingData> outputs(P);
  std::vector<InterfaceData> unknowns = held(plan, up, inputs);
  const std::vector<int> kind = kinds(unknowns);
  Eigen::VectorXd x = flatten(unknowns), r_prev;
  double omega = 1.0;  // the first sweep is taken whole
  double best = INFINITY;
  int best_iteration = 0;
  StaticsOutcome out;
  for (int it = 1; it <= o.max_iterations; ++it) {
    for (const std::vector<std::size_t>& stage : plan.stages)
      for (std::size_t p : stage) {
        for (std::size_t k : plan.into[p]) {
          const PlanLink& l = plan.links[k];
          if (l.source == LinkSource::kStepped) inputs[p][l.j] = outputs[l.q][l.i];
        }
        outputs[p] = ps[p]->statics(inputs[p]);
      }
    std::vector<CouplingData> fresh = inputs;
    for (std::size_t k : up) {
      const PlanLink& l = plan.links[k];
      fresh[l.p][l.j] = outputs[l.q][l.i];
    }
    const Eigen::VectorXd x_tilde = flatten(held(plan, up, fresh));
    Eigen::VectorXd res(x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) res[k] = x_tilde[k] - x[k];
    // The relative change per quantity.
    double worst = 0;
    for (int q = 0; q < 3; ++q) {
      double rr = 0, xx = 0;
      for (Eigen::Index k = 0; k < x.size(); ++k)
        if (kind[static_cast<std::size_t>(k)] == q) {
          rr += res[k] * res[k];
          xx += x_tilde[k] * x_tilde[k];
        }
      if (rr > 0) worst = std::max(worst, xx > 0 ? std::sqrt(rr / xx) : INFINITY);
    }
    out.iterations = it;
    out.residual = worst;
    if (worst < 0.5 * best) {
      best = worst;
      best_iteration = it;
    }
    const bool stalled = it - best_iteration >= o.stall_iterations && worst <= o.floor_tolerance;
    if (worst <= o.tolerance || stalled) {
      out.inputs = std::move(fresh);
      return out;
    }
    // Aitken's dynamic factor (as accelerator.cpp's, with its sums taken in
    // index order: see docs/architecture.md).
    if (r_prev.size() > 0) {
      Eigen::VectorXd d(res.size());
      for (Eigen::Index k = 0; k < d.size(); ++k) d[k] = res[k] - r_prev[k];
      const double dd = dot(d, d);
      if (dd > 0) omega = -omega * dot(r_prev, d) / dd;
    }
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += omega * res[k];
    r_prev = std::move(res);
    unflatten(x, unknowns);
    for (std::size_t m = 0; m < up.size(); ++m)
      inputs[plan.links[up[m]].p][plan.links[up[m]].j] = unknowns[m];
  }
  std::ostringstream s;
  s << "the coupled static state was not found: the interface values still changed by "
    << out.residual << " (relative) after " << o.max_iterations << " iterations";
  throw std::runtime_error(s.str());
}

}  // namespace railcosim::engine
