//! The force laws of the model, each written once: its force, partial
//! derivatives, stored energy and dissipated power side by side. The
//! right-hand side, the Jacobian, the outputs and the energy balance call
//! these and compute no force of their own.
//!
//! * [`sde`]: translational and torsional spring-damper between bodies, eq. 20-23;
//! * [`contact`]: penalty contact and the contact force with friction, eq. 4-11, 19;
//! * [`friction`]: the friction laws (a `Law` each: coefficient, partials, creep
//!   cap, spring energy, whether it follows the sliding velocity), eq. 12-19 and ref. [11];
//! * [`pulley`]: a pulley's drive and load, eq. 24;
//! * [`groove`]: the wedge factor of a V-ribbed groove on the friction
//!   coefficient;
//! * [`decoupler`]: the one-way decoupler between a pulley hub and its
//!   rotor (torsion spring and damper in series with a one-way clutch);
//! * [`transverse`]: the transverse (span) damping of each body's centre velocity
//!   across its axis;
//! * [`tensioner`]: an automatic tensioner arm: the pulley centre on the
//!   arm, the moment of the hub force about the pivot and the arm's pivot
//!   torque (spring, viscous damper, Coulomb friction with presliding).

pub(crate) mod contact;
pub(crate) mod decoupler;
pub(crate) mod friction;
pub(crate) mod groove;
pub(crate) mod pulley;
pub(crate) mod sde;
pub(crate) mod tensioner;
pub(crate) mod transverse;

// The elements' types that appear in the core's public interface
// (`BeltSystem`'s accessors, `PulleyConst`), and what the reference
// transcription of the right-hand side (tests/rhs_reference.rs) calls.
pub use contact::ContactLaw;
pub use decoupler::Decoupler;
pub use friction::{Friction, Law};
pub use groove::friction_factor;
pub use sde::{AxialSde, TorsionalSde};
pub use tensioner::{Arm, PivotFriction};
pub use transverse::TransverseDamper;
