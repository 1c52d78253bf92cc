#include "fmu.hpp"

#include <dlfcn.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

#include "fmi_api.hpp"
#include "fmu_api_table.hpp"
#include "fmu_error.hpp"

namespace railcosim::fmu {
namespace fs = std::filesystem;

// The FMU's log callbacks: the last message is kept for the next error.
struct LogSink {
  static void fmi2_log(fmi2::ComponentEnvironment env, fmi2::String, fmi2::Status,
                       fmi2::String category, fmi2::String format, ...) {
    if (env == nullptr || format == nullptr) return;
    char text[1024];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    keep(env, category, text);
  }
  static void fmi3_log(fmi3::InstanceEnvironment env, fmi3::Status, fmi3::String category,
                       fmi3::String message) {
    if (env != nullptr && message != nullptr) keep(env, category, message);
  }
  static void keep(void* env, const char* category, const char* text) {
    std::string& log = static_cast<Fmu*>(env)->last_log_;
    log = std::string(category ? category : "") + (category ? ": " : "") + text;
    if (log.size() > 1024) log.resize(1024);
  }
};

namespace {

void* fmi2_allocate(std::size_t count, std::size_t size) {
  return std::calloc(count, size);
}

const char* status_name(int s) {
  static const char* names[] = {"OK", "Warning", "Discard", "Error", "Fatal", "Pending"};
  return s >= 0 && s <= 5 ? names[s] : "an unknown status";
}

std::string format_time(double t) {
  char text[64];
  std::snprintf(text, sizeof text, "%.9g", t);
  return text;
}

// Opens the binary for this platform, or names the platforms the FMU has.
void* open_binary(const std::string& name, const fs::path& root, const ModelDescription& d) {
  const fs::path so = root / "binaries" / platform_folder(d.version) / (d.model_identifier + ".so");
  std::error_code ec;
  if (!fs::is_regular_file(so, ec)) {
    std::string present;
    for (const auto& e : fs::directory_iterator(root / "binaries", ec))
      present += (present.empty() ? "" : ", ") + e.path().filename().string();
    throw FmuError(name + ": no binary for this platform (binaries/" + platform_folder(d.version) +
                   "/" + d.model_identifier +
                   ".so); the FMU has binaries for: " + (present.empty() ? "none" : present));
  }
  void* lib = ::dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (lib == nullptr)
    throw FmuError(name + ": cannot load binaries/" + platform_folder(d.version) + "/" +
                   d.model_identifier + ".so: " + ::dlerror());
  return lib;
}

template <class F>
void resolve(void* lib, const std::string& name, const char* symbol, F& out, bool required) {
  out = reinterpret_cast<F>(::dlsym(lib, symbol));
  if (out == nullptr && required) throw FmuError(name + ": its binary does not export " + symbol);
}

}  // namespace

const char* platform_folder(FmiVersion v) {
  return v == FmiVersion::k2 ? "linux64" : "x86_64-linux";
}

FmuState::~FmuState() {
  if (state_ != nullptr && owner_ != nullptr) owner_->free_state(state_);
}

FmuState& FmuState::operator=(FmuState&& o) noexcept {
  if (this != &o) {
    if (state_ != nullptr && owner_ != nullptr) owner_->free_state(state_);
    owner_ = o.owner_;
    state_ = o.state_;
    o.state_ = nullptr;
  }
  return *this;
}

Fmu::Fmu(const fs::path& file, const ArchiveLimits& limits)
    : name_(file.filename().string()),
      archive_(file, limits),
      description_(read_model_description(archive_.root() / "modelDescription.xml")),
      api_(std::make_unique<Api>()) {
  library_ = open_binary(name_, archive_.root(), description_);
  const bool state = description_.capabilities.can_get_and_set_state;
  try {
    if (version() == FmiVersion::k2) {
      auto& f = api_->v2;
      resolve(library_, name_, "fmi2Instantiate", f.instantiate, true);
      resolve(library_, name_, "fmi2FreeInstance", f.free_instance, true);
      resolve(library_, name_, "fmi2SetupExperiment", f.setup_experiment, true);
      resolve(library_, name_, "fmi2EnterInitializationMode", f.enter_initialization, true);
      resolve(library_, name_, "fmi2ExitInitializationMode", f.exit_initialization, true);
      resolve(library_, name_, "fmi2Terminate", f.terminate, true);
      resolve(library_, name_, "fmi2SetReal", f.set_real, true);
      resolve(library_, name_, "fmi2GetReal", f.get_real, true);
      resolve(library_, name_, "fmi2GetInteger", f.get_integer, false);
      resolve(library_, name_, "fmi2GetBoolean", f.get_boolean, false);
      resolve(library_, name_, "fmi2GetRealStatus", f.get_real_status, false);
      resolve(library_, name_, "fmi2GetBooleanStatus", f.get_boolean_status, false);
      resolve(library_, name_, "fmi2SetRealInputDerivatives", f.set_real_input_derivatives,
              description_.capabilities.can_interpolate_inputs);
      resolve(library_, name_, "fmi2DoStep", f.do_step, true);
      resolve(library_, name_, "fmi2GetFMUstate", f.get_state, state);
      resolve(library_, name_, "fmi2SetFMUstate", f.set_state, state);
      resolve(library_, name_, "fmi2FreeFMUstate", f.free_state, state);
      f.callbacks = {&LogSink::fmi2_log, &fmi2_allocate, &std::free, nullptr, this};
    } else {
      auto& f = api_->v3;
      resolve(library_, name_, "fmi3InstantiateCoSimulation", f.instantiate, true);
      resolve(library_, name_, "fmi3FreeInstance", f.free_instance, true);
      resolve(library_, name_, "fmi3EnterInitializationMode", f.enter_initialization, true);
      resolve(library_, name_, "fmi3ExitInitializationMode", f.exit_initialization, true);
      resolve(library_, name_, "fmi3Terminate", f.terminate, true);
      resolve(library_, name_, "fmi3SetFloat64", f.set_float64, true);
      resolve(library_, name_, "fmi3GetFloat64", f.get_float64, true);
      resolve(library_, name_, "fmi3GetFloat32", f.get_float32, false);
      resolve(library_, name_, "fmi3GetInt32", f.get_int32, false);
      resolve(library_, name_, "fmi3GetInt64", f.get_int64, false);
      resolve(library_, name_, "fmi3GetInt8", f.get_int8, false);
      resolve(library_, name_, "fmi3GetUInt8", f.get_uint8, false);
      resolve(library_, name_, "fmi3GetInt16", f.get_int16, false);
      resolve(library_, name_, "fmi3GetUInt16", f.get_uint16, false);
      resolve(library_, name_, "fmi3GetUInt32", f.get_uint32, false);
      resolve(library_, name_, "fmi3GetUInt64", f.get_uint64, false);
      resolve(library_, name_, "fmi3GetBoolean", f.get_boolean, false);
      resolve(library_, name_, "fmi3DoStep", f.do_step, true);
      resolve(library_, name_, "fmi3GetFMUState", f.get_state, state);
      resolve(library_, name_, "fmi3SetFMUState", f.set_state, state);
      resolve(library_, name_, "fmi3FreeFMUState", f.free_state, state);
    }
  } catch (...) {
    ::dlclose(library_);
    throw;
  }
}

Fmu::~Fmu() {
  if (instance_ != nullptr) {
    if (version() == FmiVersion::k2)
      api_->v2.free_instance(instance_);
    else
      api_->v3.free_instance(instance_);
  }
  ::dlclose(library_);
}

void Fmu::check(int status, const char* function) const {
  if (status == 0) return;
  throw FmuError("FMU " + name_ + ": " + function + " at t = " + format_time(time_) +
                 " s returned " + status_name(status) +
                 (last_log_.empty() ? std::string() : " (its log: " + last_log_ + ")"));
}

void Fmu::need_instance(const char* function) const {
  if (instance_ == nullptr)
    throw FmuError("FMU " + name_ + ": " + function + " called before instantiate()");
}

void Fmu::instantiate(const std::string& instance_name) {
  if (instance_ != nullptr) throw FmuError("FMU " + name_ + ": instantiated twice");
  const fs::path resources = archive_.root() / "resources";
  if (version() == FmiVersion::k2) {
    const std::string uri = "file://" + resources.string();
    instance_ =
        api_->v2.instantiate(instance_name.c_str(), fmi2::kCoSimulation, description_.token.c_str(),
                             uri.c_str(), &api_->v2.callbacks, 0, 0);
  } else {
    const std::string path = resources.string() + "/";
    instance_ =
        api_->v3.instantiate(instance_name.c_str(), description_.token.c_str(), path.c_str(), false,
                             false, false, false, nullptr, 0, this, &LogSink::fmi3_log, nullptr);
  }
  if (instance_ == nullptr)
    throw FmuError(
        "FMU " + name_ + ": " +
        (version() == FmiVersion::k2 ? "fmi2Instantiate" : "fmi3InstantiateCoSimulation") +
        " returned no instance" +
        (last_log_.empty() ? std::string() : " (its log: " + last_log_ + ")"));
}

void Fmu::setup(double start, std::optional<double> stop, std::optional<double> tolerance) {
  need_instance("setup");
  time_ = start;
  stop_ = stop;
  tolerance_ = tolerance;
  if (version() == FmiVersion::k2)
    check(api_->v2.setup_experiment(instance_, tolerance ? 1 : 0, tolerance.value_or(0), start,
                                    stop ? 1 : 0, stop.value_or(0)),
          "fmi2SetupExperiment");
}

void Fmu::enter_initialization() {
  need_instance("enter_initialization");
  if (version() == FmiVersion::k2)
    return check(api_->v2.enter_initialization(instance_), "fmi2EnterInitializationMode");
  check(api_->v3.enter_initialization(instance_, tolerance_.has_value(), tolerance_.value_or(0),
                                      time_, stop_.has_value(), stop_.value_or(0)),
        "fmi3EnterInitializationMode");
}

void Fmu::exit_initialization() {
  need_instance("exit_initialization");
  if (version() == FmiVersion::k2)
    return check(api_->v2.exit_initialization(instance_), "fmi2ExitInitializationMode");
  check(api_->v3.exit_initialization(instance_), "fmi3ExitInitializationMode");
}

void Fmu::set_real(const std::vector<std::uint32_t>& refs, const std::vector<double>& values) {
  need_instance("set_real");
  if (refs.size() != values.size())
    throw FmuError("FMU " + name_ + ": set_real given " + std::to_string(refs.size()) +
                   " references and " + std::to_string(values.size()) + " values");
  if (version() == FmiVersion::k2) {
    const std::vector<fmi2::ValueReference> r(refs.begin(), refs.end());
    return check(api_->v2.set_real(instance_, r.data(), r.size(), values.data()), "fmi2SetReal");
  }
  check(api_->v3.set_float64(instance_, refs.data(), refs.size(), values.data(), values.size()),
        "fmi3SetFloat64");
}

void Fmu::set_input_slopes(const std::vector<std::uint32_t>& refs,
                           const std::vector<double>& slopes) {
  need_instance("set_input_slopes");
  if (!interpolates_inputs())
    throw FmuError("FMU " + name_ +
                   ": it does not interpolate its inputs (canInterpolateInputs is not true)");
  if (refs.size() != slopes.size())
    throw FmuError("FMU " + name_ + ": set_input_slopes given " + std::to_string(refs.size()) +
                   " references and " + std::to_string(slopes.size()) + " values");
  const std::vector<fmi2::ValueReference> r(refs.begin(), refs.end());
  const std::vector<fmi2::Integer> order(refs.size(), 1);
  check(api_->v2.set_real_input_derivatives(instance_, r.data(), r.size(), order.data(),
                                            slopes.data()),
        "fmi2SetRealInputDerivatives");
}

std::vector<double> Fmu::get_real(const std::vector<std::uint32_t>& refs) {
  need_instance("get_real");
  std::vector<double> values(refs.size());
  if (version() == FmiVersion::k2) {
    const std::vector<fmi2::ValueReference> r(refs.begin(), refs.end());
    check(api_->v2.get_real(instance_, r.data(), r.size(), values.data()), "fmi2GetReal");
  } else {
    check(api_->v3.get_float64(instance_, refs.data(), refs.size(), values.data(), values.size()),
          "fmi3GetFloat64");
  }
  return values;
}

void Fmu::do_step(double t, double h) {
  need_instance("do_step");
  time_ = t;
  if (version() == FmiVersion::k2) {
    const int status = api_->v2.do_step(instance_, t, h, 0);
    fmi2::Boolean ended = 0;
    fmi2::Real last = t;
    if (status == fmi2::kDiscard && api_->v2.get_boolean_status != nullptr &&
        api_->v2.get_boolean_status(instance_, fmi2::kTerminated, &ended) == fmi2::kOK && ended) {
      if (api_->v2.get_real_status != nullptr)
        api_->v2.get_real_status(instance_, fmi2::kLastSuccessfulTime, &last);
      time_ = last;
      throw FmuTerminated("FMU " + name_ + ": ended the simulation at t = " + format_time(last) +
                              " s (fmi2DoStep from t = " + format_time(t) + " s: fmi2Discard)",
                          last);
    }
    check(status, "fmi2DoStep");
  } else {
    fmi3::Boolean event = false, stop = false, early = false;
    fmi3::Float64 reached = t;
    check(api_->v3.do_step(instance_, t, h, false, &event, &stop, &early, &reached), "fmi3DoStep");
    if (stop) {
      time_ = reached;
      throw FmuTerminated("FMU " + name_ + ": ended the simulation at t = " + format_time(reached) +
                              " s (fmi3DoStep from t = " + format_time(t) +
                              " s: terminateSimulation)",
                          reached);
    }
    if (early)
      throw FmuError("FMU " + name_ + ": fmi3DoStep at t = " + format_time(t) +
                     " s returned early at t = " + format_time(reached) +
                     " s, which the host did not allow");
  }
  time_ = t + h;
}

FmuState Fmu::get_state() {
  need_instance("get_state");
  if (!description_.capabilities.can_get_and_set_state)
    throw FmuError("FMU " + name_ + " cannot save its state (its description does not say " +
                   (version() == FmiVersion::k2 ? "canGetAndSetFMUstate" : "canGetAndSetFMUState") +
                   "=\"true\")");
  FmuState s;
  s.owner_ = this;
  if (version() == FmiVersion::k2)
    check(api_->v2.get_state(instance_, &s.state_), "fmi2GetFMUstate");
  else
    check(api_->v3.get_state(instance_, &s.state_), "fmi3GetFMUState");
  return s;
}

void Fmu::set_state(const FmuState& state) {
  need_instance("set_state");
  if (state.owner_ != this || state.state_ == nullptr)
    throw FmuError("FMU " + name_ + ": set_state given a state it did not save");
  if (version() == FmiVersion::k2)
    check(api_->v2.set_state(instance_, state.state_), "fmi2SetFMUstate");
  else
    check(api_->v3.set_state(instance_, state.state_), "fmi3SetFMUState");
}

void Fmu::free_state(void* state) noexcept {
  if (instance_ == nullptr) return;
  if (version() == FmiVersion::k2)
    api_->v2.free_state(instance_, &state);
  else
    api_->v3.free_state(instance_, &state);
}

void Fmu::terminate() {
  need_instance("terminate");
  if (terminated_) return;
  terminated_ = true;
  if (version() == FmiVersion::k2) return check(api_->v2.terminate(instance_), "fmi2Terminate");
  check(api_->v3.terminate(instance_), "fmi3Terminate");
}

}  // namespace railcosim::fmu
