//! An accessory set of `parameters/` run at another crank speed with its
//! loads held at their idle torques: the one definition the speed benchmark
//! (benches/speeds), the step and speed profiles, the body-passing and
//! communication-step examples and tests/defaults.rs share (included with
//! `#[path]`; the including module declares `mod ssv` from
//! examples/common/ssv.rs beside it).

use belt_drive::model::params::Method;
use belt_drive::DriveParams;

/// The parameter file of a set: `acc4` (`accessory-drive-4.ssv`), `tens`
/// (`accessory-drive-tensioner.ssv`) or a file name of `parameters/`.
pub fn file(set: &str) -> &str {
    match set {
        "acc4" => "accessory-drive-4.ssv",
        "tens" => "accessory-drive-tensioner.ssv",
        f if f.ends_with(".ssv") => f,
        _ => panic!("set {set}: acc4, tens or a file of parameters/"),
    }
}

/// The set `set` ([`file`]) with its speed-driven crank (pulley 1) brought
/// to `rpm` instead of the set's own speed and every load's damping divided
/// by the same ratio, so that each load torque (damping times speed) keeps
/// the set's value; `method` at relTol 1e-4. The ramps stay the set's.
#[allow(dead_code)] // examples/body_passing.rs calls at_rpm_with
pub fn at_rpm(set: &str, rpm: f64, method: Method) -> DriveParams {
    at_rpm_with(set, rpm, method, &[])
}

/// [`at_rpm`] with the parameters `overrides` (FMU variable name, value)
/// set after the file's (e.g. `belt.nBodies`), before the speed is scaled.
#[allow(dead_code)] // not every including crate overrides
pub fn at_rpm_with(
    set: &str,
    rpm: f64,
    method: Method,
    overrides: &[(String, String)],
) -> DriveParams {
    let mut p = super::ssv::from_ssv_with(file(set), overrides);
    let own = p.pulleys[0].omega_ramp.abs() * 30.0 / std::f64::consts::PI;
    let scale = rpm / own;
    p.pulleys[0].omega_ramp *= scale;
    for q in &mut p.pulleys[1..] {
        q.load_damping /= scale;
    }
    p.solver.method = method;
    p.solver.rel_tol = 1e-4;
    p
}
