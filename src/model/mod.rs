//! The belt-drive model: the planar discrete belt model of K. Kubas (2014),
//! sections 2.1-2.3, as equations of motion. Nothing in here knows about
//! FMI or about how the equations are integrated ([`crate::solver`]).
//!
//! * [`params`]: parameters, the paper's two drives, validation;
//! * [`param_id`]: how errors and warnings name a parameter (an id, spelt
//!   by whoever shows the message);
//! * [`layout`]: belt path, body length for the preload, mounted bodies;
//! * [`elements`]: the force laws, each once (spring-dampers, contact,
//!   friction, pulley drive and load, V-groove, one-way decoupler,
//!   tensioner arm) with partials, energy and dissipation;
//! * [`system`]: the drive's equations of motion, eq. 20-24 (`BeltSystem`,
//!   the right-hand side, the creep reset, the stored energy);
//! * [`state`]: a body's block of the state vector by name (position,
//!   angle, velocity, spin, creep);
//! * [`simd`]: the instruction set detected once, and the dispatch of the
//!   vector kernels (the only `target_feature` code);
//! * [`trig`]: branch-free sine, cosine and angle wrap for the vectorised loops.

pub mod elements;
pub mod layout;
pub mod matmul;
pub mod param_id;
pub mod params;
pub mod simd;
pub mod state;
pub mod system;
pub mod trig;
