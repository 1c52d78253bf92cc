#include "window_schedule.hpp"

#include <cmath>
#include <stdexcept>

namespace railcosim {
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

// The arrays of one interface's values, in a fixed order.
std::vector<const std::vector<double>*> arrays(const InterfaceData& d) {
  return {&d.displacement, &d.velocity, &d.force};
}
std::vector<std::vector<double>*> arrays(InterfaceData& d) {
  return {&d.displacement, &d.velocity, &d.force};
}
const char* const kQuantity[] = {"displacement", "velocity", "force"};

}  // namespace

WindowSchedule::WindowSchedule(std::vector<Participant*> participants, Routing routing,
                               std::vector<std::string> roles, Scheme scheme,
                               const CouplingOptions& options, double macro_step)
    : Schedule(std::move(participants), std::move(routing)),
      roles_(std::move(roles)),
      scheme_(scheme),
      o_(options),
      macro_step_(macro_step) {
  check(o_);
  if (roles_.size() != ps_.size())
    throw std::logic_error("WindowSchedule: one role per participant");
  for (std::size_t p = 0; p < routing_.size(); ++p)
    for (std::size_t j = 0; j < routing_[p].size(); ++j) {
      const Route& r = routing_[p][j];
      links_.push_back(
          {p, j, static_cast<std::size_t>(r.participant), static_cast<std::size_t>(r.interface)});
    }
  position_.assign(links_.size(), -1);
  if (o_.method == CouplingMethod::kImplicit)
    for (std::size_t k = 0; k < links_.size(); ++k)
      if (iterated(links_[k])) {
        position_[k] = static_cast<int>(iterated_.size());
        iterated_.push_back(k);
      }
}

bool WindowSchedule::iterated(const Link& l) const {
  return scheme_ == Scheme::kJacobi || l.q > l.p;
}

std::vector<StepResult> WindowSchedule::advance(long n) {
  start_ = out_;
  std::vector<StepResult> r =
      o_.method == CouplingMethod::kImplicit ? implicit_window(n) : pass(n, {});
  past_.insert(past_.begin(), start_);
  if (past_.size() > 2) past_.pop_back();
  keep_outputs(r);
  return r;
}

void WindowSchedule::set_inputs(std::size_t p, long n,
                                const std::vector<const InterfaceData*>& end) {
  CouplingData start;
  for (const Route& r : routing_[p])
    start.push_back(
        start_[static_cast<std::size_t>(r.participant)][static_cast<std::size_t>(r.interface)]);
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

std::vector<StepResult> WindowSchedule::pass(long n, const std::vector<InterfaceData>& x) {
  const std::size_t P = ps_.size();
  std::vector<StepResult> r(P);
  std::vector<bool> fresh(P, false);
  std::vector<InterfaceData> extrapolated(links_.size());
  auto ends_for = [&](std::size_t p) {
    std::vector<const InterfaceData*> end(routing_[p].size(), nullptr);
    for (std::size_t k = 0; k < links_.size(); ++k) {
      const Link& l = links_[k];
      if (l.p != p) continue;
      if (fresh[l.q]) {
        end[l.j] = &r[l.q].outputs[l.i];
        continue;
      }
      if (!x.empty()) {
        if (position_[k] >= 0) end[l.j] = &x[static_cast<std::size_t>(position_[k])];
        continue;
      }
      const InterfaceData& now = start_[l.q][l.i];
      if (o_.inputs == InputMode::kExtrapolate1 && !past_.empty()) {
        extrapolated[k] = combine(2.0, now, -1.0, &past_[0][l.q][l.i], 0.0, nullptr);
        end[l.j] = &extrapolated[k];
      } else if (o_.inputs == InputMode::kExtrapolate2 && !past_.empty()) {
        extrapolated[k] =
            past_.size() >= 2
                ? combine(3.0, now, -3.0, &past_[0][l.q][l.i], 1.0, &past_[1][l.q][l.i])
                : combine(2.0, now, -1.0, &past_[0][l.q][l.i], 0.0, nullptr);
        end[l.j] = &extrapolated[k];
      }
    }
    return end;
  };
  if (scheme_ == Scheme::kJacobi) {
    for (std::size_t p = 0; p < P; ++p) set_inputs(p, n, ends_for(p));
    for (Participant* p : ps_) p->start_step(n);
    for (std::size_t p = 0; p < P; ++p) r[p] = ps_[p]->finish_step();
  } else {
    for (std::size_t p = 0; p < P; ++p) {
      set_inputs(p, n, ends_for(p));
      r[p] = ps_[p]->step(n);
      fresh[p] = true;
    }
  }
  return r;
}

std::vector<StepResult> WindowSchedule::implicit_window(long n) {
  const std::size_t P = ps_.size();
  std::vector<ParticipantState> checkpoint;
  checkpoint.reserve(P);
  for (Participant* p : ps_) checkpoint.push_back(p->save());

  std::vector<InterfaceData> x;
  for (std::size_t k : iterated_) x.push_back(start_[links_[k].q][links_[k].i]);
  // The blocks: one per iterated value and quantity it carries.
  std::vector<int> blocks;
  // For a velocity block, the block of the same value's displacement (-1: none).
  std::vector<int> displacement_of;
  std::vector<std::string> names;
  for (std::size_t m = 0; m < x.size(); ++m) {
    const Link& l = links_[iterated_[m]];
    const auto a = arrays(x[m]);
    for (std::size_t q = 0; q < a.size(); ++q)
      if (!a[q]->empty()) {
        blocks.push_back(static_cast<int>(a[q]->size()));
        displacement_of.push_back(q == 1 && !a[0]->empty() ? static_cast<int>(blocks.size()) - 2
                                                           : -1);
        std::string name = roles_[l.q];
        name += "_to_";
        name += roles_[l.p];
        name += '_';
        name += kQuantity[q];
        names.push_back(name);
      }
  }
  if (!accel_) {
    accel_ = make_accelerator(o_.accelerator, blocks);
    log_.quantities = names;
  }
  auto flatten = [&](const std::vector<InterfaceData>& v) {
    int size = 0;
    for (int b : blocks) size += b;
    VectorXd f(size);
    Eigen::Index at = 0;
    for (const InterfaceData& d : v)
      for (const std::vector<double>* a : arrays(d))
        for (double e : *a) f[at++] = e;
    return f;
  };
  auto unflatten = [&](const VectorXd& f) {
    Eigen::Index at = 0;
    for (InterfaceData& d : x)
      for (std::vector<double>* a : arrays(d))
        for (double& e : *a) e = f[at++];
  };

  for (int k = 1;; ++k) {
    if (k > 1)
      for (std::size_t p = 0; p < P; ++p) ps_[p]->restore(checkpoint[p]);
    std::vector<StepResult> r = pass(n, x);
    std::vector<InterfaceData> g;
    for (std::size_t m : iterated_) g.push_back(r[links_[m].q].outputs[links_[m].i]);
    const VectorXd X = flatten(x), G = flatten(g);
    ConvergenceLog::Row row;
    row.step = n;
    row.iteration = k;
    std::vector<double> scale;
    bool converged = true, finite = G.allFinite();
    Eigen::Index at = 0;
    if (largest_.empty()) largest_.assign(blocks.size(), 0.0);
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      const auto gb = G.segment(at, blocks[b]), xb = X.segment(at, blocks[b]);
      if (finite) largest_[b] = std::max({largest_[b], gb.norm(), xb.norm()});
      // A velocity is measured against its displacement's largest norm / H
      // too: a velocity error dv moves the displacement by dv H.
      const double den =
          displacement_of[b] >= 0
              ? std::max(largest_[b],
                         largest_[static_cast<std::size_t>(displacement_of[b])] / macro_step_)
              : largest_[b];
      const double res = den > 0 ? (gb - xb).norm() / den : 0.0;
      row.residual.push_back(res);
      converged = converged && res <= o_.convergence;
      scale.push_back(den > 0 ? 1.0 / den : 1.0);
      at += blocks[b];
    }
    log_.rows.push_back(std::move(row));
    if (k == 1) accel_->start_window();
    accel_->set_weights(scale);
    if (converged || !finite || k >= o_.max_iterations) {
      if (!converged && finite) {
        ++log_.not_converged;
        if (log_.first_not_converged < 0) log_.first_not_converged = n;
      }
      accel_->end_window();
      log_.iterations.push_back(k);
      return r;
    }
    unflatten(accel_->next(X, G));
  }
}

std::unique_ptr<Schedule> make_schedule(Scheme scheme, Feedthrough feedthrough,
                                        const CouplingOptions& options,
                                        std::vector<Participant*> participants, Routing routing,
                                        std::vector<std::string> roles, double macro_step) {
  if (options.is_plain())
    return make_schedule(scheme, feedthrough, std::move(participants), std::move(routing));
  if (feedthrough == Feedthrough::kResolved)
    throw std::invalid_argument(
        "--feedthrough resolved applies to explicit coupling with held inputs only (--coupling "
        "explicit --inputs hold)");
  return std::make_unique<WindowSchedule>(std::move(participants), std::move(routing),
                                          std::move(roles), scheme, options, macro_step);
}

}  // namespace railcosim
