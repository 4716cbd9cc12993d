//! Force laws of the accessory-drive elements as pure functions, each with
//! its partial derivatives, stored energy and dissipated power side by side
//! (docs/model.md, "Accessory drives"):
//!
//! * [`groove`]: the wedge factor of a V-ribbed groove on the friction
//!   coefficient;
//! * [`tensioner`]: the pivot torque of an automatic tensioner arm (spring,
//!   viscous damper, regularised Coulomb friction);
//! * [`decoupler`]: the one-way decoupler between a pulley hub and its
//!   rotor (torsion spring and damper in series with a one-way clutch).

pub mod decoupler;
pub mod groove;
pub mod tensioner;
