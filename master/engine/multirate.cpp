#include "engine/multirate.hpp"

#include <stdexcept>

#include "engine/window_schedule.hpp"

namespace railcosim::engine {
namespace {

// (1 - s) a + s b, elementwise.
std::vector<double> blend(const std::vector<double>& a, const std::vector<double>& b, double s) {
  std::vector<double> r = b;
  for (std::size_t k = 0; k < r.size() && k < a.size(); ++k) r[k] = (1 - s) * a[k] + s * b[k];
  return r;
}

StepResult between(const StepResult& a, const StepResult& b, double s) {
  StepResult r = b;
  for (std::size_t i = 0; i < r.outputs.size() && i < a.outputs.size(); ++i) {
    r.outputs[i].displacement = blend(a.outputs[i].displacement, b.outputs[i].displacement, s);
    r.outputs[i].velocity = blend(a.outputs[i].velocity, b.outputs[i].velocity, s);
    r.outputs[i].force = blend(a.outputs[i].force, b.outputs[i].force, s);
  }
  r.history = blend(a.history, b.history, s);
  r.max_abs_displacement = (1 - s) * a.max_abs_displacement + s * b.max_abs_displacement;
  r.finite = a.finite && b.finite;
  return r;
}

}  // namespace

MultirateExecutor::MultirateExecutor(RatePlan rates, std::vector<Participant*> participants,
                                     const std::vector<CouplingData>& static_inputs, Scheme scheme,
                                     CouplingOptions coupling, std::vector<std::string> roles,
                                     double fine_step)
    : rates_(std::move(rates)), ps_(std::move(participants)) {
  if (!rates_.multirate()) throw std::logic_error("MultirateExecutor: a single-rate plan");
  const PlanOptions plan{scheme, Feedthrough::kLagged, false};
  group_ =
      std::make_unique<FastGroup>(rates_, ps_, static_inputs, plan, coupling, roles, fine_step);
  std::vector<Participant*> outer;
  std::vector<std::string> outer_roles;
  for (std::size_t p : rates_.outer_members) {
    const bool group = p == rates_.fast.front();
    outer.push_back(group ? group_.get() : ps_.at(p));
    outer_roles.push_back(group ? group_->name() : roles.at(p));
  }
  outer_ = std::make_unique<StepExecutor>(outer, rates_.outer, plan, coupling, outer_roles,
                                          fine_step * static_cast<double>(rates_.ratio));
}

std::vector<StepResult> MultirateExecutor::initialize(const std::vector<CouplingData>& inputs) {
  std::vector<CouplingData> outer;
  for (std::size_t p : rates_.outer_members) {
    if (p != rates_.fast.front()) {
      outer.push_back(inputs.at(p));
      continue;
    }
    CouplingData g;
    for (const auto& [a, j] : rates_.group_interfaces) g.push_back(inputs.at(rates_.fast[a]).at(j));
    outer.push_back(g);
  }
  const std::vector<StepResult> r = outer_->initialize(outer);
  std::vector<StepResult> all(ps_.size());
  for (std::size_t a = 0; a < rates_.fast.size(); ++a)
    all[rates_.fast[a]] = group_->fine_results().front().at(a);
  for (std::size_t k = 0; k < rates_.outer_members.size(); ++k)
    if (k != rates_.group_at) all[rates_.outer_members[k]] = r[k];
  slow_last_ = all;
  window_at_ = -1;
  return all;
}

CoupledSteps::Memory MultirateExecutor::memory() const {
  Memory m = outer_->memory();
  const Memory inner = group_->inner().memory();
  m.out.insert(m.out.end(), inner.out.begin(), inner.out.end());
  if (m.past.size() != inner.past.size())
    throw std::logic_error("MultirateExecutor: the levels hold different past points");
  for (std::size_t k = 0; k < m.past.size(); ++k)
    m.past[k].insert(m.past[k].end(), inner.past[k].begin(), inner.past[k].end());
  return m;
}

void MultirateExecutor::set_memory(Memory m) {
  const auto n = static_cast<std::ptrdiff_t>(rates_.outer_members.size());
  Memory outer, inner;
  outer.out.assign(m.out.begin(), m.out.begin() + n);
  inner.out.assign(m.out.begin() + n, m.out.end());
  for (const auto& point : m.past) {
    outer.past.emplace_back(point.begin(), point.begin() + n);
    inner.past.emplace_back(point.begin() + n, point.end());
  }
  group_->set_outputs(outer.out.at(rates_.group_at));
  outer_->set_memory(std::move(outer));
  group_->set_inner_memory(std::move(inner));
  window_at_ = -1;
}

std::vector<StepResult> MultirateExecutor::advance(long n) {
  const long M = rates_.ratio, N = n / M;
  if (n % M == 0) {
    const std::vector<StepResult> r = outer_->advance(N);
    window_.assign(static_cast<std::size_t>(M), std::vector<StepResult>(ps_.size()));
    for (long k = 0; k < M; ++k) {
      auto& at = window_[static_cast<std::size_t>(k)];
      for (std::size_t a = 0; a < rates_.fast.size(); ++a)
        at[rates_.fast[a]] = group_->fine_results().at(static_cast<std::size_t>(k)).at(a);
      for (std::size_t m = 0; m < rates_.outer_members.size(); ++m) {
        if (m == rates_.group_at) continue;
        const std::size_t s = rates_.outer_members[m];
        at[s] = k + 1 == M ? r[m]
                           : between(slow_last_[s], r[m],
                                     static_cast<double>(k + 1) / static_cast<double>(M));
      }
    }
    slow_last_ = window_.back();
    window_at_ = N;
  } else if (N != window_at_) {
    throw std::logic_error("MultirateExecutor: fine window " + std::to_string(n) +
                           " asked before its slow window was stepped");
  }
  return window_[static_cast<std::size_t>(n % M)];
}

std::unique_ptr<CoupledSteps> make_coupled_steps(
    const RatePlan& rates, Scheme scheme, Feedthrough feedthrough, const CouplingOptions& coupling,
    std::vector<Participant*> participants, Routing routing, std::vector<std::string> roles,
    double macro_step, const std::vector<CouplingData>& static_inputs) {
  if (!rates.multirate())
    return make_schedule(scheme, feedthrough, coupling, std::move(participants), std::move(routing),
                         std::move(roles), macro_step);
  return std::make_unique<MultirateExecutor>(rates, std::move(participants), static_inputs, scheme,
                                             coupling, std::move(roles), macro_step);
}

}  // namespace railcosim::engine
