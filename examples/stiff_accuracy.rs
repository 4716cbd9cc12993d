//! What the stiff method's step control buys in accuracy: a drive run with
//! the stiff method at relTol 1e-4 (energy check on and off) against a tight
//! reference (RKF45 at relTol 1e-7), window means of the pulley speeds and
//! span tensions and the slip, with the step counts and CPU time of each run.
//!
//! Two means of each span tension are compared: of `span[j].tension` sampled
//! at the 1 ms communication points (as tests/defaults.rs takes them), and of
//! `span[j].meanTension` (the trapezoidal rule over the integrator's steps).
//! The sampled mean aliases the body-passing ripple: on `acc4` at 6000 rpm the
//! reference's two means of span 3 differ by 0.3 %.
//!
//! `cargo run --profile ci --example stiff_accuracy -- DRIVE RPM [ref=<relTol>]
//! [tols=<relTol>,...] [cache=1]`
//! with DRIVE `5pk` (the FMU's default drive, means over 0.35-0.6 s),
//! `sixty` (the 60-body drive of tests/defaults.rs, 0.3-0.5 s), `acc4` or
//! `tens` (the accessory sets at crank speed RPM with the loads held at their
//! idle torques, examples/common/accessory.rs, the crank ramp shortened to
//! 0.2 s as in tests/defaults.rs, 0.4-0.6 s). RPM is ignored for `5pk` and
//! `sixty`. `tols`: the stiff method's tolerances (1e-4). With `cache=1` the
//! reference is kept in /tmp (`stiff_accuracy_<drive>_<rpm>_<tol>`) and read
//! from there by the next run with `cache=1` (for variants of the stiff
//! method on one model; delete it after a change to the model).

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

#[path = "common/sixty_body.rs"]
mod sixty_body;

#[path = "../benches/common/mod.rs"]
#[allow(dead_code)] // median
mod timing;
use timing::cpu_time;

use belt_drive::drive::Integrator;
use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};

/// Means over a window: pulley speeds from the angle differences, span
/// tensions sampled at the 1 ms communication points.
struct Means {
    omega: Vec<f64>,
    tension: Vec<f64>,
    /// Means of `span[j].meanTension` (the trapezoidal rule over the
    /// integrator's steps within each communication step).
    interval: Vec<f64>,
}

/// The drive, its window, and the pulley whose slip against pulley 1 is
/// compared.
fn setup(name: &str, rpm: f64) -> (DriveParams, f64, f64, usize) {
    match name {
        "5pk" => (DriveParams::default(), 0.35, 0.6, 1),
        "sixty" => (sixty_body::sixty_body_drive(), 0.3, 0.5, 1),
        set => {
            let mut p = accessory::at_rpm(set, rpm, Method::Rosenbrock);
            p.solver.max_steps = DriveParams::default().solver.max_steps;
            for q in &mut p.pulleys {
                q.ramp_time = 0.2;
            }
            (p, 0.4, 0.6, 2)
        }
    }
}

/// Runs `p` with `method` at `rel_tol` (energy check `check`) over the
/// window; prints its counts and returns its means.
fn run(p: &DriveParams, method: Method, rel_tol: f64, check: bool, t0: f64, t1: f64) -> Means {
    let mut p = p.clone();
    p.solver.method = method;
    p.solver.rel_tol = rel_tol;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.set_energy_check(check);
    let c0 = cpu_time();
    let dt = 1e-3;
    let mut t = 0.0;
    while t < t0 - 1e-12 {
        t += dt;
        d.advance(t).expect("runs");
    }
    let np = p.pulleys.len();
    let o0 = d.outputs();
    let s0 = d.stats();
    let j0 = match d.integrator() {
        Integrator::Rosenbrock(r) => r.jacobians,
        Integrator::Rkf45(_) => 0,
    };
    let c1 = cpu_time();
    let n = ((t1 - t0) / dt).round() as usize;
    let mut tension = vec![0.0; np];
    let mut interval = vec![0.0; np];
    let mut last = o0.clone();
    for k in 1..=n {
        d.advance(t0 + k as f64 * dt).expect("runs");
        last = d.outputs();
        for (m, x) in tension.iter_mut().zip(&last.span_tension) {
            *m += x / n as f64;
        }
        for (m, x) in interval.iter_mut().zip(&last.interval.span_mean_tension) {
            *m += x / n as f64;
        }
    }
    let c2 = cpu_time();
    let s1 = d.stats();
    let j1 = match d.integrator() {
        Integrator::Rosenbrock(r) => r.jacobians,
        Integrator::Rkf45(_) => 0,
    };
    let w = t1 - t0;
    println!(
        "  {method:?} relTol {rel_tol:e} energy check {check}: window {:.0} accepted/s, {:.0} \
         rejected/s ({:.1} %), {:.0} RHS/s, {:.0} Jacobians/s; CPU {:.3} s window, {:.3} s total",
        (s1.steps - s0.steps) as f64 / w,
        (s1.rejected - s0.rejected) as f64 / w,
        100.0 * (s1.rejected - s0.rejected) as f64 / (s1.steps - s0.steps).max(1) as f64,
        (s1.rhs_evals - s0.rhs_evals) as f64 / w,
        (j1 - j0) as f64 / w,
        c2 - c1,
        c2 - c0
    );
    Means {
        omega: (0..np)
            .map(|j| (last.pulleys[j].angle - o0.pulleys[j].angle) / w)
            .collect(),
        tension,
        interval,
    }
}

fn main() {
    let (opts, args): (Vec<String>, Vec<String>) =
        std::env::args().skip(1).partition(|a| a.contains('='));
    let mut ref_tol = 1e-7;
    let mut tols = vec![1e-4];
    let mut cached = false;
    for o in &opts {
        let (k, v) = o.split_once('=').expect("key=value");
        match k {
            "ref" => ref_tol = v.parse().expect("ref"),
            "cache" => cached = v == "1",
            "tols" => tols = v.split(',').map(|x| x.parse().expect("tols")).collect(),
            _ => panic!("option {k}"),
        }
    }
    let name = args.first().map_or("acc4", |s| s.as_str());
    let rpm: f64 = args.get(1).map_or(800.0, |s| s.parse().expect("rpm"));
    let (p, t0, t1, sp) = setup(name, rpm);
    let slip = |m: &Means| {
        let v = |k: usize| {
            let side = if p.pulleys[k].back_side { -1.0 } else { 1.0 };
            side * m.omega[k] * p.pulleys[k].radius
        };
        1.0 - v(sp) / v(0)
    };
    println!("{name} at {rpm} rpm, means over {t0}-{t1} s");
    let cache = format!("/tmp/stiff_accuracy_{name}_{rpm}_{ref_tol:e}");
    let reference = match std::fs::read_to_string(&cache).ok().filter(|_| cached) {
        Some(s) => {
            let v: Vec<Vec<f64>> = s
                .lines()
                .map(|l| l.split(' ').map(|x| x.parse().expect("cached")).collect())
                .collect();
            println!("  reference RKF45 relTol {ref_tol:e} from {cache}");
            Means {
                omega: v[0].clone(),
                tension: v[1].clone(),
                interval: v[2].clone(),
            }
        }
        None => {
            let r = run(&p, Method::Rkf45, ref_tol, true, t0, t1);
            let line = |x: &[f64]| {
                x.iter()
                    .map(|v| format!("{v:e}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            if cached {
                std::fs::write(
                    &cache,
                    format!(
                        "{}\n{}\n{}\n",
                        line(&r.omega),
                        line(&r.tension),
                        line(&r.interval)
                    ),
                )
                .expect("cache");
            }
            r
        }
    };
    println!(
        "  reference: speeds {:.4?} rad/s, span tensions {:.3?} N (interval means {:.3?} N), slip \
         {:.4} %",
        reference.omega,
        reference.tension,
        reference.interval,
        100.0 * slip(&reference)
    );
    for &tol in &tols {
        for check in [true, false] {
            let m = run(&p, Method::Rosenbrock, tol, check, t0, t1);
            let dev = |a: &[f64], b: &[f64]| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| (x / y - 1.0).abs())
                    .fold(0.0, f64::max)
            };
            println!(
                "    speeds off by at most {:.4} %, span tensions {:.4} % (interval means {:.4} %), slip {:.4} % against \
                 {:.4} % ({:+.1} % of it); tensions {:.3?} N, interval means {:.3?} N",
                100.0 * dev(&m.omega, &reference.omega),
                100.0 * dev(&m.tension, &reference.tension),
                100.0 * dev(&m.interval, &reference.interval),
                100.0 * slip(&m),
                100.0 * slip(&reference),
                100.0 * (slip(&m) / slip(&reference) - 1.0),
                m.tension,
                m.interval
            );
        }
    }
}
