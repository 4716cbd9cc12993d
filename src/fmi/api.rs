//! The FMI 2.0 Co-Simulation functions, generic over the model, at the raw
//! pointer level. `exports.rs` instantiates them for the concrete model
//! under the C names; the unit tests instantiate them for a mock model.
//!
//! Every function body runs inside `catch_unwind`: a panic becomes fmi2Error
//! (logged, instance in the Error state) instead of unwinding into C.
//! Every pointer from the caller is checked for NULL (arrays only when their
//! length is > 0) before it is used.

use std::ffi::{c_char, c_int, CStr};
use std::panic::{self, AssertUnwindSafe};
use std::ptr;

use super::description::VarType;
use super::instance::{allowed, Instance, Mode};
use super::logging::{self, Logger, LOG_EVENTS, LOG_STATUS_DISCARD, LOG_STATUS_ERROR};
use super::model::FmuModel;
use super::state::Snapshot;
use super::types::*;

/// Run `body` on the instance behind `c`; map `Err` and panics to fmi2Error.
///
/// # Safety
/// `c` is NULL or a pointer returned by [`instantiate`] with the same `M`
/// and not yet freed, and no other call on it is running (FMI 2.0 forbids
/// concurrent calls on one instance).
unsafe fn with_instance<M: FmuModel>(
    c: Fmi2Component,
    function: &str,
    body: impl FnOnce(&mut Instance<M>) -> Result<Fmi2Status, String>,
) -> Fmi2Status {
    if c.is_null() {
        return Fmi2Status::Error; // no instance, so no logger to tell
    }
    // SAFETY: see the function's contract.
    let inst = unsafe { &mut *(c as *mut Instance<M>) };
    inst.trace(|| format!("{function} called in state {:?}", inst.plumbing.mode));
    match panic::catch_unwind(AssertUnwindSafe(|| body(&mut *inst))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            inst.fail(function, &message);
            Fmi2Status::Error
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic payload".into());
            inst.fail(
                function,
                &format!(
                    "internal error (Rust panic: {what}); fmi2Reset or fmi2SetFMUstate to recover"
                ),
            );
            Fmi2Status::Error
        }
    }
}

/// A caller array of `n` elements as a slice; `Err` if it is NULL while
/// `n > 0`.
///
/// # Safety
/// A non-NULL `p` points to `n` initialised elements valid for `'a`.
unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(format!("{what} is a NULL pointer but its length is {n}"));
    }
    if n.checked_mul(size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(format!("length {n} of {what} is impossibly large"));
    }
    // SAFETY: non-NULL, length checked against isize::MAX; validity is the
    // caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Mutable counterpart of [`slice`].
///
/// # Safety
/// A non-NULL `p` points to `n` writable elements, valid and unaliased for `'a`.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    // SAFETY: forwarded contract; the check below makes it mutable.
    unsafe { slice(p as *const T, n, what)? };
    // SAFETY: as in `slice`, plus exclusive access per the contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A NUL-terminated caller string; `Err` if NULL or not UTF-8.
///
/// # Safety
/// A non-NULL `p` points to a NUL-terminated string valid for `'a`.
unsafe fn string<'a>(p: *const c_char, what: &str) -> Result<&'a str, String> {
    if p.is_null() {
        return Err(format!("{what} is a NULL pointer"));
    }
    // SAFETY: non-NULL and NUL-terminated per the contract.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .map_err(|_| format!("{what} is not valid UTF-8"))
}

/// fmi2GetTypesPlatform: `"default"` (the standard C types).
pub fn get_types_platform() -> Fmi2String {
    c"default".as_ptr()
}

/// fmi2GetVersion: `"2.0"`.
pub fn get_version() -> Fmi2String {
    c"2.0".as_ptr()
}

/// fmi2Instantiate. Returns NULL (after logging why, if there is a logger)
/// for a NULL `functions`, a NULL/blank instance name, Model Exchange, or a
/// GUID that is not this build's.
///
/// # Safety
/// Pointer arguments are NULL or valid per FMI 2.0 section 2.1.5.
pub unsafe fn instantiate<M: FmuModel>(
    instance_name: Fmi2String,
    fmu_type: c_int,
    fmu_guid: Fmi2String,
    _fmu_resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let result = panic::catch_unwind(|| {
        if functions.is_null() {
            return ptr::null_mut(); // no logger to tell
        }
        // SAFETY: non-NULL; the importer's struct is valid during the call.
        // Copied, since the importer need not keep it alive.
        let callbacks = unsafe { *functions };
        // SAFETY: NULL or a NUL-terminated string per FMI 2.0.
        let name = unsafe { string(instance_name, "instanceName") };
        let refuse = |name: &str, message: String| -> Fmi2Component {
            let message = format!("fmi2Instantiate: {message}");
            logging::emit(
                &callbacks,
                &logging::c_string(name),
                Fmi2Status::Error,
                LOG_STATUS_ERROR,
                &message,
            );
            ptr::null_mut()
        };
        let name = match name {
            Ok(n) if !n.trim().is_empty() => n,
            Ok(_) => {
                return refuse(
                    "",
                    "instanceName must not be empty (FMI 2.0 section 2.1.5)".into(),
                )
            }
            Err(e) => {
                return refuse(
                    "",
                    format!("{e} (FMI 2.0 section 2.1.5 requires a non-empty name)"),
                )
            }
        };
        if fmu_type != FMI2_CO_SIMULATION {
            let what = if fmu_type == FMI2_MODEL_EXCHANGE {
                "fmi2ModelExchange".to_string()
            } else {
                format!("the invalid fmi2Type {fmu_type}")
            };
            return refuse(
                name,
                format!("fmuType is {what}, but this FMU implements Co-Simulation only"),
            );
        }
        // SAFETY: NULL or a NUL-terminated string per FMI 2.0.
        let guid = M::description().guid;
        match unsafe { string(fmu_guid, "fmuGUID") } {
            Ok(g) if g == guid => {}
            Ok(g) => {
                return refuse(
                    name,
                    format!("fmuGUID {g} does not match this binary's GUID {guid} (the modelDescription.xml belongs to another build)"),
                )
            }
            Err(e) => return refuse(name, e),
        }
        let logger = Logger::new(
            callbacks,
            logging::c_string(name),
            logging_on != FMI2_FALSE,
            M::description().log_categories,
        );
        let inst = Instance::<M>::new(logger);
        inst.logger.log(Fmi2Status::Ok, LOG_EVENTS, "instantiated");
        Box::into_raw(Box::new(inst)) as Fmi2Component
    });
    result.unwrap_or(ptr::null_mut())
}

/// fmi2FreeInstance. NULL is ignored. FMU states of the instance that the
/// importer did not free are freed with it.
///
/// # Safety
/// As for `with_instance`; `c` must not be used afterwards.
pub unsafe fn free_instance<M: FmuModel>(c: Fmi2Component) {
    if c.is_null() {
        return;
    }
    // SAFETY: `c` came from `instantiate::<M>` (Box::into_raw) and is freed once.
    let inst = unsafe { Box::from_raw(c as *mut Instance<M>) };
    let left = inst.states.len();
    let message = if left == 0 {
        "freed".to_string()
    } else {
        format!("freed, with {left} FMU state(s) the importer had not freed")
    };
    inst.logger.log(Fmi2Status::Ok, LOG_EVENTS, &message);
    // Dropping the model must not unwind into C either.
    let _ = panic::catch_unwind(AssertUnwindSafe(move || drop(inst)));
}

/// # Safety
/// As for `with_instance`; `categories` is NULL or has `n` valid strings.
pub unsafe fn set_debug_logging<M: FmuModel>(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::SET_DEBUG_LOGGING)?;
        // SAFETY: caller's array of `n` strings.
        let list = unsafe { slice(categories, n, "categories[]")? };
        let names = list
            .iter()
            .enumerate()
            // SAFETY: each entry is NULL or a NUL-terminated string.
            .map(|(i, &p)| unsafe { string(p, &format!("categories[{i}]")) })
            .collect::<Result<Vec<_>, _>>()?;
        inst.logger
            .set_debug_logging(logging_on != FMI2_FALSE, &names)?;
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetDebugLogging", body) }
}

/// # Safety
/// As for `with_instance`.
pub unsafe fn setup_experiment<M: FmuModel>(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: f64,
    start_time: f64,
    stop_time_defined: Fmi2Boolean,
    stop_time: f64,
) -> Fmi2Status {
    let tol = (tolerance_defined != FMI2_FALSE).then_some(tolerance);
    let stop = (stop_time_defined != FMI2_FALSE).then_some(stop_time);
    // SAFETY: forwarded contract.
    unsafe {
        with_instance::<M>(c, "fmi2SetupExperiment", move |inst| {
            inst.setup_experiment(tol, start_time, stop)
        })
    }
}

/// Life-cycle functions without arguments.
#[derive(Clone, Copy)]
pub enum Transition {
    /// fmi2EnterInitializationMode.
    EnterInitializationMode,
    /// fmi2ExitInitializationMode.
    ExitInitializationMode,
    /// fmi2Terminate.
    Terminate,
    /// fmi2Reset.
    Reset,
}

/// # Safety
/// As for `with_instance`.
pub unsafe fn transition<M: FmuModel>(c: Fmi2Component, t: Transition) -> Fmi2Status {
    // SAFETY (all arms): forwarded contract.
    match t {
        Transition::EnterInitializationMode => unsafe {
            with_instance::<M>(c, "fmi2EnterInitializationMode", |i| {
                i.enter_initialization_mode()
            })
        },
        Transition::ExitInitializationMode => unsafe {
            with_instance::<M>(c, "fmi2ExitInitializationMode", |i| {
                i.exit_initialization_mode()
            })
        },
        Transition::Terminate => unsafe {
            with_instance::<M>(c, "fmi2Terminate", |i| i.terminate())
        },
        Transition::Reset => unsafe { with_instance::<M>(c, "fmi2Reset", |i| i.reset()) },
    }
}

// -- Getters and setters ------------------------------------------------------

/// # Safety
/// As for `with_instance`; `vr` and `value` are NULL or have `nvr` elements.
pub unsafe fn get_real<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut f64,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice_mut(value, nvr, "value[]")?) };
        inst.get_values(VarType::Real, vrs, values, M::get_real)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetReal", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn get_integer<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice_mut(value, nvr, "value[]")?) };
        inst.get_values(VarType::Integer, vrs, values, M::get_integer)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetInteger", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn get_boolean<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice_mut(value, nvr, "value[]")?) };
        inst.get_values(VarType::Boolean, vrs, values, |m, v| {
            m.get_boolean(v)
                .map(|b| if b { FMI2_TRUE } else { FMI2_FALSE })
        })
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetBoolean", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn get_string<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice_mut(value, nvr, "value[]")?) };
        inst.get_strings(vrs, values)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetString", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn set_real<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const f64,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice(value, nvr, "value[]")?) };
        inst.set_values(VarType::Real, vrs, values, M::set_real)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetReal", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn set_integer<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const Fmi2Integer,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice(value, nvr, "value[]")?) };
        inst.set_values(VarType::Integer, vrs, values, M::set_integer)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetInteger", body) }
}

/// # Safety
/// As for [`get_real`].
pub unsafe fn set_boolean<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, values) = unsafe { (slice(vr, nvr, "vr[]")?, slice(value, nvr, "value[]")?) };
        inst.set_values(VarType::Boolean, vrs, values, |m, v, b: Fmi2Boolean| {
            m.set_boolean(v, b != FMI2_FALSE)
        })
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetBoolean", body) }
}

/// # Safety
/// As for [`get_real`]; each string is NULL or NUL-terminated.
pub unsafe fn set_string<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, ptrs) = unsafe { (slice(vr, nvr, "vr[]")?, slice(value, nvr, "value[]")?) };
        let strings = ptrs
            .iter()
            .enumerate()
            // SAFETY: each entry is NULL or a NUL-terminated string.
            .map(|(i, &p)| unsafe { string(p, &format!("value[{i}]")) })
            .collect::<Result<Vec<_>, _>>()?;
        inst.set_values(VarType::String, vrs, &strings, |m, v, s: &str| {
            m.set_string(v, s)
        })
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetString", body) }
}

// -- FMU state ------------------------------------------------------------

/// Store `snap` in `*out`: into the existing state if `*out` is not NULL
/// (FMI 2.0 allows reusing it; it must be a live state of this instance),
/// else in a new registered allocation.
///
/// # Safety
/// `out` is non-NULL and points to a readable and writable `fmi2FMUstate`.
unsafe fn store<M: FmuModel>(
    inst: &mut Instance<M>,
    out: *mut Fmi2FmuState,
    snap: Snapshot<M>,
) -> Result<(), String> {
    // SAFETY: `out` is non-NULL (checked by the callers) and readable.
    let existing = unsafe { *out };
    if existing.is_null() {
        let p = inst.states.insert(snap);
        // SAFETY: as above, writable.
        unsafe { *out = p as Fmi2FmuState };
    } else {
        *inst.states.get(existing, "*FMUstate")? = snap;
    }
    Ok(())
}

/// # Safety
/// As for `with_instance`; `state` is NULL or points to an `fmi2FMUstate`.
pub unsafe fn get_fmu_state<M: FmuModel>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        if state.is_null() {
            return Err("FMUstate is a NULL pointer".into());
        }
        let snap = Snapshot::new(inst.plumbing, inst.model.clone());
        // SAFETY: non-NULL and points to the importer's `fmi2FMUstate`.
        unsafe { store(inst, state, snap)? };
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetFMUstate", body) }
}

/// # Safety
/// As for `with_instance`; `state` is any value (checked against the instance's live states before use).
pub unsafe fn set_fmu_state<M: FmuModel>(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        let snap = inst.states.get(state, "FMUstate")?;
        let (model, plumbing) = (snap.model.clone(), snap.plumbing);
        inst.model = model;
        inst.plumbing = plumbing;
        let p = inst.plumbing;
        inst.logger.log(
            Fmi2Status::Ok,
            LOG_EVENTS,
            &format!("FMU state restored: {:?} at t = {}", p.mode, p.time),
        );
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetFMUstate", body) }
}

/// fmi2FreeFMUstate: frees `*state` and sets it to NULL. A NULL pointer is
/// ignored (FMI 2.0 section 2.1.8).
///
/// # Safety
/// As for `with_instance`; `state` is NULL or points to an `fmi2FMUstate`.
pub unsafe fn free_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        // SAFETY: `state` is NULL or writable.
        if state.is_null() || unsafe { *state }.is_null() {
            return Ok(Fmi2Status::Ok);
        }
        // SAFETY: `state` is non-NULL and readable.
        inst.states.free(unsafe { *state }, "*FMUstate")?;
        // SAFETY: `state` is non-NULL and writable.
        unsafe { *state = ptr::null_mut() };
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2FreeFMUstate", body) }
}

/// # Safety
/// As for `with_instance`; `state` is any value (checked against the instance's live states before use); `size` NULL or writable.
pub unsafe fn serialized_fmu_state_size<M: FmuModel>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        let snap = inst.states.get(state, "FMUstate")?;
        if size.is_null() {
            return Err("size is a NULL pointer".into());
        }
        // SAFETY: non-NULL and writable.
        unsafe { *size = snap.serialize().len() };
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SerializedFMUstateSize", body) }
}

/// # Safety
/// As for `with_instance`; `state` is any value (checked against the instance's live states before use); `bytes` has `size`
/// writable bytes.
pub unsafe fn serialize_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    bytes: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        let data = inst.states.get(state, "FMUstate")?.serialize();
        if size != data.len() {
            return Err(format!(
                "size = {size}, but the serialized state has {} bytes (from fmi2SerializedFMUstateSize)",
                data.len()
            ));
        }
        // SAFETY: caller's buffer of `size` bytes.
        let out = unsafe { slice_mut(bytes as *mut u8, size, "serializedState[]")? };
        out.copy_from_slice(&data);
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SerializeFMUstate", body) }
}

/// # Safety
/// As for `with_instance`; `bytes` has `size` bytes; `state` is NULL or
/// points to an `fmi2FMUstate` (NULL or ours).
pub unsafe fn deserialize_fmu_state<M: FmuModel>(
    c: Fmi2Component,
    bytes: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        inst.check_state(allowed::FMU_STATE)?;
        // SAFETY: caller's buffer of `size` bytes.
        let data = unsafe { slice(bytes as *const u8, size, "serializedState[]")? };
        if state.is_null() {
            return Err("FMUstate is a NULL pointer".into());
        }
        let snap = Snapshot::<M>::deserialize(data)?;
        // SAFETY: non-NULL and points to the importer's `fmi2FMUstate`.
        unsafe { store(inst, state, snap)? };
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2DeSerializeFMUstate", body) }
}

// -- Derivatives ------------------------------------------------------------

/// Not provided (`providesDirectionalDerivative="false"`): always fmi2Error.
///
/// # Safety
/// As for `with_instance`.
pub unsafe fn get_directional_derivative<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    let body = |inst: &mut Instance<M>| {
        inst.check_state(allowed::GET)?;
        Err("not provided: this FMU declares providesDirectionalDerivative=\"false\"".into())
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetDirectionalDerivative", body) }
}

/// # Safety
/// As for `with_instance`; the arrays are NULL or have `nvr` elements.
pub unsafe fn set_real_input_derivatives<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *const f64,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, orders, values) = unsafe {
            (
                slice(vr, nvr, "vr[]")?,
                slice(order, nvr, "order[]")?,
                slice(value, nvr, "value[]")?,
            )
        };
        inst.set_real_input_derivatives(vrs, orders, values)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2SetRealInputDerivatives", body) }
}

/// # Safety
/// As for `with_instance`; the arrays are NULL or have `nvr` elements.
pub unsafe fn get_real_output_derivatives<M: FmuModel>(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *mut f64,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        // SAFETY: caller's arrays of `nvr` elements.
        let (vrs, orders, values) = unsafe {
            (
                slice(vr, nvr, "vr[]")?,
                slice(order, nvr, "order[]")?,
                slice_mut(value, nvr, "value[]")?,
            )
        };
        inst.get_real_output_derivatives(vrs, orders, values)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetRealOutputDerivatives", body) }
}

// -- Stepping and status ----------------------------------------------------

/// # Safety
/// As for `with_instance`.
pub unsafe fn do_step<M: FmuModel>(c: Fmi2Component, t: f64, h: f64) -> Fmi2Status {
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2DoStep", move |inst| inst.do_step(t, h)) }
}

/// Asynchronous steps are not supported, so there is never a step to cancel.
///
/// # Safety
/// As for `with_instance`.
pub unsafe fn cancel_step<M: FmuModel>(c: Fmi2Component) -> Fmi2Status {
    let body = |inst: &mut Instance<M>| {
        inst.check_state(allowed::CANCEL_STEP)?;
        Ok(Fmi2Status::Ok)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2CancelStep", body) }
}

/// Status information that an fmi2GetXXXStatus call can deliver.
pub enum StatusValue {
    /// `fmi2LastSuccessfulTime`: the current communication point.
    LastSuccessfulTime(f64),
    /// `fmi2Terminated`: whether the instance asks to stop (after a
    /// discarded step).
    Terminated(bool),
}

/// Shared part of the fmi2GetXXXStatus functions: `Ok(Some(v))` to write
/// `v`; `Ok(None)` means the information is not available, which FMI 2.0
/// section 2.1.3 answers with fmi2Discard ("fmi2Discard is returned also if
/// the slave is not able to return the required status information").
/// Invalid kinds are errors.
fn status_query<M: FmuModel>(
    inst: &mut Instance<M>,
    function: &str,
    kind: c_int,
    this_type: &str,
) -> Result<Option<StatusValue>, String> {
    inst.check_state(allowed::GET_STATUS)?;
    let (name, value) = match kind {
        FMI2_DO_STEP_STATUS => ("fmi2DoStepStatus", None),
        FMI2_PENDING_STATUS => ("fmi2PendingStatus", None),
        FMI2_LAST_SUCCESSFUL_TIME => (
            "fmi2LastSuccessfulTime",
            Some(StatusValue::LastSuccessfulTime(inst.plumbing.time)),
        ),
        // After a discarded step the instance can only be terminated, reset
        // or restored with fmi2SetFMUstate (fmi2DoStep is not allowed in
        // slaveStepFailed, FMI 2.0 section 4.2.4): it asks to stop, so that a
        // master that checks fmi2Terminated ends the run at the last
        // successful time instead of retrying the step.
        FMI2_TERMINATED => (
            "fmi2Terminated",
            Some(StatusValue::Terminated(
                inst.plumbing.mode == Mode::StepFailed,
            )),
        ),
        other => return Err(format!("invalid fmi2StatusKind {other}")),
    };
    let fits = matches!(
        (this_type, &value),
        ("Real", Some(StatusValue::LastSuccessfulTime(_)))
            | ("Boolean", Some(StatusValue::Terminated(_)))
    );
    if !fits {
        let why = match kind {
            FMI2_DO_STEP_STATUS | FMI2_PENDING_STATUS => {
                "fmi2DoStep never returns fmi2Pending (no asynchronous steps)"
            }
            _ => "this status kind is not of this type",
        };
        inst.logger.log(
            Fmi2Status::Discard,
            LOG_STATUS_DISCARD,
            &format!("{function}({name}): status not available: {why}"),
        );
        return Ok(None);
    }
    Ok(value)
}

/// fmi2GetStatus / fmi2GetIntegerStatus / fmi2GetStringStatus: nothing to
/// report for any kind (fmi2Discard), but the state and kind are checked.
///
/// # Safety
/// As for `with_instance`; `value` is NULL or writable.
pub unsafe fn get_unavailable_status<M: FmuModel, T>(
    c: Fmi2Component,
    function: &'static str,
    kind: c_int,
    value: *mut T,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        if value.is_null() {
            return Err("value is a NULL pointer".into());
        }
        status_query(inst, function, kind, "other")?;
        Ok(Fmi2Status::Discard)
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, function, body) }
}

/// # Safety
/// As for `with_instance`; `value` is NULL or writable.
pub unsafe fn get_real_status<M: FmuModel>(
    c: Fmi2Component,
    kind: c_int,
    value: *mut f64,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        if value.is_null() {
            return Err("value is a NULL pointer".into());
        }
        match status_query(inst, "fmi2GetRealStatus", kind, "Real")? {
            Some(StatusValue::LastSuccessfulTime(t)) => {
                // SAFETY: non-NULL and writable.
                unsafe { *value = t };
                Ok(Fmi2Status::Ok)
            }
            _ => Ok(Fmi2Status::Discard),
        }
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetRealStatus", body) }
}

/// # Safety
/// As for `with_instance`; `value` is NULL or writable.
pub unsafe fn get_boolean_status<M: FmuModel>(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    let body = move |inst: &mut Instance<M>| {
        if value.is_null() {
            return Err("value is a NULL pointer".into());
        }
        match status_query(inst, "fmi2GetBooleanStatus", kind, "Boolean")? {
            Some(StatusValue::Terminated(b)) => {
                // SAFETY: non-NULL and writable.
                unsafe { *value = if b { FMI2_TRUE } else { FMI2_FALSE } };
                Ok(Fmi2Status::Ok)
            }
            _ => Ok(Fmi2Status::Discard),
        }
    };
    // SAFETY: forwarded contract.
    unsafe { with_instance::<M>(c, "fmi2GetBooleanStatus", body) }
}
