#![warn(missing_docs)]
//! BeltDrive: the planar discrete belt-drive model of K. Kubas (2014) as an
//! FMI 2.0 Co-Simulation FMU.
//!
//! * [`model`] is the physics core (parameters, layout, the force laws, the
//!   equations of motion); [`solver`] integrates it (RKF45, Rosenbrock-W);
//!   [`drive`] is a drive that runs, with its outputs. They know nothing
//!   about FMI.
//! * [`fmi`] is the FMI 2.0 plumbing (C ABI, state machine, logging, FMU
//!   state). It knows nothing about belts beyond the [`fmi::FmuModel`] trait.
//! * [`drawing`]: an SVG of the mounted drive (`cargo xtask layout`).
//! * `modes` (feature `modes`): modal analysis from the analytic Jacobian
//!   (docs/modes.md).
//! * [`fmu`] connects the two: it maps the variables of
//!   `modelDescription/modelDescription.xml` (its generated table,
//!   [`fmu::variables`]) onto the core's parameters, inputs and outputs.

pub mod drawing;
pub mod drive;
pub mod fmi;
pub mod fmu;
pub mod interval;
pub mod model;
#[cfg(feature = "modes")]
pub mod modes;
pub mod solver;

pub use drive::{Drive, Outputs};
pub use model::params::{DriveParams, FrictionLaw, ParamError};
pub use model::system::Inputs;

// The FMU's C functions, for its one model.
export_fmi2_co_simulation!(fmu::BeltDrive);
