//! The belt-drive physics core: the planar discrete belt model of
//! K. Kubas (2014), sections 2.1-2.3. Nothing in here knows about FMI.
//!
//! * [`params`]: parameters, the paper's two drives, validation;
//! * [`param_id`]: how errors and warnings name a parameter (an id, spelt
//!   by whoever shows the message);
//! * [`layout`]: belt path, body length for the preload, mounted bodies;
//! * [`elements`]: the force laws, each once (spring-dampers, contact,
//!   friction, pulley drive and load, V-groove, one-way decoupler,
//!   tensioner arm) with
//!   partials, energy and dissipation;
//! * [`system`]: the drive's equations of motion, eq. 20-24 (`BeltSystem`, the right-hand side);
//! * [`solver_params`]: every internal solver knob with its value and why;
//! * [`stepping`]: adaptive step-size control shared by the integrators;
//! * [`rkf45`]: the adaptive Runge-Kutta-Fehlberg 4(5) integrator;
//! * [`jacobian`], [`iteration_matrix`], [`rosenbrock`]: the stiff
//!   integrator (Rosenbrock-W ROS34PW2, analytic Jacobian, O(n) stage solve);
//! * [`simd`]: the instruction set detected once, and the dispatch of the
//!   vector kernels (the only `target_feature` code);
//! * [`trig`]: branch-free sine, cosine and angle wrap for the vectorised loops;
//! * [`drive`]: a drive that runs, with its outputs.

pub mod drive;
pub mod elements;
pub mod iteration_matrix;
pub mod jacobian;
pub mod layout;
pub mod param_id;
pub mod params;
pub mod rkf45;
pub mod rosenbrock;
pub mod simd;
pub mod solver_params;
pub mod stepping;
pub mod system;
pub mod trig;

pub use drive::{Drive, Outputs};
pub use params::{DriveParams, FrictionLaw, ParamError};
pub use system::Inputs;
