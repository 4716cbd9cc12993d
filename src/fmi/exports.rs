//! The exported C functions of the FMU (FMI 2.0 Co-Simulation; the
//! Model-Exchange-only functions are not exported). Each one forwards to the
//! generic implementation in [`super::api`] for the concrete model.
//!
//! # Safety
//! These functions are called by the importer under the FMI 2.0 contract:
//! `c` is NULL or an instance returned by `fmi2Instantiate` and not freed,
//! calls on one instance are not concurrent, array pointers are NULL or
//! valid for the given length, strings are NULL or NUL-terminated, and
//! `fmi2FMUstate` values come from this FMU. Beyond that, every argument is
//! checked (NULL pointers, value references, call sequence) and a violation
//! returns fmi2Error with a log message.
#![allow(clippy::missing_safety_doc)] // the contract above covers every function

use std::ffi::c_int;

use super::api::{self, Transition};
use super::types::*;

/// The model behind the C API.
type Model = crate::fmu_model::BeltDrive;

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> Fmi2String {
    api::get_types_platform()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> Fmi2String {
    api::get_version()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n_categories: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    unsafe { api::set_debug_logging::<Model>(c, logging_on, n_categories, categories) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: Fmi2String,
    fmu_type: c_int,
    fmu_guid: Fmi2String,
    fmu_resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    unsafe {
        api::instantiate::<Model>(
            instance_name,
            fmu_type,
            fmu_guid,
            fmu_resource_location,
            functions,
            visible,
            logging_on,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    unsafe { api::free_instance::<Model>(c) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: Fmi2Real,
    start_time: Fmi2Real,
    stop_time_defined: Fmi2Boolean,
    stop_time: Fmi2Real,
) -> Fmi2Status {
    unsafe {
        api::setup_experiment::<Model>(
            c,
            tolerance_defined,
            tolerance,
            start_time,
            stop_time_defined,
            stop_time,
        )
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    unsafe { api::transition::<Model>(c, Transition::EnterInitializationMode) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    unsafe { api::transition::<Model>(c, Transition::ExitInitializationMode) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    unsafe { api::transition::<Model>(c, Transition::Terminate) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    unsafe { api::transition::<Model>(c, Transition::Reset) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    unsafe { api::get_real::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    unsafe { api::get_integer::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    unsafe { api::get_boolean::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    unsafe { api::get_string::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Real,
) -> Fmi2Status {
    unsafe { api::set_real::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Integer,
) -> Fmi2Status {
    unsafe { api::set_integer::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    unsafe { api::set_boolean::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    unsafe { api::set_string::<Model>(c, vr, nvr, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    unsafe { api::get_fmu_state::<Model>(c, state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2Status {
    unsafe { api::set_fmu_state::<Model>(c, state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    unsafe { api::free_fmu_state::<Model>(c, state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2Status {
    unsafe { api::serialized_fmu_state_size::<Model>(c, state, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2FmuState,
    serialized_state: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    unsafe { api::serialize_fmu_state::<Model>(c, state, serialized_state, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    serialized_state: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    unsafe { api::deserialize_fmu_state::<Model>(c, serialized_state, size, state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _v_unknown_ref: *const Fmi2ValueReference,
    _n_unknown: usize,
    _v_known_ref: *const Fmi2ValueReference,
    _n_known: usize,
    _dv_known: *const Fmi2Real,
    _dv_unknown: *mut Fmi2Real,
) -> Fmi2Status {
    unsafe { api::get_directional_derivative::<Model>(c) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *const Fmi2Real,
) -> Fmi2Status {
    unsafe { api::set_real_input_derivatives::<Model>(c, vr, nvr, order, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    unsafe { api::get_real_output_derivatives::<Model>(c, vr, nvr, order, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: Fmi2Real,
    communication_step_size: Fmi2Real,
    _no_set_fmu_state_prior_to_current_point: Fmi2Boolean,
) -> Fmi2Status {
    unsafe { api::do_step::<Model>(c, current_communication_point, communication_step_size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    unsafe { api::cancel_step::<Model>(c) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    unsafe { api::get_unavailable_status::<Model, _>(c, "fmi2GetStatus", kind, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    unsafe { api::get_real_status::<Model>(c, kind, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    unsafe { api::get_unavailable_status::<Model, _>(c, "fmi2GetIntegerStatus", kind, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    unsafe { api::get_boolean_status::<Model>(c, kind, value) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2String,
) -> Fmi2Status {
    unsafe { api::get_unavailable_status::<Model, _>(c, "fmi2GetStringStatus", kind, value) }
}
