//! `cargo bench --bench belt`: cost of the right-hand side per body and the
//! real-time factor of the paper's drive. Plain timing (median of repeats),
//! no external harness; figures go to docs/benchmarks.md.
//!
//! `cargo bench --bench belt -- count-rhs <n> <reps>` evaluates the
//! right-hand side `reps` times at a running state of `n` bodies inside
//! `rhs_loop` (no timing) for instruction counts:
//! `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*rhs_loop*' <bench binary> count-rhs 150 2000`.

use belt_drive::belt::model::NoRecord;
use belt_drive::belt::{Drive, DriveParams};
use std::time::Instant;

/// CPU time of this thread [s]: unlike wall time it does not count the
/// time other processes hold the core (the development machine is shared).
fn cpu_time() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: valid pointer to a timespec; the clock id is a constant.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// A drive of `n` bodies at a running state (contacts, creep): 60 bodies
/// cannot resolve the 5PK drive's 27 mm pulleys, so below 100 bodies the
/// section-3 drive (its own mesh) is used.
fn running_drive(n: usize) -> Drive {
    let mut p = if n < 100 {
        DriveParams::kubas_section3()
    } else {
        DriveParams::kubas_section4()
    };
    p.belt.n_bodies = n;
    p.probe_body = 0;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.advance(0.01).expect("runs");
    d
}

#[inline(never)]
fn rhs_loop(d: &Drive, y: &[f64], dy: &mut [f64], reps: usize) {
    for _ in 0..reps {
        d.system()
            .rhs(0.01, std::hint::black_box(y), dy, &mut NoRecord);
        std::hint::black_box(&mut *dy);
    }
}

fn rhs_cost(n: usize) -> f64 {
    let d = running_drive(n);
    let y = d.state().to_vec();
    let mut dy = vec![0.0; y.len()];
    let reps = (2_000_000 / n).max(200);
    let samples = (0..7)
        .map(|_| {
            let t = cpu_time();
            rhs_loop(&d, &y, &mut dy, reps);
            (cpu_time() - t) / reps as f64
        })
        .collect();
    median(samples) / n as f64
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("count-rhs") {
        let n = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(150);
        let reps = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1000);
        let d = running_drive(n);
        let y = d.state().to_vec();
        let mut dy = vec![0.0; y.len()];
        rhs_loop(&d, &y, &mut dy, reps);
        println!("{n} bodies, {reps} evaluations");
        return;
    }
    if args.first().map(String::as_str) == Some("rhs") {
        for n in [60usize, 150, 600, 1200] {
            println!("n = {n:5}: {:.2} ns", rhs_cost(n) * 1e9);
        }
        return;
    }
    println!("# right-hand side, ns per body per evaluation (running state; 60 = section-3 drive, others 5PK)");
    for n in [60usize, 150, 600, 1200] {
        println!("n = {n:5}: {:.1} ns", rhs_cost(n) * 1e9);
    }
    let horizon: f64 = std::env::var("BELT_BENCH_HORIZON")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.4);
    println!("# default 5PK drive, creep law, RKF45 rtol 1e-4, 0..{horizon} s");
    let p = DriveParams::kubas_section4();
    let t = Instant::now();
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    let t_init = t.elapsed().as_secs_f64();
    let t = Instant::now();
    d.advance(horizon).expect("runs");
    let wall = t.elapsed().as_secs_f64();
    let s = d.stats();
    println!(
        "init {t_init:.3} s; wall {wall:.2} s; real-time factor {:.4}; steps {} ({:.0}/simulated s), rejected {}, rhs {}, {:.1} ns/body/rhs incl. integrator",
        horizon / wall,
        s.steps,
        s.steps as f64 / horizon,
        s.rejected,
        s.rhs_evals,
        wall * 1e9 / s.rhs_evals as f64 / p.belt.n_bodies as f64
    );
}
