//! The integrators and their numerics, for any [`step_control::OdeSystem`]:
//! nothing in here writes a force law.
//!
//! * [`knobs`]: every internal solver knob with its value and why;
//! * [`step_control`]: the ODE interface, counters, failures and the
//!   adaptive step-size control shared by the integrators;
//! * [`rkf45`]: the adaptive Runge-Kutta-Fehlberg 4(5) integrator;
//! * [`jacobian`], [`iteration_matrix`], [`rosenbrock`]: the stiff
//!   integrator (Rosenbrock-W ROS34PW2, analytic Jacobian, O(n) stage solve);
//!   [`stiff_system`]: what it needs of a system (`StiffSystem`, the
//!   `EnergyBalance` of its energy check).

pub mod iteration_matrix;
pub mod jacobian;
pub mod knobs;
pub mod rkf45;
pub mod rosenbrock;
pub mod step_control;
pub mod stiff_system;
