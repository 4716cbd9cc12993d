//! The tension, normal force, friction force, creep displacement and
//! relative velocity along both wraps of a two-pulley drive (the 5PK drive of
//! section 4 or the 2:1 drive of docs/validation.md), averaged over snapshots
//! in steady running and binned by the angle travelled from where the belt
//! arrives on the pulley. Shows where a coarse mesh's excess slip comes from
//! (docs/validation.md, "Slip against the mesh").
//!
//! `cargo run --profile ci --example wrap_profile -- [5pk|2to1] [bodies]
//! [bin width, degrees] [contact.points]` (the drive's own `contact.points`
//! when not given or 0).

use belt_drive::belt::params::{Method, PulleyParams};
use belt_drive::belt::system::{Recorder, Workspace, BODY_DOF};
use belt_drive::belt::{Drive, DriveParams};

#[path = "common/two_to_one.rs"]
mod drives;
use drives::two_to_one;

#[derive(Default)]
struct Snap {
    /// (body, pulley, N, f, v_T)
    contacts: Vec<(usize, usize, f64, f64, f64)>,
    /// (tension, midpoint)
    sdes: Vec<(f64, [f64; 2])>,
}

impl Recorder for Snap {
    const ACTIVE: bool = true;
    fn sde(&mut self, _k: usize, tension: f64, mid: [f64; 2]) {
        self.sdes.push((tension, mid));
    }
    fn contact(&mut self, body: usize, pulley: usize, n: f64, f: f64, v_t: f64, _p: f64) {
        if n > 0.0 {
            self.contacts.push((body, pulley, n, f, v_t));
        }
    }
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let which = arg(0, "5pk");
    let n: usize = arg(1, "150").parse().unwrap();
    let bin: f64 = arg(2, "10").parse::<f64>().unwrap().to_radians();
    let mut p = if which == "2to1" {
        two_to_one()
    } else {
        DriveParams::kubas_section4()
    };
    p.belt.n_bodies = n;
    let points: usize = arg(3, "0").parse().unwrap();
    if points > 0 {
        p.contact.points = points;
    }
    p.probe_body = 0;
    p.solver.method = Method::Rosenbrock;
    p.solver.rel_tol = 1e-5;
    p.solver.abs_tol = 1e-7;
    p.solver.max_steps = u64::MAX;
    let (t0, t1) = (0.5, 0.8);
    let mut d = Drive::new(&p, 0.0).expect("parameters");
    let l = d.layout().body_length;
    d.advance(t0).expect("advance");
    let o0 = d.outputs();
    let nb = (2.0 * std::f64::consts::PI / bin).ceil() as usize;
    // per pulley and bin: tension sum/count, N, f, z, v_T sums and count
    let mut ten = vec![[0.0f64; 2]; 2 * nb];
    let mut con = vec![[0.0f64; 5]; 2 * nb];
    let samples = 60;
    let mut span = [0.0; 2];
    // travel angle from the arrival: the belt runs clockwise (pulley 1
    // turns at negative omega) around both pulleys
    let travel = |j: usize, x: f64, y: f64, q: &PulleyParams| -> Option<usize> {
        let (dx, dy) = (x - q.x, y - q.y);
        if dx * dx + dy * dy > (q.radius + 2.0 * l) * (q.radius + 2.0 * l) {
            return None;
        }
        let th = dy.atan2(dx);
        // pulley 1 (left): arrives at the bottom (-90 deg) going clockwise;
        // pulley 2 (right): arrives at the top (+90 deg) going clockwise
        let start = if j == 0 { -0.5 } else { 0.5 } * std::f64::consts::PI;
        let s = (start - th).rem_euclid(2.0 * std::f64::consts::PI);
        Some(((s / bin) as usize).min(nb - 1))
    };
    for k in 1..=samples {
        d.advance(t0 + (t1 - t0) * k as f64 / samples as f64)
            .expect("advance");
        let sys = d.system().clone();
        let y = d.state().to_vec();
        let mut s = Snap::default();
        let mut dy = vec![0.0; y.len()];
        sys.rhs(&mut Workspace::new(), d.time(), &y, &mut dy, &mut s);
        for &(t, [x, yy]) in &s.sdes {
            for j in 0..2 {
                if let Some(b) = travel(j, x, yy, &p.pulleys[j]) {
                    ten[j * nb + b][0] += t;
                    ten[j * nb + b][1] += 1.0;
                }
            }
        }
        for &(i, j, nn, f, vt) in &s.contacts {
            let o = BODY_DOF * i;
            if let Some(b) = travel(j, y[o], y[o + 1], &p.pulleys[j]) {
                let c = &mut con[j * nb + b];
                c[0] += nn;
                c[1] += f;
                c[2] += y[o + 6];
                c[3] += vt;
                c[4] += 1.0;
            }
        }
        let o = d.outputs();
        span[0] += o.span_tension[0] / samples as f64;
        span[1] += o.span_tension[1] / samples as f64;
    }
    let o1 = d.outputs();
    let w: Vec<f64> = (0..2)
        .map(|j| (o1.pulleys[j].angle - o0.pulleys[j].angle) / (t1 - t0))
        .collect();
    let loss = 1.0 - (w[1] * p.pulleys[1].radius).abs() / (w[0] * p.pulleys[0].radius).abs();
    println!(
        "{which}, {n} bodies (l = {:.3} mm), contact.points {}: speed loss {:.4} %, span tensions {:.1} / {:.1} N",
        l * 1e3,
        p.contact.points,
        100.0 * loss,
        span[0],
        span[1]
    );
    for j in 0..2 {
        println!("\npulley {} (travel from arrival [deg], mean SDE tension [N], per contact: N [N], f [N], z [um], v_T [mm/s], contacts per snapshot)", j + 1);
        for b in 0..nb {
            let t = ten[j * nb + b];
            let c = con[j * nb + b];
            if c[4] == 0.0 && t[1] == 0.0 {
                continue;
            }
            let m = c[4].max(1.0);
            println!(
                "{:6.1} {:8.1} | {:7.1} {:8.2} {:8.2} {:8.3} {:5.2}",
                (b as f64 + 0.5) * bin.to_degrees(),
                t[0] / t[1].max(1.0),
                c[0] / m,
                c[1] / m,
                1e6 * c[2] / m,
                1e3 * c[3] / m,
                c[4] / samples as f64
            );
        }
    }
}
