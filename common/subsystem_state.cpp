// A subsystem's checkpoint: its whole state as one vector of numbers
// (save), and back (restore), for implicit coupling and the node's Save and
// Restore requests.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "subsystem.hpp"
#include "subsystem_motion.hpp"

namespace railcosim {

namespace {

void put(std::vector<double>& out, const std::vector<double>& v) {
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.begin(), v.end());
}
void put(std::vector<double>& out, const Vector& v) {
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.data(), v.data() + v.size());
}

class Cursor {
 public:
  Cursor(const std::vector<double>& v, const std::string& who) : v_(v), who_(who) {}
  double next() {
    if (i_ >= v_.size()) throw BadInputError(who_ + ": restore() rejected: the state is truncated");
    return v_[i_++];
  }
  std::size_t count(std::size_t limit) {
    const double c = next();
    if (!(c >= 0 && c <= static_cast<double>(limit)))
      throw BadInputError(who_ + ": restore() rejected: the state does not fit this subsystem");
    return static_cast<std::size_t>(c);
  }
  std::vector<double> vec(std::size_t limit) {
    const std::size_t n = count(limit);
    std::vector<double> out(n);
    for (auto& x : out) x = next();
    return out;
  }
  bool done() const { return i_ == v_.size(); }

 private:
  const std::vector<double>& v_;
  std::string who_;
  std::size_t i_ = 0;
};

}  // namespace

ParticipantState Subsystem::save() {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "save()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  const NewmarkState& s = newmark_->state();
  ParticipantState st;
  auto& o = st.values;
  o.push_back(static_cast<double>(next_step_));
  o.push_back(phase_ == Phase::kInputsSet ? 1.0 : 0.0);
  o.push_back(static_cast<double>(s.level));
  o.push_back(static_cast<double>(s.micro_steps));
  o.push_back(static_cast<double>(s.rejected_steps));
  o.push_back(s.contact_force);
  put(o, s.u);
  put(o, s.v);
  put(o, s.a);
  o.push_back(ramp_ ? 1.0 : 0.0);
  for (const CouplingData* held : {&held_, &held_end_})
    for (const InterfaceData& h : *held) {
      put(o, h.displacement);
      put(o, h.velocity);
      put(o, h.force);
    }
  return st;
}

void Subsystem::restore(const ParticipantState& state) {
  require(phase_ != Phase::kCreated && phase_ != Phase::kStepping, "restore()",
          phase_ == Phase::kCreated ? "initialize() must come first" : "a step is in progress");
  Cursor c(state.values, name());
  // Counts are checked before they are converted: any double may arrive.
  constexpr std::size_t kMaxCount = std::size_t{1} << 53;
  const auto step = static_cast<long>(c.count(kMaxCount));
  const bool inputs_set = c.next() != 0.0;
  const auto level = static_cast<int>(c.count(Newmark::kMaxLevel));
  const auto micro = static_cast<long>(c.count(kMaxCount));
  const auto rejected = static_cast<long>(c.count(kMaxCount));
  const double force = c.next();
  const auto n = static_cast<std::size_t>(sys_.layout.size);
  const std::vector<double> u = c.vec(n), v = c.vec(n), a = c.vec(n);
  const bool ramp = c.next() != 0.0;
  CouplingData held(points_.size()), held_end(points_.size());
  for (CouplingData* h : {&held, &held_end})
    for (std::size_t j = 0; j < points_.size(); ++j) {
      const auto N = static_cast<std::size_t>(points_[j]);
      (*h)[j] = {c.vec(N), c.vec(N), c.vec(N)};
    }
  if (!c.done() || u.size() != n || v.size() != n || a.size() != n || step < 0 || level < 0 ||
      level > Newmark::kMaxLevel)
    throw BadInputError(name() + ": restore() rejected: the state does not fit this subsystem");
  // The inputs of the step being set up, or of the step last taken.
  const long ramp_step = inputs_set ? step : std::max(0L, step - 1);
  apply_inputs(held, ramp ? &held_end : nullptr, time(ramp_step));
  NewmarkState& s = newmark_->state();
  s.u = Eigen::Map<const Vector>(u.data(), static_cast<Eigen::Index>(n));
  s.v = Eigen::Map<const Vector>(v.data(), static_cast<Eigen::Index>(n));
  s.a = Eigen::Map<const Vector>(a.data(), static_cast<Eigen::Index>(n));
  s.level = level;
  s.micro_steps = micro;
  s.rejected_steps = rejected;
  s.contact_force = force;
  next_step_ = step;
  phase_ = inputs_set ? Phase::kInputsSet : Phase::kAwaitingInputs;
}

namespace {

// Where the motion (u, v, a) sits in a Subsystem's snapshot (see save()):
// after six header values, three counted vectors of n values each.
std::size_t motion_size(const ParticipantState& state) {
  constexpr std::size_t kHeader = 6;
  if (state.values.size() < kHeader + 1)
    throw BadInputError("not a subsystem's snapshot: " + std::to_string(state.values.size()) +
                        " values");
  const double n = state.values[kHeader];
  if (!(n >= 0) || state.values.size() < kHeader + 3 * (static_cast<std::size_t>(n) + 1))
    throw BadInputError("not a subsystem's snapshot: its motion does not fit");
  return static_cast<std::size_t>(n);
}

}  // namespace

std::vector<double> snapshot_motion(const ParticipantState& state) {
  const std::size_t n = motion_size(state);
  std::vector<double> m;
  m.reserve(3 * n);
  for (std::size_t k = 0; k < 3; ++k) {
    const auto at = state.values.begin() + static_cast<std::ptrdiff_t>(7 + k * (n + 1));
    m.insert(m.end(), at, at + static_cast<std::ptrdiff_t>(n));
  }
  return m;
}

void set_snapshot_motion(ParticipantState& state, const std::vector<double>& motion) {
  const std::size_t n = motion_size(state);
  if (motion.size() != 3 * n)
    throw BadInputError("set_snapshot_motion: " + std::to_string(motion.size()) +
                        " values for a motion of " + std::to_string(3 * n));
  for (std::size_t k = 0; k < 3; ++k)
    std::copy(motion.begin() + static_cast<std::ptrdiff_t>(k * n),
              motion.begin() + static_cast<std::ptrdiff_t>((k + 1) * n),
              state.values.begin() + static_cast<std::ptrdiff_t>(7 + k * (n + 1)));
}

}  // namespace railcosim
