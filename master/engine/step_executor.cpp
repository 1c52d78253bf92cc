#include "engine/step_executor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "engine/interface_values.hpp"

namespace railcosim::engine {
namespace {

using Eigen::VectorXd;

// a*x + b*y + c*z elementwise over every quantity (y, z may be null).
InterfaceData combine(double a, const InterfaceData& x, double b, const InterfaceData* y, double c,
                      const InterfaceData* z) {
  InterfaceData r = x;
  auto mix = [&](std::vector<double>& out, const std::vector<double>* ys,
                 const std::vector<double>* zs) {
    for (std::size_t k = 0; k < out.size(); ++k) {
      out[k] *= a;
      if (ys) out[k] += b * (*ys)[k];
      if (zs) out[k] += c * (*zs)[k];
    }
  };
  mix(r.displacement, y ? &y->displacement : nullptr, z ? &z->displacement : nullptr);
  mix(r.velocity, y ? &y->velocity : nullptr, z ? &z->velocity : nullptr);
  mix(r.force, y ? &y->force : nullptr, z ? &z->force : nullptr);
  return r;
}

// Substep waveforms, implicit: the accelerator works on each iterated link's
// values at this many equally spaced times of the window (the last t_n + H).
constexpr std::size_t kWaveNodes = 4;

// The values at several times stacked array by array: every time's
// displacements, then every time's velocities, then forces.
InterfaceData stack(const std::vector<InterfaceData>& at) {
  InterfaceData s;
  for (const InterfaceData& d : at) {
    s.displacement.insert(s.displacement.end(), d.displacement.begin(), d.displacement.end());
    s.velocity.insert(s.velocity.end(), d.velocity.begin(), d.velocity.end());
    s.force.insert(s.force.end(), d.force.begin(), d.force.end());
  }
  return s;
}

// The k-th of m stacked values.
InterfaceData unstack(const InterfaceData& s, std::size_t k, std::size_t m) {
  InterfaceData d;
  auto part = [&](const std::vector<double>& a, std::vector<double>& out) {
    const auto n = static_cast<std::ptrdiff_t>(a.size() / m);
    out.assign(a.begin() + static_cast<std::ptrdiff_t>(k) * n,
               a.begin() + static_cast<std::ptrdiff_t>(k + 1) * n);
  };
  part(s.displacement, d.displacement);
  part(s.velocity, d.velocity);
  part(s.force, d.force);
  return d;
}

}  // namespace

StepExecutor::StepExecutor(std::vector<Participant*> participants, Routing routing,
                           PlanOptions plan, CouplingOptions coupling,
                           std::vector<std::string> roles, double macro_step)
    : ps_(std::move(participants)),
      routing_(std::move(routing)),
      plan_options_(plan),
      o_(coupling),
      roles_(std::move(roles)),
      macro_step_(macro_step) {
  check(plan_options_);
  check(o_);
  plan_options_.implicit = o_.method == CouplingMethod::kImplicit;
  if (plan_options_.implicit && roles_.size() != ps_.size())
    throw std::logic_error("StepExecutor: one role per participant");
}

std::vector<StepResult> StepExecutor::initialize(const std::vector<CouplingData>& inputs) {
  std::vector<StepResult> r;
  for (std::size_t p = 0; p < ps_.size(); ++p) r.push_back(ps_[p]->initialize(inputs[p]));
  out_.resize(r.size());
  std::vector<bool> force(r.size());
  for (std::size_t p = 0; p < r.size(); ++p) {
    out_[p] = r[p].outputs;
    force[p] = sends_force(out_[p]);
  }
  plan_ = plan_steps(routing_, plan_options_, force, leads_);
  degree_ = waveform_degree(o_.inputs);
  nodes_ = degree_ >= 0 && plan_options_.implicit ? kWaveNodes : 1;
  if (degree_ >= 0)
    for (Participant* p : ps_) p->record_samples(true);
  fresh_.assign(ps_.size(), {});
  last_.assign(ps_.size(), {});
  last_step_ = -1;
  position_.assign(plan_.links.size(), -1);
  iterated_.clear();
  for (std::size_t k = 0; k < plan_.links.size(); ++k)
    if (plan_.links[k].iterated) {
      position_[k] = static_cast<int>(iterated_.size());
      iterated_.push_back(k);
    }
  return r;
}

std::vector<StepResult> StepExecutor::advance(long n) {
  std::vector<StepResult> r =
      o_.method == CouplingMethod::kImplicit ? implicit_step(n) : pass(n, nullptr);
  if (o_.inputs == InputMode::kExtrapolate1 || o_.inputs == InputMode::kExtrapolate2) {
    past_.insert(past_.begin(), out_);
    if (past_.size() > 2) past_.pop_back();
  }
  for (std::size_t p = 0; p < r.size(); ++p) out_[p] = r[p].outputs;
  return r;
}

StepExecutor::Checkpoint StepExecutor::checkpoint() const {
  return {.memory = memory(),
          .accel = accel_ ? std::shared_ptr<const Accelerator>(accel_->clone()) : nullptr,
          .largest = largest_};
}

void StepExecutor::restore(const Checkpoint& c) {
  set_memory(c.memory);
  accel_ = c.accel ? c.accel->clone() : nullptr;
  largest_ = c.largest;
}

void StepExecutor::set_inputs(std::size_t p, long n, const std::vector<CouplingData>* refreshed,
                              const std::vector<const InterfaceData*>& end) {
  if (degree_ >= 0) {
    set_waveforms(p, n, refreshed, end);
    return;
  }
  CouplingData start;
  start.reserve(plan_.into[p].size());
  for (std::size_t k : plan_.into[p]) {
    const PlanLink& l = plan_.links[k];
    const bool fresh = refreshed && l.source == LinkSource::kRefreshed;
    start.push_back((fresh ? (*refreshed)[l.q] : out_[l.q])[l.i]);
  }
  bool any_end = false;
  for (const InterfaceData* e : end) any_end = any_end || e != nullptr;
  if (!any_end) {
    ps_[p]->set_inputs(n, start);
    return;
  }
  CouplingData last = start;
  for (std::size_t j = 0; j < end.size(); ++j)
    if (end[j]) last[j] = *end[j];
  if (o_.inputs == InputMode::kHold)
    ps_[p]->set_inputs(n, last);
  else
    ps_[p]->set_inputs(n, start, last);
}

const InterfaceData* StepExecutor::end_value(std::size_t k, const std::vector<InterfaceData>* x,
                                             std::vector<InterfaceData>& extrapolated) const {
  if (x) return position_[k] >= 0 ? &(*x)[static_cast<std::size_t>(position_[k])] : nullptr;
  if (past_.empty()) return nullptr;
  const PlanLink& l = plan_.links[k];
  const InterfaceData& now = out_[l.q][l.i];
  if (o_.inputs == InputMode::kExtrapolate1) {
    extrapolated[k] = combine(2.0, now, -1.0, &past_[0][l.q][l.i], 0.0, nullptr);
    return &extrapolated[k];
  }
  if (o_.inputs == InputMode::kExtrapolate2) {
    extrapolated[k] = past_.size() >= 2
                          ? combine(3.0, now, -3.0, &past_[0][l.q][l.i], 1.0, &past_[1][l.q][l.i])
                          : combine(2.0, now, -1.0, &past_[0][l.q][l.i], 0.0, nullptr);
    return &extrapolated[k];
  }
  return nullptr;
}

std::vector<StepResult> StepExecutor::pass(long n, const std::vector<InterfaceData>* x) {
  const std::size_t P = ps_.size();
  std::vector<StepResult> r(P);
  std::vector<InterfaceData> extrapolated(plan_.links.size());
  auto ends_for = [&](std::size_t p) {
    std::vector<const InterfaceData*> end(plan_.into[p].size(), nullptr);
    for (std::size_t k : plan_.into[p]) {
      const PlanLink& l = plan_.links[k];
      end[l.j] =
          l.source == LinkSource::kStepped ? &r[l.q].outputs[l.i] : end_value(k, x, extrapolated);
    }
    return end;
  };
  std::vector<CouplingData> refreshed(P);
  for (const std::vector<std::size_t>& stage : plan_.stages) {
    for (std::size_t p : stage) set_inputs(p, n, nullptr, ends_for(p));
    // Resolved feedthrough: the refreshed senders' outputs once their inputs
    // are set, and their receivers' inputs again from those.
    bool any = false;
    for (std::size_t p : stage)
      if (plan_.refreshed[p]) {
        refreshed[p] = ps_[p]->outputs();
        any = true;
      }
    if (any)
      for (std::size_t p : stage)
        for (std::size_t k : plan_.into[p])
          if (plan_.links[k].source == LinkSource::kRefreshed) {
            set_inputs(p, n, &refreshed, ends_for(p));
            break;
          }
    for (std::size_t p : stage) ps_[p]->start_step(n);
    for (std::size_t p : stage) r[p] = ps_[p]->finish_step();
    if (degree_ >= 0)
      for (std::size_t p : stage) fresh_[p] = ps_[p]->step_samples();
  }
  if (degree_ >= 0) {
    last_ = fresh_;
    last_step_ = n;
  }
  return r;
}

void StepExecutor::set_waveforms(std::size_t p, long n, const std::vector<CouplingData>* refreshed,
                                 const std::vector<const InterfaceData*>& end) {
  InputWaveforms w;
  w.reserve(plan_.into[p].size());
  for (std::size_t k : plan_.into[p]) {
    const PlanLink& l = plan_.links[k];
    const bool fresh = refreshed && l.source == LinkSource::kRefreshed;
    const InterfaceData& start = (fresh ? (*refreshed)[l.q] : out_[l.q])[l.i];
    w.push_back(link_waveform(k, n, start, end[l.j]));
  }
  ps_[p]->set_input_waveforms(n, w);
}

double StepExecutor::node_time(long n, std::size_t k) const {
  return k + 1 == nodes_
             ? static_cast<double>(n + 1) * macro_step_
             : (static_cast<double>(n) + static_cast<double>(k + 1) / static_cast<double>(nodes_)) *
                   macro_step_;
}

InterfaceData StepExecutor::at_nodes(const OutputSamples& samples, std::size_t i, long n) const {
  if (nodes_ == 1) return samples.back().outputs[i];
  Waveform w(degree_, pack_values(samples.front().outputs[i]).size());
  for (const OutputSample& s : samples) w.add(s.t, pack_values(s.outputs[i]));
  std::vector<InterfaceData> at;
  for (std::size_t k = 0; k < nodes_; ++k)
    at.push_back(unpack_values(w.at(node_time(n, k)), samples.front().outputs[i]));
  return stack(at);
}

Waveform StepExecutor::link_waveform(std::size_t k, long n, const InterfaceData& start,
                                     const InterfaceData* end) const {
  const PlanLink& l = plan_.links[k];
  const std::vector<double> a = pack_values(start);
  Waveform w(degree_, a.size());
  const double t0 = static_cast<double>(n) * macro_step_;
  const bool iterated = position_[k] >= 0 && end && l.source != LinkSource::kStepped;
  // An iterated link's `end` holds its values at the nodes of the window.
  const std::size_t m = iterated ? nodes_ : 1;
  const OutputSamples* samples = nullptr;
  if (l.source == LinkSource::kStepped)
    samples = &fresh_[l.q];
  else if (iterated && last_step_ == n)
    samples = &last_[l.q];
  if (!samples) {
    // Held, or (first iteration) through the values at the nodes.
    w.add(t0, a);
    if (end)
      for (std::size_t j = 0; j < m; ++j)
        w.add(m == 1 ? static_cast<double>(n + 1) * macro_step_ : node_time(n, j),
              pack_values(unstack(*end, j, m)));
    return w;
  }
  // The sender's samples; an iterated link's are corrected by a waveform
  // through 0 at t_n and, at each node, the accelerator's value less the
  // samples' own there.
  Waveform correction(std::max(1, degree_), a.size());
  correction.add(t0, std::vector<double>(a.size(), 0.0));
  if (iterated) {
    const InterfaceData own = m == 1 ? samples->back().outputs[l.i] : at_nodes(*samples, l.i, n);
    for (std::size_t j = 0; j < m; ++j) {
      std::vector<double> e = pack_values(unstack(*end, j, m));
      const std::vector<double> g = pack_values(unstack(own, j, m));
      for (std::size_t c = 0; c < e.size(); ++c) e[c] -= g[c];
      correction.add(m == 1 ? static_cast<double>(n + 1) * macro_step_ : node_time(n, j), e);
    }
  }
  for (const OutputSample& s : *samples) {
    std::vector<double> v = pack_values(s.outputs[l.i]);
    if (iterated) {
      const std::vector<double> c = correction.at(s.t);
      for (std::size_t q = 0; q < v.size(); ++q) v[q] += c[q];
    }
    w.add(s.t, v);
  }
  return w;
}

void StepExecutor::make_blocks() {
  blocks_.clear();
  displacement_of_.clear();
  log_.quantities.clear();
  for (std::size_t k : iterated_) {
    const PlanLink& l = plan_.links[k];
    const auto a = arrays(out_[l.q][l.i]);
    for (std::size_t q = 0; q < a.size(); ++q)
      if (!a[q]->empty()) {
        blocks_.push_back(static_cast<int>(a[q]->size() * nodes_));
        displacement_of_.push_back(q == 1 && !a[0]->empty() ? static_cast<int>(blocks_.size()) - 2
                                                            : -1);
        std::string name = roles_[l.q];
        name += "_to_";
        name += roles_[l.p];
        name += '_';
        name += kQuantityNames[q];
        log_.quantities.push_back(name);
      }
  }
  accel_ = make_accelerator(o_.accelerator, blocks_);
  largest_.assign(blocks_.size(), 0.0);
}

bool StepExecutor::measure(long n, int k, const VectorXd& X, const VectorXd& G,
                           std::vector<double>& scale) {
  ConvergenceLog::Row row;
  row.step = n;
  row.iteration = k;
  bool converged = true;
  const bool finite = G.allFinite();
  Eigen::Index at = 0;
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const auto gb = G.segment(at, blocks_[b]), xb = X.segment(at, blocks_[b]);
    if (finite) largest_[b] = std::max({largest_[b], gb.norm(), xb.norm()});
    // A velocity is measured against its displacement's largest norm / H
    // too: a velocity error dv moves the displacement by dv H.
    const double den =
        displacement_of_[b] >= 0
            ? std::max(largest_[b],
                       largest_[static_cast<std::size_t>(displacement_of_[b])] / macro_step_)
            : largest_[b];
    const double res = den > 0 ? (gb - xb).norm() / den : 0.0;
    row.residual.push_back(res);
    converged = converged && res <= o_.convergence;
    scale.push_back(den > 0 ? 1.0 / den : 1.0);
    at += blocks_[b];
  }
  log_.rows.push_back(std::move(row));
  return converged;
}

std::vector<StepResult> StepExecutor::implicit_step(long n) {
  const std::size_t P = ps_.size();
  std::vector<ParticipantState> checkpoint;
  checkpoint.reserve(P);
  for (Participant* p : ps_) checkpoint.push_back(p->save());
  std::vector<InterfaceData> x;
  for (std::size_t k : iterated_)
    x.push_back(
        stack(std::vector<InterfaceData>(nodes_, out_[plan_.links[k].q][plan_.links[k].i])));
  if (!accel_) make_blocks();
  const bool single = std::exchange(single_pass_, false);
  for (int k = 1;; ++k) {
    if (o_.iteration_budget > 0 && log_.total >= o_.iteration_budget)
      throw IterationBudgetSpent(o_.iteration_budget, n);
    ++log_.total;
    if (k > 1)
      for (std::size_t p = 0; p < P; ++p) ps_[p]->restore(checkpoint[p]);
    std::vector<StepResult> r = pass(n, &x);
    std::vector<InterfaceData> g;
    for (std::size_t m : iterated_)
      g.push_back(degree_ >= 0 ? at_nodes(fresh_[plan_.links[m].q], plan_.links[m].i, n)
                               : r[plan_.links[m].q].outputs[plan_.links[m].i]);
    const VectorXd X = flatten(x), G = flatten(g);
    std::vector<double> scale;
    const bool converged = measure(n, k, X, G, scale), finite = G.allFinite();
    if (k == 1) accel_->start_window();
    accel_->set_weights(scale);
    if (converged || !finite || single || k >= o_.max_iterations) {
      if (!converged && finite && !single) {
        ++log_.not_converged;
        if (log_.first_not_converged < 0) log_.first_not_converged = n;
      }
      accel_->end_window();
      log_.iterations.push_back(k);
      return r;
    }
    unflatten(accel_->next(X, G), x);
  }
}

}  // namespace railcosim::engine
