// One FMU loaded into this process: unpacked into a private folder, its
// description read, its binary for this platform opened and its functions
// resolved. `Fmu` is the same small API for FMI 2.0 and 3.0 co-simulation;
// every FMI status other than OK is an FmuError naming the FMU, the
// function and the time. An FMU is native code that runs with the user's
// rights: load only FMUs you would run as a program.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "archive.hpp"
#include "description.hpp"

namespace railcosim::fmu {

// Where an FMU of that version keeps its Linux x86_64 binary, under binaries/.
const char* platform_folder(FmiVersion v);  // "linux64", "x86_64-linux"

class Fmu;

// A state saved by Fmu::get_state, freed by the FMU when it goes.
class FmuState {
 public:
  FmuState() = default;
  ~FmuState();
  FmuState(FmuState&& o) noexcept : owner_(o.owner_), state_(o.state_) { o.state_ = nullptr; }
  FmuState& operator=(FmuState&& o) noexcept;
  FmuState(const FmuState&) = delete;
  FmuState& operator=(const FmuState&) = delete;
  bool empty() const { return state_ == nullptr; }

 private:
  friend class Fmu;
  Fmu* owner_ = nullptr;
  void* state_ = nullptr;
};

class Fmu {
 public:
  // Unpacks `file`, reads its description and loads its binary (not yet
  // instantiated). Throws FmuError for any refusal.
  explicit Fmu(const std::filesystem::path& file, const ArchiveLimits& limits = {});
  ~Fmu();
  Fmu(const Fmu&) = delete;
  Fmu& operator=(const Fmu&) = delete;

  const ModelDescription& description() const { return description_; }
  // The folder the FMU is unpacked into (removed with the Fmu).
  const std::filesystem::path& root() const { return archive_.root(); }
  FmiVersion version() const { return description_.version; }
  // The FMU's file name, as errors name it.
  const std::string& name() const { return name_; }
  // The time of the last call that set it (setup, do_step, set_state).
  double time() const { return time_; }

  void instantiate(const std::string& instance_name);
  // The experiment: start time and, where given, stop time and tolerance
  // (FMI 2 fmi2SetupExperiment; FMI 3 passes them at initialization).
  void setup(double start, std::optional<double> stop = std::nullopt,
             std::optional<double> tolerance = std::nullopt);
  void enter_initialization();
  void exit_initialization();
  // Real (FMI 2) / Float64 (FMI 3) values by value reference.
  void set_real(const std::vector<std::uint32_t>& refs, const std::vector<double>& values);
  std::vector<double> get_real(const std::vector<std::uint32_t>& refs);
  // Whether the FMU follows its inputs' time derivatives over a step (FMI 2
  // canInterpolateInputs; FMI 3 co-simulation has no input derivatives).
  bool interpolates_inputs() const { return description_.capabilities.can_interpolate_inputs; }
  // The first time derivative of these real inputs from the current
  // communication point on (fmi2SetRealInputDerivatives, order 1): the FMU
  // ramps them over the next step. Refused unless interpolates_inputs().
  void set_input_slopes(const std::vector<std::uint32_t>& refs, const std::vector<double>& slopes);
  // One scalar of any type the host reads (readable()), as a double: Real,
  // Integer, Enumeration, Boolean (0 or 1) in FMI 2; Float64, Float32, the
  // signed and unsigned integers of 8 to 64 bits, Enumeration, Boolean in
  // FMI 3. Throws FmuError for another
  // type or a getter the binary does not export.
  double get_value(const Variable& v);
  // Every value of a variable: one for a scalar, the array's in its order
  // (FMI 3 arrays; the sizes of their dimensions read where a structural
  // parameter holds them, at most 10,000,000 values).
  std::vector<double> get_values(const Variable& v);
  static bool readable(FmiVersion version, const std::string& type);
  // One communication step from t to t + h.
  void do_step(double t, double h);
  // State save and restore; refused with a message when the FMU's
  // description does not offer them.
  FmuState get_state();
  void set_state(const FmuState& state);
  void terminate();

  struct Api;  // the resolved functions of either version (fmu.cpp)

 private:
  friend class FmuState;
  void free_state(void* state) noexcept;
  void check(int status, const char* function) const;
  void need_instance(const char* function) const;
  std::size_t array_size(const Variable& v);

  std::string name_;
  UnpackedArchive archive_;
  ModelDescription description_;
  void* library_ = nullptr;
  std::unique_ptr<Api> api_;
  void* instance_ = nullptr;
  std::optional<double> stop_, tolerance_;
  double time_ = 0;
  bool terminated_ = false;
  std::string last_log_;  // the FMU's last log message, for errors
  friend struct LogSink;
};

}  // namespace railcosim::fmu
