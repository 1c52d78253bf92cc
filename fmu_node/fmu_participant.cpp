#include "fmu_participant.hpp"

#include <cmath>
#include <filesystem>
#include <set>

#include "fmu_error.hpp"

namespace railcosim {
namespace {

const char* unit_of(Quantity q) {
  return q == Quantity::kDisplacement ? "m" : q == Quantity::kVelocity ? "m/s" : "N";
}

// The variable name of point i: "{i}" in the pattern replaced by i.
std::string name_at(const std::string& pattern, std::size_t i) {
  const auto at = pattern.find("{i}");
  if (at == std::string::npos) return pattern;
  return pattern.substr(0, at) + std::to_string(i) + pattern.substr(at + 3);
}

std::vector<double>& values_of(InterfaceData& d, Quantity q) {
  return q == Quantity::kDisplacement ? d.displacement
         : q == Quantity::kVelocity   ? d.velocity
                                      : d.force;
}
const std::vector<double>& values_of(const InterfaceData& d, Quantity q) {
  return values_of(const_cast<InterfaceData&>(d), q);
}

std::filesystem::path fmu_file(const OwnConfig& config) {
  std::filesystem::path file = config.string("file");
  std::error_code ec;
  const std::filesystem::path source = config.source();
  if (file.is_relative() && std::filesystem::is_regular_file(source, ec))
    file = source.parent_path() / file;
  return file;
}

}  // namespace

FmuParticipant::FmuParticipant(const ParticipantSetup& setup) {
  const OwnConfig& config = setup.config;
  if (config.empty())
    throw BadRequestError(
        "the FMU participant needs its configuration: --config FILE with a "
        "table naming the FMU (file = \"NAME.fmu\") and its variables");
  try {
    fmu_ = std::make_unique<fmu::Fmu>(fmu_file(config));
  } catch (const fmu::FmuError& e) {
    throw BadRequestError(config.where("file") + ": " + e.what());
  }
  macro_step_ = setup.run.macro_step;
  interfaces_ = setup.interfaces.size();
  map_ports(setup);
  set_parameters(config);
  declare_channels(config);
}

FmuParticipant::~FmuParticipant() = default;

std::string FmuParticipant::name() const {
  return "FMU " + fmu_->name();
}

void FmuParticipant::map_ports(const ParticipantSetup& setup) {
  const OwnConfig& config = setup.config;
  std::set<std::string> known{"file", "peak_history"};
  // The scene's own [soil] table (model = "external") may carry the mapping.
  if (config.has("model")) {
    if (config.string("model") != "external")
      throw BadRequestError(config.where("model") + ": \"" + config.string("model") +
                            "\": an FMU is the scene's soil as model = \"external\"");
    known.insert("model");
  }
  for (std::size_t k = 0; k < setup.interfaces.size(); ++k) {
    const Interface& itf = setup.interfaces[k];
    for (bool in : {true, false}) {
      for (Quantity q : in ? itf.receives : itf.sends) {
        const std::string key = itf.cut + (in ? "_in_" : "_out_") + to_string(q);
        known.insert(key);
        const std::string pattern = config.string(key);
        if (itf.n() > 1 && pattern.find("{i}") == std::string::npos)
          throw BadRequestError(config.where(key) + ": \"" + pattern +
                                "\" names one variable "
                                "for " +
                                std::to_string(itf.n()) +
                                " coupling points: put {i} "
                                "where the point's number goes");
        Port port{k, q, {}};
        for (std::size_t i = 0; i < itf.n(); ++i) {
          const std::string var_name = name_at(pattern, i);
          const fmu::Variable* v = fmu_->description().find(var_name);
          const std::string causality = in ? "input" : "output";
          if (v == nullptr)
            throw BadRequestError(config.where(key) + ": the FMU has no variable '" + var_name +
                                  "'");
          if (!v->is_real() || v->causality != causality)
            throw BadRequestError(config.where(key) + ": variable '" + var_name + "' is " +
                                  v->causality + " (" + v->type + "), not a real " + causality);
          if (!v->unit.empty() && v->unit != unit_of(q))
            throw BadRequestError(config.where(key) + ": variable '" + var_name + "' is in " +
                                  v->unit + ", the interface's " + to_string(q) + " in " +
                                  unit_of(q));
          port.refs.push_back(v->value_reference);
        }
        (in ? inputs_ : outputs_).push_back(std::move(port));
      }
    }
  }
  for (const std::string& key : config.keys())
    if (!known.count(key) && key.rfind("set_", 0) != 0 && key.rfind("result_", 0) != 0 &&
        key.rfind("history_", 0) != 0)
      throw BadRequestError(
          config.where(key) +
          ": not a key of the FMU participant (file, "
          "CUT_in_QUANTITY and CUT_out_QUANTITY of its interfaces, set_NAME, "
          "peak_history, history_NAME, result_NAME; model = \"external\" in a scene)");
}

void FmuParticipant::set_parameters(const OwnConfig& config) {
  for (const std::string& key : config.keys()) {
    if (key.rfind("set_", 0) != 0) continue;
    const std::string var_name = key.substr(4);
    const fmu::Variable* v = fmu_->description().find(var_name);
    if (v == nullptr || !v->is_real() || v->causality != "parameter")
      throw BadRequestError(config.where(key) + ": the FMU has no real parameter '" + var_name +
                            "'");
    parameters_.emplace_back(v->value_reference, config.number(key));
  }
}

void FmuParticipant::declare_channels(const OwnConfig& config) {
  if (config.has("peak_history")) {
    channels_.history.push_back(config.string("peak_history"));
    peak_history_ = true;
  }
  for (const std::string& key : config.keys()) {
    if (key.rfind("history_", 0) != 0) continue;
    const fmu::Variable* v = fmu_->description().find(config.string(key));
    if (v == nullptr || !v->is_real())
      throw BadRequestError(config.where(key) + ": the FMU has no real variable '" +
                            config.string(key) + "'");
    channels_.history.push_back(key.substr(8));
    history_refs_.push_back(v->value_reference);
  }
  const auto& variables = fmu_->description().variables;
  for (const std::string& key : config.keys()) {
    if (key.rfind("result_", 0) != 0) continue;
    const std::string pattern = config.string(key);
    std::vector<std::uint32_t> refs;
    for (std::size_t i = 0; i <= variables.size(); ++i) {
      const fmu::Variable* v = fmu_->description().find(name_at(pattern, i));
      if (v == nullptr || !v->is_real()) break;
      refs.push_back(v->value_reference);
      if (pattern.find("{i}") == std::string::npos) break;
    }
    if (refs.empty())
      throw BadRequestError(config.where(key) + ": the FMU has no real variable '" +
                            name_at(pattern, 0) + "'");
    channels_.results.push_back(key.substr(7));
    result_refs_.push_back(std::move(refs));
  }
}

void FmuParticipant::enter_initialization() {
  if (in_initialization_) return;
  fmu_->instantiate("railcosim");
  fmu_->setup(0.0);
  for (const auto& [ref, value] : parameters_) fmu_->set_real({ref}, {value});
  fmu_->enter_initialization();
  in_initialization_ = true;
}

void FmuParticipant::check_inputs(long n, const CouplingData& inputs) const {
  if (n != next_ && next_ >= 0)
    throw CallOrderError(name() + ": inputs for step " + std::to_string(n) + ", at step " +
                         std::to_string(next_));
  if (inputs.size() != interfaces_)
    throw BadInputError(name() + ": inputs of " + std::to_string(inputs.size()) +
                        " interfaces, expected " + std::to_string(interfaces_));
  for (const Port& p : inputs_) {
    const std::vector<double>& v = values_of(inputs[p.interface], p.quantity);
    if (v.size() != p.refs.size())
      throw BadInputError(name() + ": " + std::to_string(v.size()) + " values of " +
                          to_string(p.quantity) + ", expected " + std::to_string(p.refs.size()));
    for (double x : v)
      if (!std::isfinite(x)) throw BadInputError(name() + ": an input is not finite");
  }
}

void FmuParticipant::set_inputs(long n, const CouplingData& inputs) {
  check_inputs(n, inputs);
  for (const Port& p : inputs_) {
    fmu_->set_real(p.refs, values_of(inputs[p.interface], p.quantity));
    // Held: an FMU that follows input derivatives is told they are zero
    // (a ramp of an earlier step, or of a restored state, ends here).
    if (fmu_->interpolates_inputs() && next_ >= 0)
      fmu_->set_input_slopes(p.refs, std::vector<double>(p.refs.size(), 0.0));
  }
}

void FmuParticipant::set_inputs(long n, const CouplingData& start, const CouplingData& end) {
  if (!fmu_->interpolates_inputs())
    throw BadRequestError(
        name() + ": ramped inputs for step " + std::to_string(n) +
        " refused: the FMU does not interpolate its inputs (FMI 2 canInterpolateInputs is not "
        "true; FMI 3 co-simulation has no input derivatives), so it takes held inputs only "
        "(degree 0): run it with --inputs hold");
  if (next_ < 0) throw CallOrderError(name() + ": ramped inputs before initialize()");
  check_inputs(n, start);
  check_inputs(n, end);
  for (const Port& p : inputs_) {
    const std::vector<double>& a = values_of(start[p.interface], p.quantity);
    const std::vector<double>& b = values_of(end[p.interface], p.quantity);
    std::vector<double> slope(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) slope[i] = (b[i] - a[i]) / macro_step_;
    fmu_->set_real(p.refs, a);
    fmu_->set_input_slopes(p.refs, slope);
  }
}

CouplingData FmuParticipant::outputs() {
  CouplingData out(interfaces_);
  for (const Port& p : outputs_) values_of(out[p.interface], p.quantity) = fmu_->get_real(p.refs);
  return out;
}

CouplingData FmuParticipant::statics(const CouplingData& inputs) {
  if (next_ >= 0) throw CallOrderError(name() + ": statics() after initialize()");
  enter_initialization();
  set_inputs(0, inputs);
  return outputs();
}

StepResult FmuParticipant::initialize(const CouplingData& inputs) {
  statics(inputs);
  fmu_->exit_initialization();
  next_ = 0;
  return report();
}

void FmuParticipant::start_step(long n) {
  if (n != next_)
    throw CallOrderError(name() + ": step " + std::to_string(n) + " asked, at step " +
                         std::to_string(next_));
  try {
    fmu_->do_step(static_cast<double>(n) * macro_step_, macro_step_);
  } catch (const fmu::FmuError& e) {
    throw std::runtime_error(std::string(e.what()) + " (macro step " + std::to_string(n) + ")");
  }
  ++steps_;
  ++next_;
}

StepResult FmuParticipant::finish_step() {
  return report();
}

StepResult FmuParticipant::report() {
  StepResult r;
  r.outputs = outputs();
  for (const InterfaceData& d : r.outputs) {
    for (const auto* a : {&d.displacement, &d.velocity, &d.force})
      for (double x : *a) r.finite = r.finite && std::isfinite(x);
    for (double x : d.displacement)
      r.max_abs_displacement = std::max(r.max_abs_displacement, std::abs(x));
  }
  if (peak_history_) r.history = {r.max_abs_displacement};
  if (!history_refs_.empty()) {
    const std::vector<double> h = fmu_->get_real(history_refs_);
    r.history.insert(r.history.end(), h.begin(), h.end());
  }
  return r;
}

ParticipantResults FmuParticipant::results() {
  ParticipantResults r;
  for (const auto& refs : result_refs_) r.fields.push_back(fmu_->get_real(refs));
  r.micro_steps = steps_;
  return r;
}

ParticipantState FmuParticipant::save() {
  if (next_ < 0) throw CallOrderError(name() + ": save() before initialize()");
  fmu::FmuState s;
  try {
    s = fmu_->get_state();
  } catch (const fmu::FmuError& e) {
    throw BadRequestError(std::string(e.what()) + ": explicit coupling only");
  }
  if (states_.size() == kKeptStates) states_.erase(states_.begin());
  const long id = next_state_++;
  states_.emplace(id, std::move(s));
  return {{static_cast<double>(id), static_cast<double>(next_), static_cast<double>(steps_)}};
}

void FmuParticipant::restore(const ParticipantState& state) {
  const auto& v = state.values;
  if (v.size() != 3 || !(v[0] >= 0) || v[0] > 1e15)
    throw BadInputError(name() + ": the state does not fit this participant");
  const auto it = states_.find(static_cast<long>(v[0]));
  if (it == states_.end())
    throw BadInputError(name() + ": state " + std::to_string(static_cast<long>(v[0])) +
                        " is not kept (only the last " + std::to_string(kKeptStates) + " are)");
  fmu_->set_state(it->second);
  next_ = static_cast<long>(v[1]);
  steps_ = static_cast<long>(v[2]);
}

}  // namespace railcosim
