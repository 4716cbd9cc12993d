//! The heavy-belt drive of `tests/python/test_mean_forces.py`, shared by
//! examples/wrap_profile.rs and examples/stiff_energy.rs: included with
//! `#[path]`, so each keeps one definition.

use belt_drive::DriveParams;

/// A 60 mm crank speed-driven to 150 rad/s over 0.1 s, the default driven
/// pulley 0.35 m away loaded by 0.01 N m s/rad, belt 0.3 kg/m, 120 bodies.
pub fn heavy_belt_drive() -> DriveParams {
    let mut p = DriveParams::default();
    p.belt.n_bodies = 120;
    p.belt.mass_per_length = 0.3;
    p.pulleys[0].radius = 0.06;
    p.pulleys[0].speed_driven = true;
    p.pulleys[0].omega_ramp = -150.0;
    p.pulleys[0].torque_ramp = 0.0;
    p.pulleys[0].ramp_time = 0.1;
    p.pulleys[1].x = 0.35;
    p.pulleys[1].load_damping = 0.01;
    p.pulleys[1].ramp_time = 0.1;
    p
}
