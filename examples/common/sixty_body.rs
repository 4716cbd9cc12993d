//! The 60-body drive of `tests/defaults.rs` (`integrators_agree_on_a_sixty_body_drive`),
//! shared by examples/wrap_profile.rs, examples/landing_energy.rs and
//! examples/stiff_energy.rs: included
//! with `#[path]`, so each keeps one definition.

use belt_drive::DriveParams;

/// Two 50 mm pulleys 0.25 m apart, 300 N preload, 60 bodies, pulley 1
/// driven by 2 N m (reached over 0.05 s), pulley 2 loaded by 0.05 N m s/rad.
pub fn sixty_body_drive() -> DriveParams {
    let mut p = DriveParams::default();
    p.belt.n_bodies = 60;
    p.belt.preload = 300.0;
    p.pulleys[0].radius = 0.05;
    p.pulleys[1].radius = 0.05;
    p.pulleys[1].x = 0.25;
    p.pulleys[0].torque_ramp = -2.0;
    p.pulleys[0].ramp_time = 0.05;
    p.pulleys[1].load_damping = 0.05;
    p.pulleys[1].ramp_time = 0.05;
    p
}
