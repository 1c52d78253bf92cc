// The functions of an FMU's binary that the host resolved (FMI 2.0 or 3.0),
// shared by fmu.cpp (loading, stepping, state) and fmu_values.cpp (reading
// values of every type). Private to fmu/.
#pragma once

#include "fmi_api.hpp"
#include "fmu.hpp"

namespace railcosim::fmu {

struct Fmu::Api {
  struct {
    fmi2::InstantiateFn instantiate;
    fmi2::FreeInstanceFn free_instance;
    fmi2::SetupExperimentFn setup_experiment;
    fmi2::ComponentFn enter_initialization, exit_initialization, terminate;
    fmi2::SetRealFn set_real;
    fmi2::GetRealFn get_real;
    fmi2::GetIntegerFn get_integer;
    fmi2::GetBooleanFn get_boolean;
    fmi2::GetRealStatusFn get_real_status;
    fmi2::GetBooleanStatusFn get_boolean_status;
    fmi2::SetRealInputDerivativesFn set_real_input_derivatives;
    fmi2::DoStepFn do_step;
    fmi2::GetStateFn get_state;
    fmi2::SetStateFn set_state;
    fmi2::FreeStateFn free_state;
    fmi2::CallbackFunctions callbacks;
  } v2{};
  struct {
    fmi3::InstantiateCoSimulationFn instantiate;
    fmi3::FreeInstanceFn free_instance;
    fmi3::EnterInitializationModeFn enter_initialization;
    fmi3::InstanceFn exit_initialization, terminate;
    fmi3::SetFloat64Fn set_float64;
    fmi3::GetFloat64Fn get_float64;
    fmi3::GetFloat32Fn get_float32;
    fmi3::GetInt32Fn get_int32;
    fmi3::GetInt64Fn get_int64;
    fmi3::GetInt8Fn get_int8;
    fmi3::GetUInt8Fn get_uint8;
    fmi3::GetInt16Fn get_int16;
    fmi3::GetUInt16Fn get_uint16;
    fmi3::GetUInt32Fn get_uint32;
    fmi3::GetUInt64Fn get_uint64;
    fmi3::GetBooleanFn get_boolean;
    fmi3::DoStepFn do_step;
    fmi3::GetStateFn get_state;
    fmi3::SetStateFn set_state;
    fmi3::FreeStateFn free_state;
  } v3{};
};

}  // namespace railcosim::fmu
