#include "engine/fast_group.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace railcosim::engine {

SlowView::SlowView(std::string name, CouplingData start, double fine_step, int intervals)
    : name_(std::move(name)),
      shape_(start),
      now_(std::move(start)),
      h_(fine_step),
      intervals_(std::max(1, intervals)) {}

CouplingData SlowView::statics(const CouplingData&) {
  throw CallOrderError(name_ +
                       ": statics() rejected: a view only replays its participant's values");
}

StepResult SlowView::initialize(const CouplingData&) {
  StepResult r;
  r.outputs = now_;
  return r;
}

CouplingData SlowView::at(double t) const {
  if (window_.size() != shape_.size())
    throw CallOrderError(name_ + ": stepped before its window's values were set");
  CouplingData d;
  for (std::size_t i = 0; i < shape_.size(); ++i)
    d.push_back(unpack_values(window_[i].at(t), shape_[i]));
  return d;
}

void SlowView::start_step(long n) {
  n_ = n;
  now_ = at(static_cast<double>(n) * h_);
}

StepResult SlowView::finish_step() {
  const double t0 = static_cast<double>(n_) * h_, t1 = static_cast<double>(n_ + 1) * h_;
  // Its samples: at `intervals_` equal parts of the fine window, at times
  // that do not move with the slow participant's micro steps from one
  // iteration to the next (a degree-p waveform through p + 1 of them keeps
  // its order in h).
  if (record_) {
    samples_.assign(1, OutputSample{.t = t0, .outputs = now_});
    for (int k = 1; k < intervals_; ++k) {
      const double t = t0 + (t1 - t0) * k / intervals_;
      samples_.push_back(OutputSample{.t = t, .outputs = at(t)});
    }
  }
  now_ = at(t1);
  if (record_) samples_.push_back(OutputSample{.t = t1, .outputs = now_});
  StepResult r;
  r.outputs = now_;
  for (const InterfaceData& d : now_)
    for (const auto* a : {&d.displacement, &d.velocity, &d.force})
      r.finite =
          r.finite && std::all_of(a->begin(), a->end(), [](double x) { return std::isfinite(x); });
  return r;
}

namespace {

// A view's samples divide each fine window into this many parts: fixed
// times (they do not move with the slow side's micro steps), enough for a
// cubic waveform's four.
constexpr int kViewIntervals = 4;

std::string group_name(const RatePlan& rates, const std::vector<std::string>& roles) {
  std::string s;
  for (std::size_t p : rates.fast) s += (s.empty() ? "" : "+") + roles.at(p);
  return s;
}

}  // namespace

FastGroup::FastGroup(const RatePlan& rates, const std::vector<Participant*>& all,
                     const std::vector<CouplingData>& static_inputs, PlanOptions plan,
                     CouplingOptions coupling, const std::vector<std::string>& roles,
                     double fine_step)
    : name_(group_name(rates, roles)), rates_(rates), h_(fine_step) {
  const std::size_t F = rates.fast.size();
  std::vector<Participant*> inner;
  std::vector<std::string> inner_roles;
  for (std::size_t p : rates.fast) {
    members_.push_back(all.at(p));
    inner.push_back(all.at(p));
    inner_roles.push_back(roles.at(p));
    inner_start_.push_back(static_inputs.at(p));
  }
  for (std::size_t v = 0; v < rates.viewed.size(); ++v) {
    // What the view shows at t = 0: what its fast peers take from it.
    CouplingData start;
    for (const Route& to : rates.inner[F + v]) {
      const auto a = static_cast<std::size_t>(to.participant);
      start.push_back(static_inputs.at(rates.fast[a]).at(static_cast<std::size_t>(to.interface)));
    }
    const std::string& role = roles.at(rates.viewed[v]);
    views_.push_back(
        std::make_unique<SlowView>(role + " (over its window)", start, fine_step, kViewIntervals));
    inner.push_back(views_.back().get());
    inner_roles.push_back(role);
    inner_start_.emplace_back();
  }
  // The one member on the slow side whose own substep samples the group
  // sends (members_.size() when several members face the slow side).
  boundary_ =
      rates.group_interfaces.empty() ? members_.size() : rates.group_interfaces.front().first;
  for (const auto& [a, j] : rates.group_interfaces) {
    if (a != boundary_) boundary_ = members_.size();
    const Route& to = rates.inner[a][j];
    view_of_.emplace_back(static_cast<std::size_t>(to.participant) - F,
                          static_cast<std::size_t>(to.interface));
  }
  coupling.iteration_budget = 0;  // the outer level's budget bounds every pass
  // The inner level converges ten times tighter than the outer one, whose
  // fixed point would otherwise see the inner iterations' own residual.
  coupling.convergence *= 0.1;
  inner_ =
      std::make_unique<StepExecutor>(inner, rates.inner, plan, coupling, inner_roles, fine_step);
  std::vector<bool> leads(inner.size(), false);
  std::fill(leads.begin() + static_cast<std::ptrdiff_t>(F), leads.end(), true);
  inner_->set_leading(leads);
}

CouplingData FastGroup::statics(const CouplingData&) {
  throw CallOrderError(name_ + ": statics() rejected: the coupled static state is its members'");
}

StepResult FastGroup::group_result(const std::vector<StepResult>& members) const {
  StepResult r;
  for (const auto& [a, j] : rates_.group_interfaces) r.outputs.push_back(members[a].outputs[j]);
  for (const StepResult& m : members) {
    r.max_abs_displacement = std::max(r.max_abs_displacement, m.max_abs_displacement);
    r.finite = r.finite && m.finite;
  }
  return r;
}

StepResult FastGroup::initialize(const CouplingData&) {
  std::vector<StepResult> r = inner_->initialize(inner_start_);
  r.resize(members_.size());
  fine_.assign(1, r);
  StepResult g = group_result(r);
  last_ = g.outputs;
  return g;
}

void FastGroup::to_views(const InputWaveforms& w) {
  std::vector<std::vector<Waveform>> per_view(views_.size());
  for (std::size_t v = 0; v < views_.size(); ++v)
    per_view[v].assign(rates_.view_interfaces[v].size(), Waveform(0, 0));
  for (std::size_t g = 0; g < w.size(); ++g) per_view[view_of_[g].first][view_of_[g].second] = w[g];
  for (std::size_t v = 0; v < views_.size(); ++v) views_[v]->set_window(std::move(per_view[v]));
}

void FastGroup::set_inputs(long n, const CouplingData& inputs) {
  InputWaveforms w;
  for (const InterfaceData& d : inputs) {
    const std::vector<double> v = pack_values(d);
    w.emplace_back(0, v.size());
    w.back().add(static_cast<double>(n * rates_.ratio) * h_, v);
  }
  to_views(w);
}

void FastGroup::set_inputs(long n, const CouplingData& start, const CouplingData& end) {
  InputWaveforms w;
  for (std::size_t g = 0; g < start.size(); ++g) {
    const std::vector<double> a = pack_values(start[g]);
    w.emplace_back(1, a.size());
    w.back().add(static_cast<double>(n * rates_.ratio) * h_, a);
    w.back().add(static_cast<double>((n + 1) * rates_.ratio) * h_, pack_values(end.at(g)));
  }
  to_views(w);
}

void FastGroup::set_input_waveforms(long, const InputWaveforms& inputs) {
  to_views(inputs);
}

StepResult FastGroup::finish_step() {
  const long first = n_ * rates_.ratio;
  if (record_)
    samples_.assign(1, OutputSample{.t = static_cast<double>(first) * h_, .outputs = last_});
  fine_.clear();
  StepResult g;
  for (long k = 0; k < rates_.ratio; ++k) {
    std::vector<StepResult> r = inner_->advance(first + k);
    r.resize(members_.size());
    g = group_result(r);
    fine_.push_back(std::move(r));
    if (record_) record_window(first + k, g.outputs);
  }
  last_ = g.outputs;
  return g;
}

void FastGroup::record_window(long n, const CouplingData& end) {
  // One member on the slow side: its own substep samples (the slow side's
  // waveform keeps its order in h); several: the fine window's end.
  const std::size_t b = boundary_;
  if (b == members_.size()) {
    samples_.push_back(OutputSample{.t = static_cast<double>(n + 1) * h_, .outputs = end});
    return;
  }
  const OutputSamples own = members_[b]->step_samples();
  for (std::size_t k = 1; k < own.size(); ++k) {
    OutputSample s{.t = own[k].t, .outputs = {}};
    for (const auto& [a, j] : rates_.group_interfaces) s.outputs.push_back(own[k].outputs.at(j));
    samples_.push_back(std::move(s));
  }
}

ParticipantState FastGroup::save() {
  kept_.clear();
  for (Participant* m : members_) kept_.push_back(m->save());
  kept_inner_ = inner_->checkpoint();
  kept_last_ = last_;
  ParticipantState s;
  s.kept = true;
  return s;
}

void FastGroup::restore(const ParticipantState&) {
  if (kept_.size() != members_.size())
    throw CallOrderError(name_ + ": restore() rejected: nothing was saved");
  for (std::size_t m = 0; m < members_.size(); ++m) members_[m]->restore(kept_[m]);
  inner_->restore(kept_inner_);
  last_ = kept_last_;
}

}  // namespace railcosim::engine
