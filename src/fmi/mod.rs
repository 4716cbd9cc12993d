//! FMI 2.0 Co-Simulation plumbing: C types, logging, the state machine,
//! FMU-state framing and the exported C functions. Generic over
//! [`FmuModel`]; knows nothing about belts.
//!
//! * [`types`]: `fmi2TypesPlatform.h` / `fmi2FunctionTypes.h` as `repr(C)`.
//! * [`logging`]: categories, fmi2SetDebugLogging, the logger callback.
//! * [`instance`]: one instance and its state machine (FMI 2.0 section 4.2.4).
//! * [`state`]: `fmi2FMUstate` snapshots and their serialized form.
//! * [`api`]: the functions at the pointer level, generic over the model.
//! * [`exports`]: `#[no_mangle] extern "C" fn fmi2...` for
//!   `crate::fmu_model::BeltDrive`.

pub mod api;
pub mod exports;
pub mod instance;
pub mod logging;
pub mod model;
pub mod state;
pub mod types;

pub use model::{FmuModel, StepError};

#[cfg(test)]
mod tests;
