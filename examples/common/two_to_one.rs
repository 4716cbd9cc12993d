//! The 2:1 drive of the mesh study (docs/validation.md, "Slip against the
//! mesh"), shared by examples/mesh_study.rs, examples/wrap_profile.rs and
//! tests/mesh.rs: included with `#[path]`, so each keeps one definition.

use belt_drive::model::params::PulleyParams;
use belt_drive::DriveParams;

/// The 2:1 drive: 40 mm pulley speed-driven at -40 rad/s (0.1 s ramp), 80 mm
/// pulley loaded by a viscous 30 N m at its speed; 5PK belt, 500 N preload.
pub fn two_to_one() -> DriveParams {
    let mut p = DriveParams::kubas_section4();
    p.belt.preload = 500.0;
    let mut p1 = PulleyParams::paper_5pk(0.0, 0.0);
    p1.radius = 0.04;
    p1.speed_driven = true;
    p1.omega_ramp = -40.0;
    p1.ramp_time = 0.1;
    let mut p2 = PulleyParams::paper_5pk(0.3, 0.0);
    p2.radius = 0.08;
    p2.inertia = 2e-3;
    p2.load_damping = 30.0 / 20.0;
    p2.ramp_time = 0.1;
    p.pulleys = vec![p1, p2];
    p
}
