//! One FMU instance: the Co-Simulation state machine of FMI 2.0 section
//! 4.2.4 around a model.
//!
//! States (the standard's names):
//! * `Instantiated`, `InitializationMode`, `StepComplete`, `Terminated`;
//! * `StepFailed`: fmi2DoStep returned fmi2Discard. The model stayed at the
//!   last communication point; the importer may read values and statuses,
//!   terminate, reset, or go back with fmi2SetFMUstate and retry;
//! * `Error`: any function returned fmi2Error ("the simulation cannot be
//!   continued with this FMU instance"). Left only by fmi2Reset or
//!   fmi2SetFMUstate.
//!
//! `StepInProgress` and `StepCanceled` are never entered (fmi2DoStep is
//! synchronous, `canRunAsynchronuously="false"`); `fmi2Fatal` is never
//! returned (instances share nothing, so an error never spoils the others),
//! so there is no `Fatal` state.
//!
//! The methods return `Ok(status)` or `Err(message)`; the C boundary
//! ([`super::api`]) logs an `Err` as fmi2Error, prefixed with the function
//! name, and moves the instance to `Error`.

use std::ffi::CString;

use super::description::{Causality, VarInfo, VarType, Variability};
use super::logging::{self, Logger, LOG_ALL, LOG_EVENTS, LOG_STATUS_DISCARD, LOG_STATUS_WARNING};
use super::model::{FmuModel, StepError};
use super::state::Registry;
use super::types::{Fmi2Status, Fmi2String};

/// The Co-Simulation states this FMU can be in (see module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Mode {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated = 1,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode = 2,
    /// Initialized; ready for fmi2DoStep.
    StepComplete = 3,
    /// fmi2DoStep returned fmi2Discard.
    StepFailed = 4,
    /// After fmi2Terminate.
    Terminated = 5,
    /// A function returned fmi2Error.
    Error = 6,
}

impl Mode {
    const fn bit(self) -> u8 {
        1 << (self as u8)
    }

    /// The state with this discriminant (from a serialized FMU state).
    pub fn from_u8(x: u8) -> Option<Mode> {
        [
            Mode::Instantiated,
            Mode::InitializationMode,
            Mode::StepComplete,
            Mode::StepFailed,
            Mode::Terminated,
            Mode::Error,
        ]
        .into_iter()
        .find(|m| *m as u8 == x)
    }
}

/// Sets of states in which a function may be called: the Co-Simulation
/// columns of the table in FMI 2.0 section 4.2.4 (StepInProgress and
/// StepCanceled omitted, see module docs).
pub mod allowed {
    use super::Mode::*;

    /// Every state.
    pub const ANY: u8 = Instantiated.bit()
        | InitializationMode.bit()
        | StepComplete.bit()
        | StepFailed.bit()
        | Terminated.bit()
        | Error.bit();
    /// fmi2SetDebugLogging, fmi2Reset, fmi2FreeInstance, fmi2Get/Set/FreeFMUstate,
    /// fmi2(De)SerializeFMUstate, fmi2SerializedFMUstateSize.
    pub const SET_DEBUG_LOGGING: u8 = ANY;
    /// fmi2Reset.
    pub const RESET: u8 = ANY;
    /// fmi2Get/Set/FreeFMUstate, fmi2(De)SerializeFMUstate, fmi2SerializedFMUstateSize.
    pub const FMU_STATE: u8 = ANY;
    /// fmi2SetupExperiment.
    pub const SETUP_EXPERIMENT: u8 = Instantiated.bit();
    /// fmi2EnterInitializationMode.
    pub const ENTER_INITIALIZATION_MODE: u8 = Instantiated.bit();
    /// fmi2ExitInitializationMode.
    pub const EXIT_INITIALIZATION_MODE: u8 = InitializationMode.bit();
    /// fmi2Terminate.
    pub const TERMINATE: u8 = StepComplete.bit() | StepFailed.bit();
    /// fmi2GetReal/Integer/Boolean/String and fmi2GetDirectionalDerivative.
    pub const GET: u8 = InitializationMode.bit()
        | StepComplete.bit()
        | StepFailed.bit()
        | Terminated.bit()
        | Error.bit();
    /// fmi2SetReal/Integer/Boolean/String (which variables: see `check_settable`).
    pub const SET: u8 = Instantiated.bit() | InitializationMode.bit() | StepComplete.bit();
    /// fmi2SetRealInputDerivatives.
    pub const SET_REAL_INPUT_DERIVATIVES: u8 =
        Instantiated.bit() | InitializationMode.bit() | StepComplete.bit();
    /// fmi2GetRealOutputDerivatives.
    pub const GET_REAL_OUTPUT_DERIVATIVES: u8 =
        StepComplete.bit() | StepFailed.bit() | Terminated.bit() | Error.bit();
    /// fmi2DoStep.
    pub const DO_STEP: u8 = StepComplete.bit();
    /// Only StepInProgress, which this FMU never enters.
    pub const CANCEL_STEP: u8 = 0;
    /// fmi2GetStatus and fmi2Get{Real,Integer,Boolean,String}Status.
    pub const GET_STATUS: u8 = StepComplete.bit() | StepFailed.bit() | Terminated.bit();
}

/// The plumbing's part of an FMU state (saved and restored with the model).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plumbing {
    /// State-machine state.
    pub mode: Mode,
    /// Current communication point (= last successful time).
    pub time: f64,
    /// fmi2SetupExperiment(stopTimeDefined = true): stepping past it is an error.
    pub stop_time: Option<f64>,
}

impl Default for Plumbing {
    fn default() -> Self {
        Plumbing {
            mode: Mode::Instantiated,
            time: 0.0,
            stop_time: None,
        }
    }
}

/// Communication points are compared with a relative tolerance of 1e-9
/// (absolute near zero), so a master that computes `t0 + n*h` instead of
/// summing step sizes is not rejected for rounding.
pub fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

/// What an `fmi2Component` points to: one instance of model `M`.
pub struct Instance<M> {
    /// The importer's logger and the category switches.
    pub logger: Logger,
    /// State-machine state and times.
    pub plumbing: Plumbing,
    /// The model.
    pub model: M,
    /// The FMU states handed out and not yet freed (freed with the instance).
    pub states: Registry<M>,
    /// Keeps the strings handed out by fmi2GetString alive until the next call.
    strings: Vec<CString>,
}

impl<M: FmuModel> Instance<M> {
    /// A new instance in Instantiated with a fresh model.
    pub fn new(logger: Logger) -> Self {
        Instance {
            logger,
            plumbing: Plumbing::default(),
            model: M::new(),
            states: Registry::default(),
            strings: Vec::new(),
        }
    }

    /// Log `message` in the category of `status`.
    pub fn log(&self, status: Fmi2Status, message: &str) {
        self.logger
            .log(status, logging::category_of(status), message);
    }

    /// Trace a call (category logAll).
    pub fn trace(&self, message: impl FnOnce() -> String) {
        if self.logger.is_enabled(LOG_ALL) {
            self.logger.log(Fmi2Status::Ok, LOG_ALL, &message());
        }
    }

    /// Log an fmi2Error return of `function` and enter the Error state.
    pub fn fail(&mut self, function: &str, message: &str) {
        self.plumbing.mode = Mode::Error;
        self.log(Fmi2Status::Error, &format!("{function}: {message}"));
    }

    /// The call-sequence rule (FMI 2.0 section 4.2.4).
    pub fn check_state(&self, allowed: u8) -> Result<(), String> {
        if allowed & self.plumbing.mode.bit() != 0 {
            return Ok(());
        }
        let allowed_in: Vec<String> = (1..=6u8)
            .filter_map(Mode::from_u8)
            .filter(|m| allowed & m.bit() != 0)
            .map(|m| format!("{m:?}"))
            .collect();
        Err(format!(
            "illegal call sequence: not allowed in state {:?} (FMI 2.0 section 4.2.4 allows it in: {})",
            self.plumbing.mode,
            if allowed_in.is_empty() { "StepInProgress only, which this FMU never enters".into() } else { allowed_in.join(", ") }
        ))
    }

    // -- Life cycle ---------------------------------------------------------

    /// fmi2SetupExperiment.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::SETUP_EXPERIMENT)?;
        if !start_time.is_finite() {
            return Err(format!("startTime = {start_time} is not finite"));
        }
        if let Some(tol) = tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(format!("tolerance = {tol} must be finite and > 0"));
            }
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop >= start_time) {
                return Err(format!(
                    "stopTime = {stop} must be finite and >= startTime = {start_time}"
                ));
            }
        }
        self.model.setup_experiment(tolerance, start_time);
        self.plumbing.time = start_time;
        self.plumbing.stop_time = stop_time;
        Ok(Fmi2Status::Ok)
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Result<Fmi2Status, String> {
        self.check_state(allowed::ENTER_INITIALIZATION_MODE)?;
        self.plumbing.mode = Mode::InitializationMode;
        self.logger
            .log(Fmi2Status::Ok, LOG_EVENTS, "entered Initialization Mode");
        Ok(Fmi2Status::Ok)
    }

    /// fmi2ExitInitializationMode: the model initializes; its warnings are logged.
    pub fn exit_initialization_mode(&mut self) -> Result<Fmi2Status, String> {
        self.check_state(allowed::EXIT_INITIALIZATION_MODE)?;
        // Warnings go to the logger only: some importers stop on a
        // function status fmi2Warning, and nothing here is an error.
        for w in self.model.initialize()? {
            self.logger
                .always(Fmi2Status::Warning, LOG_STATUS_WARNING, &w);
        }
        for note in self.model.notes() {
            self.logger.log(Fmi2Status::Ok, LOG_EVENTS, &note);
        }
        self.plumbing.mode = Mode::StepComplete;
        let t = self.plumbing.time;
        self.logger.log(
            Fmi2Status::Ok,
            LOG_EVENTS,
            &format!("initialized at t = {t}"),
        );
        Ok(Fmi2Status::Ok)
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Result<Fmi2Status, String> {
        self.check_state(allowed::TERMINATE)?;
        self.plumbing.mode = Mode::Terminated;
        let t = self.plumbing.time;
        self.logger.log(
            Fmi2Status::Ok,
            LOG_EVENTS,
            &format!("terminated at t = {t}"),
        );
        Ok(Fmi2Status::Ok)
    }

    /// Back to Instantiated with a fresh model; logger settings are kept.
    pub fn reset(&mut self) -> Result<Fmi2Status, String> {
        self.check_state(allowed::RESET)?;
        self.model = M::new();
        self.plumbing = Plumbing::default();
        self.strings.clear();
        self.logger.log(
            Fmi2Status::Ok,
            LOG_EVENTS,
            "reset to Instantiated with start values",
        );
        Ok(Fmi2Status::Ok)
    }

    // -- Variables ----------------------------------------------------------

    /// The variable of type `ty` with value reference `vr`.
    pub fn variable(ty: VarType, vr: u32) -> Result<&'static VarInfo<M::Var>, String> {
        let description = M::description();
        if let Some(v) = description.lookup(ty, vr) {
            return Ok(v);
        }
        Err(match description.by_vr(vr) {
            Some(v) => format!(
                "value reference {vr} is the {:?} variable \"{}\", not a {ty:?} variable",
                v.ty, v.name
            ),
            None => format!("unknown value reference {vr} (not in modelDescription.xml)"),
        })
    }

    /// Which variables may be set in which state (FMI 2.0 section 4.2.4,
    /// footnotes of the fmi2SetXXX row): parameters and inputs before and
    /// during initialization; afterwards inputs and tunable parameters only.
    /// Outputs, calculated parameters, locals, constants: never.
    pub fn check_settable(&self, v: &VarInfo<M::Var>) -> Result<(), String> {
        let never = match v.causality {
            Causality::Output => Some("an output"),
            Causality::CalculatedParameter => Some("a calculated parameter"),
            Causality::Local => Some("a local variable"),
            Causality::Independent => Some("the independent variable"),
            Causality::Parameter | Causality::Input => None,
        };
        if let Some(what) = never {
            return Err(format!(
                "\"{}\" (vr {}) is {what} and cannot be set (FMI 2.0: only parameters and inputs are set by the importer)",
                v.name, v.vr
            ));
        }
        if v.variability == Variability::Constant {
            return Err(format!(
                "\"{}\" (vr {}) is a constant and cannot be set",
                v.name, v.vr
            ));
        }
        let late = self.plumbing.mode == Mode::StepComplete;
        if late && v.causality == Causality::Parameter && v.variability != Variability::Tunable {
            return Err(format!(
                "\"{}\" (vr {}) is a {:?} parameter; it can only be set in Instantiated or Initialization Mode (FMI 2.0 section 4.2.4), not after initialization",
                v.name, v.vr, v.variability
            ));
        }
        Ok(())
    }

    /// fmi2GetReal/Integer/Boolean: `get` reads one variable from the model.
    pub fn get_values<T>(
        &mut self,
        ty: VarType,
        vrs: &[u32],
        values: &mut [T],
        get: impl Fn(&mut M, &VarInfo<M::Var>) -> Result<T, String>,
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::GET)?;
        for (&vr, value) in vrs.iter().zip(values.iter_mut()) {
            let v = Self::variable(ty, vr)?;
            *value =
                get(&mut self.model, v).map_err(|e| format!("\"{}\" (vr {vr}): {e}", v.name))?;
        }
        Ok(Fmi2Status::Ok)
    }

    /// fmi2SetReal/Integer/Boolean/String: `set` writes one variable.
    pub fn set_values<T: Copy>(
        &mut self,
        ty: VarType,
        vrs: &[u32],
        values: &[T],
        set: impl Fn(&mut M, &VarInfo<M::Var>, T) -> Result<(), String>,
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::SET)?;
        for (&vr, &value) in vrs.iter().zip(values) {
            let v = Self::variable(ty, vr)?;
            self.check_settable(v)?;
            set(&mut self.model, v, value).map_err(|e| format!("\"{}\" (vr {vr}): {e}", v.name))?;
        }
        Ok(Fmi2Status::Ok)
    }

    /// fmi2GetString: the pointers stay valid until the next fmi2GetString
    /// call, fmi2Reset or fmi2FreeInstance of this instance.
    pub fn get_strings(
        &mut self,
        vrs: &[u32],
        values: &mut [Fmi2String],
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::GET)?;
        self.strings.clear();
        for (&vr, value) in vrs.iter().zip(values.iter_mut()) {
            let v = Self::variable(VarType::String, vr)?;
            let s = self
                .model
                .get_string(v)
                .map_err(|e| format!("\"{}\" (vr {vr}): {e}", v.name))?;
            let s = logging::c_string(&s);
            *value = s.as_ptr(); // the heap buffer does not move with the CString
            self.strings.push(s);
        }
        Ok(Fmi2Status::Ok)
    }

    /// fmi2SetRealInputDerivatives: inputs only, order >= 1.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::SET_REAL_INPUT_DERIVATIVES)?;
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let v = Self::variable(VarType::Real, vr)?;
            if v.causality != Causality::Input {
                return Err(format!("\"{}\" (vr {vr}) is not an input", v.name));
            }
            if order < 1 {
                return Err(format!(
                    "\"{}\" (vr {vr}): derivative order {order} must be >= 1",
                    v.name
                ));
            }
            self.model
                .set_input_derivative(v, order, value)
                .map_err(|e| format!("\"{}\" (vr {vr}): {e}", v.name))?;
        }
        Ok(Fmi2Status::Ok)
    }

    /// fmi2GetRealOutputDerivatives: outputs only, order >= 1.
    pub fn get_real_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Result<Fmi2Status, String> {
        self.check_state(allowed::GET_REAL_OUTPUT_DERIVATIVES)?;
        for ((&vr, &order), value) in vrs.iter().zip(orders).zip(values.iter_mut()) {
            let v = Self::variable(VarType::Real, vr)?;
            if v.causality != Causality::Output {
                return Err(format!("\"{}\" (vr {vr}) is not an output", v.name));
            }
            if order < 1 {
                return Err(format!(
                    "\"{}\" (vr {vr}): derivative order {order} must be >= 1",
                    v.name
                ));
            }
            *value = self
                .model
                .get_output_derivative(v, order)
                .map_err(|e| format!("\"{}\" (vr {vr}): {e}", v.name))?;
        }
        Ok(Fmi2Status::Ok)
    }

    // -- Stepping -----------------------------------------------------------

    /// fmi2DoStep: checks the communication point, step size and stop time, then steps the model.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<Fmi2Status, String> {
        self.check_state(allowed::DO_STEP)?;
        let now = self.plumbing.time;
        if !t.is_finite() || !same_time(t, now) {
            return Err(format!(
                "currentCommunicationPoint = {t} differs from the FMU's current time {now} (FMI 2.0 section 4.2.2: it must equal the end of the previous step)"
            ));
        }
        if !(h.is_finite() && h > 0.0) {
            return Err(format!(
                "communicationStepSize = {h} must be finite and > 0"
            ));
        }
        if let Some(stop) = self.plumbing.stop_time {
            if now + h > stop && !same_time(now + h, stop) {
                return Err(format!(
                    "the step to t = {} would pass stopTime = {stop} set by fmi2SetupExperiment (FMI 2.0 section 2.1.6)",
                    now + h
                ));
            }
        }
        self.trace(|| format!("fmi2DoStep(t = {now}, h = {h})"));
        match self.model.do_step(now, h) {
            Ok(()) => {
                self.plumbing.time = now + h;
                Ok(Fmi2Status::Ok)
            }
            Err(StepError::Discard(msg)) => {
                // The model is back at `now`; so is the plumbing.
                self.plumbing.mode = Mode::StepFailed;
                self.logger.log(
                    Fmi2Status::Discard,
                    LOG_STATUS_DISCARD,
                    &format!("fmi2DoStep: step from t = {now} with h = {h} discarded: {msg}; last successful time is {now}"),
                );
                Ok(Fmi2Status::Discard)
            }
            Err(StepError::Error(msg)) => {
                Err(format!("step from t = {now} with h = {h} failed: {msg}"))
            }
        }
    }
}
