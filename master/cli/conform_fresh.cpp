#include "cli/conform_fresh.hpp"

#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

#include "remote/remote_participant.hpp"

namespace railcosim::cli {
namespace {

// One draw of the random inputs of a check.
struct Draw {
  CouplingData direction;  // d: each input times a random factor in [-size, size]
  double factor = 0;       // c
};

Draw draw(const CouplingData& base, std::uint64_t seed, double size) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), factor(1.5, 4.0);
  Draw d{base, factor(rng)};
  for (InterfaceData& i : d.direction)
    for (auto* v : {&i.displacement, &i.velocity, &i.force})
      for (double& x : *v) x *= size * unit(rng);
  return d;
}

CouplingData plus(const CouplingData& a, const CouplingData& d, double c) {
  CouplingData r = a;
  for (std::size_t i = 0; i < r.size(); ++i) {
    auto add = [c](std::vector<double>& x, const std::vector<double>& y) {
      for (std::size_t k = 0; k < x.size() && k < y.size(); ++k) x[k] += c * y[k];
    };
    add(r[i].displacement, d[i].displacement);
    add(r[i].velocity, d[i].velocity);
    add(r[i].force, d[i].force);
  }
  return r;
}

// Every output value, in order.
std::vector<double> flat(const CouplingData& o) {
  std::vector<double> v;
  for (const InterfaceData& i : o)
    for (const auto* q : {&i.displacement, &i.velocity, &i.force})
      v.insert(v.end(), q->begin(), q->end());
  return v;
}

double norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

// "" when o(c) - o0 = c (o1 - o0) within `tolerance` of its size.
std::string scales(const CouplingData& o0, const CouplingData& o1, const CouplingData& oc, double c,
                   double tolerance, const std::string& what, std::uint64_t seed) {
  const std::vector<double> a = flat(o0), b = flat(o1), x = flat(oc);
  if (a.size() != b.size() || a.size() != x.size()) return what + ": outputs of another size";
  std::vector<double> d1(a.size()), dc(a.size()), err(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    d1[k] = b[k] - a[k];
    dc[k] = x[k] - a[k];
    err[k] = dc[k] - c * d1[k];
  }
  std::ostringstream s;
  s << what << " (seed " << seed << "): ";
  if (norm(d1) == 0.0 || norm(dc) == 0.0) {
    s << "the outputs did not change with inputs never sent before";
    return s.str();
  }
  const double rel = norm(err) / norm(dc);
  if (rel <= tolerance) return "";
  s << "the change of the outputs under the input change scaled by c = " << c
    << " is not c times the change under the input change itself: relative error " << rel
    << " (at most " << tolerance << ")";
  return s.str();
}

std::unique_ptr<remote::RemoteParticipant> session(const FreshSubject& s) {
  remote::RemoteTimeouts t;
  t.reply = t.step_min = t.step_max = std::chrono::milliseconds(10000);
  return std::make_unique<remote::RemoteParticipant>(s.o.address, s.scene, s.config, t, s.o.token);
}

// Initializes `p` and takes macro steps 0 .. n - 1 with the kit's inputs.
void steps_before(remote::RemoteParticipant& p, const FreshSubject& s, long n) {
  p.initialize(s.inputs(0));
  for (long k = 0; k < n; ++k) {
    p.set_inputs(k, s.inputs(k));
    p.step(k);
  }
}

}  // namespace

std::string check_static_loads(const FreshSubject& s) {
  auto p = session(s);
  const CouplingData load = plus(s.inputs(0), draw(s.inputs(0), s.seed + 1, 0.2).direction, 1.0);
  const Draw d = draw(load, s.seed, 2e-3);
  const CouplingData o0 = p->statics(load);
  const CouplingData o1 = p->statics(plus(load, d.direction, 1.0));
  const CouplingData oc = p->statics(plus(load, d.direction, d.factor));
  return scales(o0, o1, oc, d.factor, 1e-2, "statics", s.seed);
}

std::string check_restore_new_inputs(const FreshSubject& s) {
  const long n = 3;
  const CouplingData a = s.inputs(n);
  const Draw d = draw(a, s.seed + 2, 1e-3);
  const CouplingData b = plus(a, d.direction, 1.0), c = plus(a, d.direction, d.factor);
  auto p = session(s);
  steps_before(*p, s, n);
  const ParticipantState saved = p->save();
  auto step = [&](const CouplingData& in) {
    p->set_inputs(n, in);
    return p->step(n).outputs;
  };
  const CouplingData oa = step(a);
  p->restore(saved);
  const CouplingData ob = step(b);
  p->restore(saved);
  const CouplingData oc = step(c);
  p.reset();
  std::ostringstream seed;
  seed << " (seed " << s.seed << ")";
  if (ob == oa)
    return "after a restore, new inputs gave the outputs of the first pass" + seed.str();
  if (std::string why = scales(oa, ob, oc, d.factor, 1e-2, "a step after a restore", s.seed);
      !why.empty())
    return why;
  auto fresh = session(s);
  steps_before(*fresh, s, n);
  fresh->set_inputs(n, b);
  if (fresh->step(n).outputs != ob)
    return "the step after a restore with new inputs differs from a fresh session's step with "
           "those inputs" +
           seed.str();
  return "";
}

}  // namespace railcosim::cli
