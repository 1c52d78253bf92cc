#include "coupled_statics.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "subsystem.hpp"

namespace railcosim {

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

// The upward values: every input a participant gets from a later one.
struct Upward {
  std::vector<std::pair<std::size_t, std::size_t>> slots;  // (participant, interface)

  std::vector<double> flatten(const std::vector<CouplingData>& data) const {
    std::vector<double> x;
    for (auto [p, j] : slots)
      for (const auto* v : {&data[p][j].displacement, &data[p][j].velocity, &data[p][j].force})
        x.insert(x.end(), v->begin(), v->end());
    return x;
  }
  void scatter(const std::vector<double>& x, std::vector<CouplingData>& data) const {
    std::size_t k = 0;
    for (auto [p, j] : slots)
      for (auto* v : {&data[p][j].displacement, &data[p][j].velocity, &data[p][j].force})
        for (double& e : *v) e = x[k++];
  }
  // Which quantity each flattened entry is (0 displacement, 1 velocity, 2 force).
  std::vector<int> kinds(const std::vector<CouplingData>& data) const {
    std::vector<int> q;
    for (auto [p, j] : slots) {
      q.insert(q.end(), data[p][j].displacement.size(), 0);
      q.insert(q.end(), data[p][j].velocity.size(), 1);
      q.insert(q.end(), data[p][j].force.size(), 2);
    }
    return q;
  }
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

StaticsOutcome find_static_state(const std::vector<Participant*>& ps, const Routing& routing,
                                 std::vector<CouplingData> inputs, const StaticsOptions& o) {
  const std::size_t P = ps.size();
  Upward up;
  for (std::size_t p = 0; p < P; ++p)
    for (std::size_t j = 0; j < routing[p].size(); ++j)
      if (static_cast<std::size_t>(routing[p][j].participant) > p) up.slots.emplace_back(p, j);

  std::vector<CouplingData> outputs(P);
  const std::vector<int> kind = up.kinds(inputs);
  std::vector<double> x = up.flatten(inputs), r_prev;
  double omega = 1.0;  // the first sweep is taken whole
  double best = INFINITY;
  int best_iteration = 0;
  StaticsOutcome out;
  for (int it = 1; it <= o.max_iterations; ++it) {
    for (std::size_t p = 0; p < P; ++p) {
      for (std::size_t j = 0; j < routing[p].size(); ++j) {
        const Route& r = routing[p][j];
        const auto q = static_cast<std::size_t>(r.participant);
        if (q < p) inputs[p][j] = outputs[q][static_cast<std::size_t>(r.interface)];
      }
      outputs[p] = ps[p]->statics(inputs[p]);
    }
    std::vector<CouplingData> fresh = inputs;
    for (auto [p, j] : up.slots) {
      const Route& r = routing[p][j];
      fresh[p][j] =
          outputs[static_cast<std::size_t>(r.participant)][static_cast<std::size_t>(r.interface)];
    }
    const std::vector<double> x_tilde = up.flatten(fresh);
    std::vector<double> res(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) res[k] = x_tilde[k] - x[k];
    // The relative change per quantity.
    double worst = 0;
    for (int q = 0; q < 3; ++q) {
      double rr = 0, xx = 0;
      for (std::size_t k = 0; k < x.size(); ++k)
        if (kind[k] == q) {
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
    if (!r_prev.empty()) {
      std::vector<double> d(res.size());
      for (std::size_t k = 0; k < d.size(); ++k) d[k] = res[k] - r_prev[k];
      const double dd = dot(d, d);
      if (dd > 0) omega = -omega * dot(r_prev, d) / dd;
    }
    for (std::size_t k = 0; k < x.size(); ++k) x[k] += omega * res[k];
    r_prev = std::move(res);
    up.scatter(x, inputs);
  }
  std::ostringstream s;
  s << "the coupled static state was not found: the interface values still changed by "
    << out.residual << " (relative) after " << o.max_iterations << " iterations";
  throw std::runtime_error(s.str());
}

}  // namespace railcosim
