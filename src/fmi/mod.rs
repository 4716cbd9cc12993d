//! FMI 2.0 Co-Simulation plumbing: C types, logging, the state machine,
//! FMU-state framing and the exported C functions. Generic over
//! [`FmuModel`], which hands over the model's identity and variable table
//! ([`ModelDescription`]); nothing here knows a particular model.
//!
//! * [`description`]: a model's identity and variable table.
//! * [`types`]: `fmi2TypesPlatform.h` / `fmi2FunctionTypes.h` as `repr(C)`.
//! * [`logging`]: categories, fmi2SetDebugLogging, the logger callback.
//! * [`instance`]: one instance and its state machine (FMI 2.0 section 4.2.4).
//! * [`state`]: `fmi2FMUstate` snapshots and their serialized form.
//! * [`api`]: the functions at the pointer level, generic over the model.
//! * [`exports`]: the macro [`crate::export_fmi2_co_simulation`] that writes
//!   the `#[no_mangle] extern "C" fn fmi2...` for one model.

#![warn(missing_docs)]

pub mod api;
pub mod description;
pub mod exports;
pub mod instance;
pub mod logging;
pub mod model;
pub mod state;
pub mod types;

pub use description::{Causality, ModelDescription, Start, VarInfo, VarType, Variability};
pub use model::{FmuModel, StepError};

#[cfg(test)]
mod tests;
