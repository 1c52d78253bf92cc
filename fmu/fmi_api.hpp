// The C types and function signatures of the FMI 2.0 and 3.0 co-simulation
// interface that the host calls, declared here from the published standards
// (Functional Mock-up Interface 2.0.x and 3.0.x, chapters on the C API).
// Only what the host uses is declared; an FMU exports these names with C
// linkage from binaries/<platform>/<modelIdentifier>.so.
#pragma once

#include <cstddef>
#include <cstdint>

namespace railcosim::fmu {

// ---- FMI 2.0 -------------------------------------------------------------
namespace fmi2 {
using Component = void*;
using ComponentEnvironment = void*;
using State = void*;
using ValueReference = unsigned int;
using Real = double;
using Boolean = int;  // fmi2True = 1, fmi2False = 0
using String = const char*;

enum Status : int { kOK = 0, kWarning = 1, kDiscard = 2, kError = 3, kFatal = 4, kPending = 5 };
enum Type : int { kModelExchange = 0, kCoSimulation = 1 };

// The callbacks the host hands the FMU at instantiation (the logger is
// variadic, a printf format and its arguments).
struct CallbackFunctions {
  void (*logger)(ComponentEnvironment, String instance, Status, String category, String message,
                 ...);
  void* (*allocate_memory)(std::size_t count, std::size_t size);
  void (*free_memory)(void*);
  void (*step_finished)(ComponentEnvironment, Status);
  ComponentEnvironment environment;
};

using InstantiateFn = Component (*)(String instance, Type, String guid, String resource_uri,
                                    const CallbackFunctions*, Boolean visible, Boolean logging);
using FreeInstanceFn = void (*)(Component);
using SetupExperimentFn = Status (*)(Component, Boolean tolerance_defined, Real tolerance,
                                     Real start, Boolean stop_defined, Real stop);
using ComponentFn = Status (*)(Component);  // enter/exit initialization, terminate
using SetRealFn = Status (*)(Component, const ValueReference*, std::size_t, const Real*);
using GetRealFn = Status (*)(Component, const ValueReference*, std::size_t, Real*);
using Integer = int;
enum StatusKind : int {
  kDoStepStatus = 0,
  kPendingStatus = 1,
  kLastSuccessfulTime = 2,
  kTerminated = 3
};
using GetRealStatusFn = Status (*)(Component, StatusKind, Real*);
using GetBooleanStatusFn = Status (*)(Component, StatusKind, Boolean*);
using GetIntegerFn = Status (*)(Component, const ValueReference*, std::size_t, Integer*);
// The order-th time derivative of each input at the current communication
// point (canInterpolateInputs: the FMU then follows them over the step).
using SetRealInputDerivativesFn = Status (*)(Component, const ValueReference*, std::size_t,
                                             const Integer* order, const Real* value);
using GetBooleanFn = Status (*)(Component, const ValueReference*, std::size_t, Boolean*);
using DoStepFn = Status (*)(Component, Real t, Real h, Boolean no_set_state_before_t);
using GetStateFn = Status (*)(Component, State*);
using SetStateFn = Status (*)(Component, State);
using FreeStateFn = Status (*)(Component, State*);
}  // namespace fmi2

// ---- FMI 3.0 -------------------------------------------------------------
namespace fmi3 {
using Instance = void*;
using InstanceEnvironment = void*;
using State = void*;
using ValueReference = std::uint32_t;
using Float64 = double;
using Boolean = bool;
using String = const char*;

enum Status : int { kOK = 0, kWarning = 1, kDiscard = 2, kError = 3, kFatal = 4 };

using LogMessageFn = void (*)(InstanceEnvironment, Status, String category, String message);
using IntermediateUpdateFn = void (*)(InstanceEnvironment, Float64 time, Boolean set_requested,
                                      Boolean get_allowed, Boolean step_finished,
                                      Boolean can_return_early, Boolean* early_return_requested,
                                      Float64* early_return_time);

using InstantiateCoSimulationFn = Instance (*)(
    String instance, String token, String resource_path, Boolean visible, Boolean logging,
    Boolean event_mode_used, Boolean early_return_allowed, const ValueReference* intermediate,
    std::size_t n_intermediate, InstanceEnvironment, LogMessageFn, IntermediateUpdateFn);
using FreeInstanceFn = void (*)(Instance);
using EnterInitializationModeFn = Status (*)(Instance, Boolean tolerance_defined, Float64 tolerance,
                                             Float64 start, Boolean stop_defined, Float64 stop);
using InstanceFn = Status (*)(Instance);  // exit initialization, terminate
using SetFloat64Fn = Status (*)(Instance, const ValueReference*, std::size_t, const Float64*,
                                std::size_t n_values);
using GetFloat64Fn = Status (*)(Instance, const ValueReference*, std::size_t, Float64*,
                                std::size_t n_values);
using GetFloat32Fn = Status (*)(Instance, const ValueReference*, std::size_t, float*,
                                std::size_t n_values);
using GetInt32Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::int32_t*,
                              std::size_t n_values);
using GetInt8Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::int8_t*,
                             std::size_t n_values);
using GetUInt8Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::uint8_t*,
                              std::size_t n_values);
using GetInt16Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::int16_t*,
                              std::size_t n_values);
using GetUInt16Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::uint16_t*,
                               std::size_t n_values);
using GetUInt32Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::uint32_t*,
                               std::size_t n_values);
using GetUInt64Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::uint64_t*,
                               std::size_t n_values);
using GetInt64Fn = Status (*)(Instance, const ValueReference*, std::size_t, std::int64_t*,
                              std::size_t n_values);
using GetBooleanFn = Status (*)(Instance, const ValueReference*, std::size_t, Boolean*,
                                std::size_t n_values);
using DoStepFn = Status (*)(Instance, Float64 t, Float64 h, Boolean no_set_state_before_t,
                            Boolean* event_handling_needed, Boolean* terminate,
                            Boolean* early_return, Float64* last_successful_time);
using GetStateFn = Status (*)(Instance, State*);
using SetStateFn = Status (*)(Instance, State);
using FreeStateFn = Status (*)(Instance, State*);
}  // namespace fmi3

}  // namespace railcosim::fmu
