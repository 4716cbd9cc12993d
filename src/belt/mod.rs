//! The belt-drive physics core: the planar discrete belt model of
//! K. Kubas (2014), sections 2.1-2.3. Nothing in here knows about FMI.
//!
//! * [`params`]: parameters, the paper's two drives, validation;
//! * [`layout`]: belt path, body length for the preload, mounted bodies;
//! * [`contact`]: penalty contact, eq. 4-11;
//! * [`friction`]: the two friction laws, eq. 12-19 and ref. [11];
//! * [`elements`]: the accessory-drive elements (V-groove, tensioner arm,
//!   one-way decoupler) as force laws with partials and energy;
//! * [`model`]: equations of motion, eq. 20-24 (the right-hand side);
//! * [`stepping`]: adaptive step-size control shared by the integrators;
//! * [`rkf45`]: the adaptive Runge-Kutta-Fehlberg 4(5) integrator;
//! * [`jacobian`], [`iteration_matrix`], [`rosenbrock`]: the stiff
//!   integrator (Rosenbrock-W ROS34PW2, analytic Jacobian, O(n) stage solve);
//! * [`trig`]: branch-free sine, cosine and angle wrap for the vectorised loops;
//! * [`drive`]: a drive that runs, with its outputs.

pub mod contact;
pub mod drive;
pub mod elements;
pub mod friction;
pub mod iteration_matrix;
pub mod jacobian;
pub mod layout;
pub mod model;
pub mod params;
pub mod rkf45;
pub mod rosenbrock;
pub mod stepping;
pub mod trig;

pub use drive::{Drive, Outputs};
pub use model::Inputs;
pub use params::{DriveParams, FrictionLaw, ParamError};
