//! The heavy-belt running drive of the running modal analysis (docs/modes.md),
//! shared by examples/floquet_substeps.rs and tests/modes.rs: included with
//! `#[path]`, so each keeps one definition.

use belt_drive::model::params::Method;
use belt_drive::DriveParams;

/// A heavy belt (0.5 kg/m) under 100 N on two 50 mm pulleys 0.4 m apart,
/// pulley 1 speed-driven to -140 rad/s over 0.1 s, pulley 2 free and
/// unloaded; `n` bodies, integrated by `method`.
pub fn heavy_running(n: usize, method: Method) -> DriveParams {
    let mut p = DriveParams::kubas_section4();
    p.pulleys[0].radius = 0.05;
    p.pulleys[0].torque_ramp = 0.0;
    p.pulleys[0].speed_driven = true;
    p.pulleys[0].omega_ramp = -140.0;
    p.pulleys[0].ramp_time = 0.1;
    p.pulleys[1].radius = 0.05;
    p.pulleys[1].x = 0.4;
    p.pulleys[1].inertia = 1e-3;
    p.pulleys[1].load_damping = 0.0;
    p.belt.n_bodies = n;
    p.belt.preload = 100.0;
    p.belt.mass_per_length = 0.5;
    p.solver.method = method;
    p.probe_body = 0;
    p
}
