// An FMU's modelDescription.xml, as far as a co-simulation host needs it:
// the FMI version (2.0 or 3.0), the co-simulation interface and its
// capabilities, the variables and the default experiment. A description is
// refused when it offers no co-simulation, when its counts exceed the
// bounds below, or when it lies about its variables (two with one value
// reference, or a reference to a variable that does not exist).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace railcosim::fmu {

enum class FmiVersion { k2, k3 };
const char* version_name(FmiVersion v);  // "2.0", "3.0"

// What the co-simulation interface says it can do (false or 0 when the
// description does not say).
struct Capabilities {
  bool can_get_and_set_state = false;             // canGetAndSetFMU[sS]tate
  bool can_handle_variable_step = false;          // canHandleVariableCommunicationStepSize
  bool can_interpolate_inputs = false;            // FMI 2 canInterpolateInputs
  int max_output_derivative_order = 0;            // maxOutputDerivativeOrder
  bool provides_directional_derivatives = false;  // providesDirectionalDerivative(s)
  bool can_serialize_state = false;               // canSerializeFMU[sS]tate
  bool needs_execution_tool = false;              // needsExecutionTool
  std::optional<double> fixed_internal_step;      // FMI 3 fixedInternalStepSize
};

struct Variable {
  std::string name;
  std::uint32_t value_reference = 0;
  std::string causality = "local";  // parameter, input, output, local, ...
  std::string variability = "continuous";
  std::string type;             // "Real" (FMI 2), "Float64" (FMI 3), or another type
  std::optional<double> start;  // for a Real/Float64 with a start value
  std::string unit;             // empty when none is declared
  bool is_real() const { return type == "Real" || type == "Float64"; }
  // FMI 3 arrays: per <Dimension>, its size given (start) or the value
  // reference of the structural parameter that holds it. Empty: a scalar.
  struct Dimension {
    std::optional<std::uint64_t> start;
    std::optional<std::uint32_t> value_reference;
  };
  std::vector<Dimension> dimensions;
};

struct DefaultExperiment {
  std::optional<double> start_time, stop_time, tolerance, step_size;
};

// Bounds on what a description may declare, checked as it is read.
struct DescriptionLimits {
  std::uint64_t max_file_bytes = std::uint64_t{64} << 20;  // modelDescription.xml: 64 MiB
  std::size_t max_variables = 100000;
  std::size_t max_name_bytes = 1024;
};

struct ModelDescription {
  FmiVersion version = FmiVersion::k2;
  std::string model_name;
  std::string token;  // FMI 2 guid, FMI 3 instantiationToken
  std::string model_identifier;
  Capabilities capabilities;
  std::vector<Variable> variables;
  DefaultExperiment default_experiment;

  // The variable of that name, or nullptr.
  const Variable* find(const std::string& name) const;
};

// Reads `file` (the unpacked FMU's modelDescription.xml); throws FmuError
// naming the file, the element and what is wrong.
ModelDescription read_model_description(const std::filesystem::path& file,
                                        const DescriptionLimits& limits = {});
// The same from text; `where` names it in errors.
ModelDescription parse_model_description(const std::string& text, const std::string& where,
                                         const DescriptionLimits& limits = {});

// The record of the default experiment's outputs an FMU carries under the
// FMI layered standard for reference results: the `Related` entry of role
// "result" and type text/csv in extra/org.fmi-standard.fmi-ls-ref/
// fmi-ls-manifest.xml of the unpacked FMU at `root`; its path, or nothing
// when the FMU carries none. A source that is not a plain file name in that
// folder is refused (FmuError).
std::optional<std::filesystem::path> reference_result(const std::filesystem::path& root);

}  // namespace railcosim::fmu
