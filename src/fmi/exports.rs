//! The exported C functions of an FMU (FMI 2.0 Co-Simulation; the
//! Model-Exchange-only functions are not exported), generated for one model
//! by [`export_fmi2_co_simulation!`](crate::export_fmi2_co_simulation). Each
//! one forwards to the generic implementation in [`super::api`].
//!
//! # Safety
//! These functions are called by the importer under the FMI 2.0 contract:
//! `c` is NULL or an instance returned by `fmi2Instantiate` and not freed,
//! calls on one instance are not concurrent, array pointers are NULL or
//! valid for the given length, strings are NULL or NUL-terminated, and
//! `fmi2FMUstate` values come from this FMU. Beyond that, every argument is
//! checked (NULL pointers, value references, call sequence) and a violation
//! returns fmi2Error with a log message.

/// Export the FMI 2.0 Co-Simulation C functions (`fmi2Instantiate`,
/// `fmi2DoStep`, ...) for the model type `$model` (an
/// [`FmuModel`](crate::fmi::FmuModel)). A shared library exports one model:
/// invoke this once per crate.
#[macro_export]
macro_rules! export_fmi2_co_simulation {
    ($model:ty) => {
        // An anonymous scope: the functions are exported by their C names
        // (`#[no_mangle]`) and add nothing to the invoking module. The
        // safety contract is the one in the documentation of `fmi::exports`.
        #[allow(clippy::missing_safety_doc)]
        const _: () = {
            use std::ffi::c_int;
            #[allow(unused_imports)]
            use $crate::fmi::types::*;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> Fmi2String {
                $crate::fmi::api::get_types_platform()
            }

            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> Fmi2String {
                $crate::fmi::api::get_version()
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: Fmi2Component,
                logging_on: Fmi2Boolean,
                n_categories: usize,
                categories: *const Fmi2String,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::set_debug_logging::<$model>(
                        c,
                        logging_on,
                        n_categories,
                        categories,
                    )
                }
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
                    $crate::fmi::api::instantiate::<$model>(
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
                unsafe { $crate::fmi::api::free_instance::<$model>(c) }
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
                    $crate::fmi::api::setup_experiment::<$model>(
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
                unsafe {
                    $crate::fmi::api::transition::<$model>(
                        c,
                        $crate::fmi::api::Transition::EnterInitializationMode,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::transition::<$model>(
                        c,
                        $crate::fmi::api::Transition::ExitInitializationMode,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::transition::<$model>(
                        c,
                        $crate::fmi::api::Transition::Terminate,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::transition::<$model>(c, $crate::fmi::api::Transition::Reset)
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *mut Fmi2Real,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_real::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *mut Fmi2Integer,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_integer::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_boolean::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *mut Fmi2String,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_string::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *const Fmi2Real,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::set_real::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *const Fmi2Integer,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::set_integer::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *const Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::set_boolean::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                value: *const Fmi2String,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::set_string::<$model>(c, vr, nvr, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(
                c: Fmi2Component,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_fmu_state::<$model>(c, state) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(
                c: Fmi2Component,
                state: Fmi2FmuState,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::set_fmu_state::<$model>(c, state) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(
                c: Fmi2Component,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::free_fmu_state::<$model>(c, state) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: Fmi2Component,
                state: Fmi2FmuState,
                size: *mut usize,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::serialized_fmu_state_size::<$model>(c, state, size) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: Fmi2Component,
                state: Fmi2FmuState,
                serialized_state: *mut Fmi2Byte,
                size: usize,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::serialize_fmu_state::<$model>(
                        c,
                        state,
                        serialized_state,
                        size,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: Fmi2Component,
                serialized_state: *const Fmi2Byte,
                size: usize,
                state: *mut Fmi2FmuState,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::deserialize_fmu_state::<$model>(
                        c,
                        serialized_state,
                        size,
                        state,
                    )
                }
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
                unsafe { $crate::fmi::api::get_directional_derivative::<$model>(c) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                order: *const Fmi2Integer,
                value: *const Fmi2Real,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::set_real_input_derivatives::<$model>(c, vr, nvr, order, value)
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: Fmi2Component,
                vr: *const Fmi2ValueReference,
                nvr: usize,
                order: *const Fmi2Integer,
                value: *mut Fmi2Real,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::get_real_output_derivatives::<$model>(
                        c, vr, nvr, order, value,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(
                c: Fmi2Component,
                current_communication_point: Fmi2Real,
                communication_step_size: Fmi2Real,
                _no_set_fmu_state_prior_to_current_point: Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::do_step::<$model>(
                        c,
                        current_communication_point,
                        communication_step_size,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
                unsafe { $crate::fmi::api::cancel_step::<$model>(c) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: Fmi2Component,
                kind: c_int,
                value: *mut Fmi2Status,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::get_unavailable_status::<$model, _>(
                        c,
                        "fmi2GetStatus",
                        kind,
                        value,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: Fmi2Component,
                kind: c_int,
                value: *mut Fmi2Real,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_real_status::<$model>(c, kind, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: Fmi2Component,
                kind: c_int,
                value: *mut Fmi2Integer,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::get_unavailable_status::<$model, _>(
                        c,
                        "fmi2GetIntegerStatus",
                        kind,
                        value,
                    )
                }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: Fmi2Component,
                kind: c_int,
                value: *mut Fmi2Boolean,
            ) -> Fmi2Status {
                unsafe { $crate::fmi::api::get_boolean_status::<$model>(c, kind, value) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: Fmi2Component,
                kind: c_int,
                value: *mut Fmi2String,
            ) -> Fmi2Status {
                unsafe {
                    $crate::fmi::api::get_unavailable_status::<$model, _>(
                        c,
                        "fmi2GetStringStatus",
                        kind,
                        value,
                    )
                }
            }
        };
    };
}
