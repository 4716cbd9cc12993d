//! The body-passing component of the instantaneous outputs: how much of the
//! alternator's belt torque and of each span tension oscillates at the
//! frequency at which the belt's bodies pass a point of the path,
//! f_bp = v / l (belt speed over body length), a frequency a continuous belt
//! does not have.
//!
//! `cargo run --profile ci --example body_passing -- [SET ...] [rpm=R]
//! [method=stiff|rkf45] [NAME=VALUE ...]`, NAME=VALUE any parameter by its
//! FMU variable name (e.g. `belt.nBodies=320 contact.points=1`), SET one of
//! `acc4` (`parameters/accessory-drive-4.ssv`, the default together with
//! `tens`), `tens`
//! (`parameters/accessory-drive-tensioner.ssv`); the crank at R rpm (800,
//! idle, by default; the load damping scaled by 800 / R so the load torques
//! keep their idle values), RKF45 at relTol 1e-4 by default. Each run
//! settles for 0.1 s after the 0.5 s speed ramp, then samples the outputs
//! every 20 us for 0.2 s and prints, per signal, its mean and the amplitude
//! of its largest spectral line within 5 % of f_bp and of 2 f_bp and f_bp / 2
//! (Hann window, single-frequency DFT on a grid of 0.1 % of f_bp), plus the
//! peak-to-peak swing.

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

#[path = "common/body_passing.rs"]
mod body_passing;

use belt_drive::model::params::Method;

fn run(set: &str, rpm: f64, method: Method, overrides: &[(String, String)]) {
    let (p, f_bp, signals) = body_passing::measure_with(set, rpm, method, overrides);
    let v = p.pulleys[0].omega_ramp.abs() * p.pulleys[0].radius;
    println!(
        "{set} at {rpm} rpm ({method:?}, relTol 1e-4, {} bodies): belt speed {v:.2} m/s, \
         body-passing frequency {f_bp:.1} Hz",
        p.belt.n_bodies
    );
    for s in &signals {
        let (a1, f1) = s.at_f_bp;
        println!(
            "  {}: mean {:.3}, peak-to-peak {:.3}; at f_bp {a1:.4} ({:.1} % of the mean, \
             line at {f1:.1} Hz), at 2 f_bp {:.4}, at f_bp/2 {:.4}",
            s.name,
            s.mean,
            s.peak_to_peak,
            100.0 * a1 / s.mean.abs(),
            s.at_2f_bp,
            s.at_half_f_bp
        );
    }
}

fn main() {
    let mut sets = Vec::new();
    let (mut rpm, mut method) = (800.0, Method::Rkf45);
    let mut overrides = Vec::new();
    for a in std::env::args().skip(1) {
        match a.split_once('=') {
            Some(("rpm", r)) => rpm = r.parse().expect("rpm"),
            Some(("method", "stiff")) => method = Method::Rosenbrock,
            Some(("method", "rkf45")) => method = Method::Rkf45,
            Some((name, v)) if name.contains('.') => overrides.push((name.into(), v.into())),
            None => sets.push(a),
            _ => panic!("argument {a}"),
        }
    }
    if sets.is_empty() {
        sets = vec!["acc4".into(), "tens".into()];
    }
    for s in &sets {
        run(s, rpm, method, &overrides);
    }
}
