#![warn(missing_docs)]
//! BeltDrive: the planar discrete belt-drive model of K. Kubas (2014) as an
//! FMI 2.0 Co-Simulation FMU.
//!
//! * [`belt`] is the physics core (bodies, contact, friction, layout, RKF45).
//!   It knows nothing about FMI.
//! * [`fmi`] is the FMI 2.0 plumbing (C ABI, state machine, logging, FMU
//!   state). It knows nothing about belts beyond the [`fmi::FmuModel`] trait.
//! * [`drawing`]: an SVG of the mounted drive (`cargo xtask layout`).
//! * `modes` (feature `modes`): modal analysis from the analytic Jacobian
//!   (docs/modes.md).
//! * [`fmu`] connects the two: it maps the variables of
//!   `modelDescription/modelDescription.xml` (its generated table,
//!   [`fmu::variables`]) onto the core's parameters, inputs and outputs.

pub mod belt;
pub mod drawing;
pub mod fmi;
pub mod fmu;
#[cfg(feature = "modes")]
pub mod modes;

// The FMU's C functions, for its one model.
export_fmi2_co_simulation!(fmu::BeltDrive);
