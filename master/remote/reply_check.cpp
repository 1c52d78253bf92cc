#include "remote/reply_check.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "channel_names.hpp"
#include "scene.hpp"
#include "subsystem.hpp"

namespace railcosim::remote {
namespace {

std::string count_text(std::size_t n, const char* what) {
  std::string s = std::to_string(n);
  s += ' ';
  s += what;
  if (n != 1) s += 's';
  return s;
}

const std::vector<double>& values(const InterfaceData& d, Quantity q) {
  switch (q) {
    case Quantity::kDisplacement:
      return d.displacement;
    case Quantity::kVelocity:
      return d.velocity;
    case Quantity::kForce:
      break;
  }
  return d.force;
}

// The first non-finite value of `v`, as text, or "".
std::string first_non_finite(const std::vector<double>& v, const std::string& what) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k])) {
      std::ostringstream s;
      s << what << " [" << k << "] is " << v[k] << " (not finite)";
      return s.str();
    }
  return "";
}

}  // namespace

ReplyShape reply_shape(const Scene& scene, const SubsystemConfig& config) {
  ReplyShape s;
  for (const InterfaceSpec& i : config.participant.interfaces)
    s.interfaces.push_back(
        {i.kind().name, static_cast<std::size_t>(interface_points(scene, i)), i.sends()});
  s.macro_step = config.macro_step;
  s.rail_nodes = static_cast<std::size_t>(scene.rail_nodes());
  s.sleepers = static_cast<std::size_t>(scene.sleeper_count);
  return s;
}

std::string declare_channels(ReplyShape& shape, const Channels& declared) {
  shape.history = declared.history.size();
  shape.results = declared.results;
  shape.result_sizes.clear();
  for (const std::string& r : declared.results) {
    std::size_t n = 0;
    if (r == "rail_w_m") n = shape.rail_nodes;
    if (r == "soil_m") n = shape.sleepers;
    shape.result_sizes.push_back(n);
  }
  // Each name plain and declared once (channel_names.hpp).
  return check_declared_channels({{"configured: the node", declared}});
}

void require_distinct_channels(const std::vector<Participant*>& ps) {
  std::vector<std::pair<std::string, Channels>> declared;
  for (Participant* p : ps) declared.emplace_back(p->name(), p->channels());
  if (const std::string why = check_declared_channels(declared); !why.empty())
    throw std::runtime_error(why);
}

std::string check_reply_id(std::uint64_t got, std::uint64_t want) {
  if (got == want) return "";
  return "the reply carries id " + std::to_string(got) + ", the request it answers id " +
         std::to_string(want);
}

std::string check_outputs(const CouplingData& out, const ReplyShape& shape) {
  if (out.size() != shape.interfaces.size())
    return "the outputs have " + count_text(out.size(), "interface") + ", the participant " +
           std::to_string(shape.interfaces.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const ReplyShape::Interface& want = shape.interfaces[i];
    for (Quantity q : {Quantity::kDisplacement, Quantity::kVelocity, Quantity::kForce}) {
      const std::vector<double>& v = values(out[i], q);
      bool sent = false;
      for (Quantity s : want.sends) sent = sent || s == q;
      const std::size_t n = sent ? want.points : 0;
      std::string what = "output ";
      what += to_string(q);
      what += " at interface ";
      what += want.cut;
      if (v.size() != n)
        return what + " has " + count_text(v.size(), "value") + ", expected " + std::to_string(n) +
               (sent ? " (one per coupling point)" : " (not sent there)");
      if (std::string bad = first_non_finite(v, what); !bad.empty()) return bad;
    }
  }
  return "";
}

std::string check_step_report(const StepResult& r, std::int64_t got_step, double got_t,
                              std::int64_t want_step, const ReplyShape& shape) {
  if (got_step != want_step)
    return "the step report names communication point " + std::to_string(got_step) +
           ", the request asked for " + std::to_string(want_step);
  const double want_t = static_cast<double>(want_step) * shape.macro_step;
  if (!(std::abs(got_t - want_t) <= kTimeSlack * shape.macro_step)) {
    std::ostringstream s;
    s << "the step report gives t = " << got_t << " s for communication point " << want_step
      << ", which is at t = " << want_t << " s";
    return s.str();
  }
  if (r.history.size() != shape.history)
    return "the step report carries " + count_text(r.history.size(), "history value") +
           ", the node declared " + std::to_string(shape.history);
  // A node that says its state ran away is believed: the run diverges.
  if (!r.finite) return "";
  if (!std::isfinite(r.max_abs_displacement) || r.max_abs_displacement < 0) {
    std::ostringstream s;
    s << "the step report's maximum displacement is " << r.max_abs_displacement
      << " while it says the state is finite";
    return s.str();
  }
  if (std::string bad = first_non_finite(r.history, "history value"); !bad.empty())
    return "the step report says the state is finite, but its " + bad;
  if (std::string bad = check_outputs(r.outputs, shape); !bad.empty())
    return "the step report: " + bad;
  return "";
}

std::string check_results(const ParticipantResults& r, const ReplyShape& shape) {
  if (r.micro_steps < 0)
    return "the results give a negative micro-step count (" + std::to_string(r.micro_steps) + ")";
  if (r.fields.size() != shape.results.size())
    return "the results carry " + count_text(r.fields.size(), "field") + ", the node declared " +
           std::to_string(shape.results.size());
  for (std::size_t k = 0; k < r.fields.size(); ++k) {
    const std::string what = "result field '" + shape.results[k] + "'";
    const std::size_t want = shape.result_sizes[k];
    if (want != 0 && r.fields[k].size() != want)
      return what + " has " + count_text(r.fields[k].size(), "value") + ", the model " +
             std::to_string(want);
    if (std::string bad = first_non_finite(r.fields[k], what); !bad.empty()) return bad;
  }
  return "";
}

std::string check_state(const ParticipantState& state) {
  return first_non_finite(state.values, "saved state value");
}

}  // namespace railcosim::remote
