//! Where does T_tight + T_slack go? A measurement on the section-4 5PK drive
//! (docs/validation.md, "Convergence"): the tension of every SDE, grouped by
//! where its gap lies (top span, bottom span, each wrap), averaged over
//! snapshots in steady operation, against the mounted belt at rest.
//!
//! The belt's length is fixed by the path, so its mean tension can only move
//! with the path (penetrations on the wraps) and the sum of the span forces
//! only with how the tension is distributed over the wraps. The output splits
//! 2 x mean span force - 2 x preload into those two parts.
//!
//! `cargo run --release --example tension_sum -- [bodies] [method 1|2]
//! [relTol] [law creep|kubas2014] [dv]`

use belt_drive::model::params::Method;
use belt_drive::model::system::{Recorder, Workspace};
use belt_drive::{Drive, DriveParams, FrictionLaw};

/// Per-snapshot record: SDE tensions and gap midpoints, penetrations and
/// normal forces of the contacts.
struct Snapshot {
    tension: Vec<f64>,
    mid: Vec<[f64; 2]>,
    /// (pulley, penetration, normal force) of each active contact.
    contacts: Vec<(usize, f64, f64)>,
}

impl Recorder for Snapshot {
    const ACTIVE: bool = true;
    fn sde(&mut self, k: usize, tension: f64, mid: [f64; 2]) {
        self.tension[k] = tension;
        self.mid[k] = mid;
    }
    fn contact(&mut self, _body: usize, pulley: usize, n: f64, _f: f64, _v_t: f64, p: f64) {
        if n > 0.0 {
            self.contacts.push((pulley, p, n));
        }
    }
}

/// Regions of the two-pulley drive (pulley 1 left at x1, pulley 2 right).
const TOP: usize = 0;
const BOTTOM: usize = 1;
const WRAP1: usize = 2;
const WRAP2: usize = 3;
const NAMES: [&str; 4] = [
    "top span",
    "bottom span",
    "wrap, pulley 1",
    "wrap, pulley 2",
];

#[derive(Default, Clone, Copy)]
struct Sums {
    tension: [f64; 4],
    count: [f64; 4],
    pen: [f64; 2],
    pen_count: [f64; 2],
    all: f64,
    all_count: f64,
    span_mid: [f64; 2],
    samples: f64,
}

fn snapshot(d: &mut Drive, x1: f64, x2: f64, acc: &mut Sums) {
    let sys = d.system().clone();
    let n = sys.n_bodies();
    let mut s = Snapshot {
        tension: vec![0.0; n],
        mid: vec![[0.0; 2]; n],
        contacts: Vec::new(),
    };
    let mut dy = vec![0.0; d.state().len()];
    sys.rhs(&mut Workspace::new(), d.time(), d.state(), &mut dy, &mut s);
    for k in 0..n {
        let [x, y] = s.mid[k];
        let region = if x < x1 {
            WRAP1
        } else if x > x2 {
            WRAP2
        } else if y > 0.0 {
            TOP
        } else {
            BOTTOM
        };
        acc.tension[region] += s.tension[k];
        acc.count[region] += 1.0;
        acc.all += s.tension[k];
        acc.all_count += 1.0;
    }
    for &(j, p, _) in &s.contacts {
        acc.pen[j] += p;
        acc.pen_count[j] += 1.0;
    }
    let o = d.outputs();
    acc.span_mid[0] += o.span_tension[0];
    acc.span_mid[1] += o.span_tension[1];
    acc.samples += 1.0;
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let n: usize = arg(0, "150").parse().unwrap();
    let method: u32 = arg(1, "1").parse().unwrap();
    let rtol: f64 = arg(2, "1e-4").parse().unwrap();
    let law = arg(3, "creep");
    let dv: f64 = arg(4, "1e-3").parse().unwrap();

    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = n;
    p.probe_body = 1;
    p.solver.method = if method == 2 {
        Method::Rosenbrock
    } else {
        Method::Rkf45
    };
    p.solver.rel_tol = rtol;
    p.solver.abs_tol = rtol * 1e-2;
    if law == "kubas2014" {
        p.friction.law = FrictionLaw::Kubas2014;
        p.friction.dv = dv;
    } else {
        p.friction.law = FrictionLaw::Creep;
    }
    let (x1, x2) = (p.pulleys[0].x, p.pulleys[1].x);
    let t0 = p.belt.preload;
    let ea = p.belt.ea;

    let mut d = Drive::new(&p, 0.0).expect("parameters");
    let layout = d.layout().clone();
    // The mounted belt at rest (t = 0: pre-set penetrations, no torque yet).
    let mut rest = Sums::default();
    snapshot(&mut d, x1, x2, &mut rest);

    // Steady operation: 26 snapshots over 0.35-0.6 s (after the 0.3 s ramp).
    let mut run = Sums::default();
    d.advance(0.35).expect("advance");
    for k in 0..=25 {
        let t = 0.35 + 0.01 * k as f64;
        d.advance(t).expect("advance");
        snapshot(&mut d, x1, x2, &mut run);
    }
    let stats = d.stats();

    let mean = |s: &Sums, r: usize| s.tension[r] / s.count[r].max(1.0);
    println!(
        "5PK drive, {n} bodies, {law}{}, method {method}, relTol {rtol:e}; {:?}",
        if law == "kubas2014" {
            format!(" dv = {dv:e}")
        } else {
            String::new()
        },
        stats
    );
    println!(
        "path length {:.6} m, body length {:.6} m, preload {t0} N, EA {ea} N",
        layout.path_length, layout.body_length
    );
    for (label, s) in [("at rest (t = 0)", &rest), ("running (0.35-0.6 s)", &run)] {
        println!("\n{label}:");
        for (r, name) in NAMES.iter().enumerate() {
            println!(
                "  {:<16} mean SDE tension {:9.3} N over {:6.1} SDEs",
                name,
                mean(s, r),
                s.count[r] / s.samples
            );
        }
        let all = s.all / s.all_count;
        println!("  whole belt       mean SDE tension {all:9.3} N");
        for j in 0..2 {
            println!(
                "  pulley {}: mean penetration {:.4e} m over {:.1} contacts (mounted: {:.4e} m)",
                j + 1,
                s.pen[j] / s.pen_count[j].max(1.0),
                s.pen_count[j] / s.samples,
                layout.wraps[j].penetration
            );
        }
        let (m1, m2) = (s.span_mid[0] / s.samples, s.span_mid[1] / s.samples);
        println!(
            "  mid-span SDEs (the FMU's span tensions): {m1:.3} / {m2:.3} N, sum {:.3} N = 2 T0 {:+.3} %",
            m1 + m2,
            100.0 * ((m1 + m2) / (2.0 * t0) - 1.0)
        );
    }

    // Decomposition of the sum of the two span forces (run, span means).
    let (ts, tb) = (mean(&run, TOP), mean(&run, BOTTOM));
    let n_span = run.count[TOP] + run.count[BOTTOM];
    let n_wrap = run.count[WRAP1] + run.count[WRAP2];
    let all_rest = rest.all / rest.all_count;
    let all_run = run.all / run.all_count;
    let wrap_mean = (run.tension[WRAP1] + run.tension[WRAP2]) / n_wrap;
    let span_avg = 0.5 * (ts + tb);
    // n T_all = n_span (ts + tb) / 2 + n_wrap wrap_mean (equal spans), so
    // (ts + tb) / 2 - T_all = n_wrap / n_span (T_all - wrap_mean).
    println!("\ndecomposition of (T_top + T_bottom) / 2 - preload (span means):");
    println!(
        "  (T_top + T_bottom) / 2 = {span_avg:.3} N; excess over T0 {:+.3} N ({:+.3} %)",
        span_avg - t0,
        100.0 * (span_avg / t0 - 1.0)
    );
    println!(
        "  a) mounted belt's mean tension - T0            {:+.3} N",
        all_rest - t0
    );
    println!(
        "  b) change of the belt's mean tension in running {:+.3} N",
        all_run - all_rest
    );
    // The path on a wrap runs at radius r - p: less mean penetration is a
    // longer path, which the belt must stretch to cover.
    let mut d_path = 0.0;
    for (j, w) in layout.wraps.iter().enumerate().take(2) {
        let p_rest = rest.pen[j] / rest.pen_count[j].max(1.0);
        let p_run = run.pen[j] / run.pen_count[j].max(1.0);
        d_path -= w.angle * (p_run - p_rest);
    }
    println!(
        "     closed form from the wraps' mean penetrations: path {:+.3e} m, EA dL/L = {:+.3} N",
        d_path,
        ea * d_path / layout.path_length
    );
    println!(
        "  c) wraps below the span average: n_wrap/n_span (T_all - T_wrap) = {:.3} x ({:.3} - {:.3}) = {:+.3} N",
        n_wrap / n_span,
        all_run,
        wrap_mean,
        n_wrap / n_span * (all_run - wrap_mean)
    );
    println!(
        "  check a + b + c = {:+.3} N",
        all_rest - t0 + all_run - all_rest + n_wrap / n_span * (all_run - wrap_mean)
    );
}
