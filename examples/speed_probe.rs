//! Instruction-count probe of the stiff method on an accessory set:
//! `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*measured*'
//! target/ci/examples/speed_probe [acc4|tens] RPM [T0] [WINDOW] [stiff|rkf45]`.
//! Runs the set (speed set as in `step_profile`, ramp 0.2 s) to T0
//! (default 0.05 s) and then WINDOW (default 0.01 s) in 1 ms communication
//! steps inside `measured`; prints steps, rejections, Jacobians.

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

use belt_drive::drive::Integrator;
use belt_drive::model::params::Method;
use belt_drive::Drive;

#[inline(never)]
fn measured(d: &mut Drive, t0: f64, window: f64) {
    let n = (window / 1e-3).round() as usize;
    for k in 1..=n {
        d.advance(t0 + k as f64 * 1e-3).expect("runs");
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let set = match a.first().map(String::as_str) {
        Some("tens") => "tens",
        _ => "acc4",
    };
    let rpm: f64 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(800.0);
    let t0: f64 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.05);
    let window: f64 = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.01);
    let method = match a.get(4).map(String::as_str) {
        Some("rkf45") => Method::Rkf45,
        _ => Method::Rosenbrock,
    };
    let mut p = accessory::at_rpm(set, rpm, method);
    for q in &mut p.pulleys {
        q.ramp_time = 0.2;
    }
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    let n0 = (t0 / 1e-3).round() as usize;
    for k in 1..=n0 {
        d.advance(k as f64 * 1e-3).expect("runs");
    }
    let s0 = d.stats();
    measured(&mut d, n0 as f64 * 1e-3, window);
    let s1 = d.stats();
    let jac = match d.integrator() {
        Integrator::Rosenbrock(r) => r.jacobians,
        Integrator::Rkf45(_) => 0,
    };
    println!(
        "{set} {rpm} rpm: {} steps, {} rejected, {} rhs; jacobians (cumulative) {jac}",
        s1.steps - s0.steps,
        s1.rejected - s0.rejected,
        s1.rhs_evals - s0.rhs_evals
    );
}
