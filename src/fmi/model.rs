//! The small interface between the FMI plumbing and a model.
//!
//! The plumbing (state machine, argument checks, logging, FMU-state framing)
//! lives in this module tree and is generic over [`FmuModel`]; a model
//! implements it and hands over its identity and variable table through
//! [`FmuModel::description`]. Causality/variability rules and the
//! call-sequence rules are enforced by the plumbing *before* these methods
//! are called, so an implementation only maps variables onto its data.

use super::description::{ModelDescription, VarInfo};

/// Why a communication step could not be completed.
#[derive(Debug, Clone, PartialEq)]
pub enum StepError {
    /// The step could not be finished (e.g. the integrator's step-count guard
    /// or a non-finite state); the model is back at the last good state and
    /// the importer may retry with a smaller step (fmi2Discard).
    Discard(String),
    /// The model is unusable (fmi2Error).
    Error(String),
}

/// A co-simulation model behind the FMI 2.0 C API.
pub trait FmuModel: Clone + Send + Sized + 'static {
    /// The model's key for a variable (`VarInfo::var`).
    type Var: Copy + std::fmt::Debug + Send + Sync + 'static;

    /// The first 8 bytes of this model's serialized FMU states (tells a
    /// state of this model from any other bytes).
    const STATE_MAGIC: [u8; 8];

    /// The model's identity (model identifier, GUID, log categories) and
    /// its variable table, generated from its model description.
    fn description() -> &'static ModelDescription<Self::Var>;

    /// A fresh model with every variable at its start value.
    fn new() -> Self;

    /// Value of a Real variable (parameter, input or output). `&mut self`
    /// lets the model build or refresh cached outputs lazily (e.g. when an
    /// output is read in Initialization Mode). An `Err` carries a message
    /// that names the offending parameter and its allowed range.
    fn get_real(&mut self, v: &VarInfo<Self::Var>) -> Result<f64, String>;
    /// Set a Real parameter or input.
    fn set_real(&mut self, v: &VarInfo<Self::Var>, value: f64) -> Result<(), String>;
    /// Value of an Integer variable.
    fn get_integer(&mut self, v: &VarInfo<Self::Var>) -> Result<i32, String>;
    /// Set an Integer parameter or input.
    fn set_integer(&mut self, v: &VarInfo<Self::Var>, value: i32) -> Result<(), String>;
    /// Value of a Boolean variable.
    fn get_boolean(&mut self, v: &VarInfo<Self::Var>) -> Result<bool, String>;
    /// Set a Boolean parameter or input.
    fn set_boolean(&mut self, v: &VarInfo<Self::Var>, value: bool) -> Result<(), String>;
    /// Value of a String variable (default: the model has none).
    fn get_string(&mut self, v: &VarInfo<Self::Var>) -> Result<String, String> {
        Err(format!("{} is not a String variable", v.name))
    }
    /// Set a String parameter or input (default: the model has none).
    fn set_string(&mut self, v: &VarInfo<Self::Var>, _value: &str) -> Result<(), String> {
        Err(format!("{} is not a String variable", v.name))
    }

    /// fmi2SetupExperiment: `tolerance` is `Some` when toleranceDefined.
    fn setup_experiment(&mut self, tolerance: Option<f64>, start_time: f64);

    /// fmi2ExitInitializationMode: validate parameters and build the model.
    /// `Err` names the parameter and the allowed range; `Ok` carries
    /// warnings about valid but doubtful parameter choices, which the
    /// plumbing logs with status fmi2Warning (the call still returns fmi2OK).
    fn initialize(&mut self) -> Result<Vec<String>, String>;

    /// Choices the model made itself at initialization (e.g. a parameter
    /// left at "automatic"), logged with status fmi2OK in the category
    /// logEvents after a successful [`initialize`](Self::initialize).
    fn notes(&self) -> Vec<String> {
        Vec::new()
    }

    /// fmi2DoStep: integrate from `t` to exactly `t + h`. On `Err` the model
    /// must be left at its state at `t`.
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError>;

    /// fmi2SetRealInputDerivatives (order 1 only: inputs ramp linearly
    /// within the next communication step).
    fn set_input_derivative(
        &mut self,
        v: &VarInfo<Self::Var>,
        order: i32,
        value: f64,
    ) -> Result<(), String>;

    /// fmi2GetRealOutputDerivatives (order 1 only).
    fn get_output_derivative(&mut self, v: &VarInfo<Self::Var>, order: i32) -> Result<f64, String>;

    /// Append a self-contained, versioned byte image of the model (for
    /// fmi2SerializeFMUstate). The plumbing adds its own framing (magic,
    /// GUID, length, checksum) around it.
    fn serialize(&self, out: &mut Vec<u8>);
    /// Rebuild a model from [`FmuModel::serialize`] output. Must never read
    /// past the end of `bytes` or panic on corrupt input.
    fn deserialize(bytes: &[u8]) -> Result<Self, String>;
}
