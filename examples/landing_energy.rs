//! Where an integrator's energy error is made on the 60-body drive of
//! `tests/defaults.rs` (docs/model.md, "Not the landing either"): the drive
//! is advanced one integrator step at a time (each call to the step the
//! integrator proposes), and each step's energy residual, the input work less
//! the dissipated energy less the change of the stored energy, is summed by
//! the step's relation to the bodies' landings on the pulleys.
//!
//! `cargo run --profile ci --example landing_energy -- [bodies] [solver.method] [contact.points] [off]`
//! (60 bodies, the stiff method (2) and the drive's own contact points (`-`)
//! when not given; relTol 1e-4, means over 0.3-0.5 s; `off` runs the stiff
//! method without its energy check).

use belt_drive::model::params::Method;
use belt_drive::model::system::{BeltSystem, Recorder, Workspace};
use belt_drive::Drive;

#[path = "common/sixty_body.rs"]
mod sixty_body;
use sixty_body::sixty_body_drive;

/// The body-pulley pairs in contact (normal force > 0).
#[derive(Default)]
struct Contacts(Vec<(usize, usize)>);

impl Recorder for Contacts {
    const ACTIVE: bool = true;
    fn sde(&mut self, _k: usize, _tension: f64, _mid: [f64; 2]) {}
    fn contact(&mut self, body: usize, pulley: usize, n: f64, _f: f64, _v_t: f64, _p: f64) {
        if n > 0.0 {
            self.0.push((body, pulley));
        }
    }
}

fn contacts(sys: &BeltSystem, ws: &mut Workspace, t: f64, y: &[f64]) -> Vec<(usize, usize)> {
    let mut c = Contacts::default();
    let mut dy = vec![0.0; y.len()];
    sys.rhs(ws, t, y, &mut dy, &mut c);
    c.0.sort_unstable();
    c.0
}

/// The input work less the dissipated and the stored energy [J]. The state's
/// friction-work accumulator includes the work stored in the creep springs,
/// which the potential energy also holds: the dissipated energy is that
/// accumulator less the creep springs' energy, as `energy.dissipated` is.
fn balance(sys: &BeltSystem, y: &[f64]) -> f64 {
    let e = sys.state_layout().energy();
    let (kinetic, potential) = sys.energies(y);
    let dissipated = y[e.dissipated] - sys.creep_spring_energy(y);
    y[e.work_in] - dissipated - kinetic - potential
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = a.first().map_or(60, |v| v.parse().unwrap());
    let method = match a.get(1).map(String::as_str) {
        Some("1") => Method::Rkf45,
        _ => Method::Rosenbrock,
    };
    let mut p = sixty_body_drive();
    p.belt.n_bodies = n;
    p.probe_body = 0;
    p.solver.method = method;
    p.solver.rel_tol = 1e-4;
    if let Some(k) = a.get(2).filter(|k| k.as_str() != "-") {
        p.contact.points = k.parse().unwrap();
    }
    let (t0, t1) = (0.3, 0.5);
    let mut d = Drive::new(&p, 0.0).expect("parameters");
    d.set_energy_check(a.get(3).map(String::as_str) != Some("off"));
    d.advance(t0).expect("advance");
    let sys = d.system().clone();
    let mut ws = Workspace::new();
    // the time each body-pulley contact began
    let mut onset: Vec<((usize, usize), f64)> = Vec::new();
    // rows: a body landed in the step, ending within 0.3 / 1 ms of a
    // landing, a body left (none landed), all; columns: steps, time, residual
    let windows = [3e-4, 1e-3];
    let mut sums = [[0.0f64; 3]; 5];
    let steps0 = d.stats().steps;
    let mut y0 = d.state().to_vec();
    let mut c0 = contacts(&sys, &mut ws, d.time(), &y0);
    for &k in &c0 {
        onset.push((k, f64::NEG_INFINITY));
    }
    while d.time() < t1 {
        let t = d.time();
        let s = d.stats().steps;
        d.advance((t + d.next_step_size()).min(t1))
            .expect("advance");
        let (h, y1) = (d.time() - t, d.state().to_vec());
        let c1 = contacts(&sys, &mut ws, d.time(), &y1);
        let steps = (d.stats().steps - s) as f64;
        let residual = balance(&sys, &y1) - balance(&sys, &y0);
        let landed = c1.iter().any(|k| c0.binary_search(k).is_err());
        let left = c0.iter().any(|k| c1.binary_search(k).is_err());
        onset.retain(|(k, _)| c1.binary_search(k).is_ok());
        for k in &c1 {
            if !onset.iter().any(|(o, _)| o == k) {
                onset.push((*k, d.time()));
            }
        }
        let youngest = onset
            .iter()
            .map(|(_, o)| d.time() - o)
            .fold(f64::INFINITY, f64::min);
        let rows = [
            landed,
            youngest <= windows[0],
            youngest <= windows[1],
            left && !landed,
            true,
        ];
        for (row, _) in sums.iter_mut().zip(rows).filter(|(_, r)| *r) {
            row[0] += steps;
            row[1] += h;
            row[2] += residual;
        }
        y0 = y1;
        c0 = c1;
    }
    let all = sums[4];
    println!(
        "60-body drive, {n} bodies, contact.points {}, {method:?} at relTol 1e-4, {t0}-{t1} s: {} steps, energy residual {:.3} W",
        p.contact.points,
        d.stats().steps - steps0,
        all[2] / (t1 - t0)
    );
    let names = [
        "a body lands within the step",
        "ending within 0.3 ms of a landing",
        "ending within 1 ms of a landing",
        "a body leaves a pulley within the step, none lands",
    ];
    for (name, row) in names.iter().zip(&sums) {
        println!(
            "  {name}: {} steps, {:.1} % of the time, {:.1} % of the residual ({:.3} W), mean step {:.2e} s",
            row[0],
            100.0 * row[1] / all[1],
            100.0 * row[2] / all[2],
            row[2] / (t1 - t0),
            row[1] / row[0].max(1.0)
        );
    }
}
