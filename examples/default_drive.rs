//! The FMU's default drive (`DriveParams::default()`) with `solver.method`
//! M and relTol T over 0..H s in 1 ms steps: CPU time of the thread, steps,
//! rejected steps, right-hand sides, and means over the last third of the
//! run of the pulley speeds, span tensions, the driven pulley's slip and the
//! belt's power loss. For side-by-side figures of one model change
//! (docs/model.md, "The bodies' pitching").
//!
//! `cargo run --profile ci --example default_drive -- M H [T [F]]`, F =
//! `belt.shearDampingFactor` (default: the model description's start value).
use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};

fn cpu() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + 1e-9 * ts.tv_nsec as f64
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let usage = "usage: default_drive METHOD HORIZON [RELTOL [SHEAR_DAMPING_FACTOR]]";
    let method: u32 = a.get(1).and_then(|s| s.parse().ok()).expect(usage);
    let horizon: f64 = a.get(2).and_then(|s| s.parse().ok()).expect(usage);
    let mut p = DriveParams::default();
    p.solver.method = if method == 1 {
        Method::Rkf45
    } else {
        Method::Rosenbrock
    };
    if let Some(t) = a.get(3) {
        p.solver.rel_tol = t.parse().expect("relTol");
    }
    if let Some(f) = a.get(4) {
        p.belt.shear_damping_factor = f.parse().expect("belt.shearDampingFactor");
    }
    let mut d = Drive::new(&p, 0.0).expect("a valid drive");
    let c0 = cpu();
    let n = (horizon / 1e-3).round() as usize;
    let mut acc = [0.0f64; 6];
    let mut cnt = 0.0;
    for k in 1..=n {
        d.advance(k as f64 * 1e-3).expect("the run");
        if 3 * k > 2 * n {
            let o = d.outputs();
            acc[0] += o.pulleys[0].omega;
            acc[1] += o.pulleys[1].omega;
            acc[2] += o.span_tension[0];
            acc[3] += o.span_tension[1];
            acc[4] += o.pulleys[1].slip;
            acc[5] += o.belt_power_loss;
            cnt += 1.0;
        }
    }
    let c = cpu() - c0;
    let s = d.stats();
    println!(
        "method {method} rtol {:e} shearDampingFactor {} 0..{horizon} s: CPU {c:.2} s (rt factor {:.3}), steps {}, rejected {}, rhs {}; means last third: w1 {:.6} w2 {:.6} rad/s, span1 {:.3} N, span2 {:.3} N, slip2 {:.5} %, beltLoss {:.4} W",
        p.solver.rel_tol, p.belt.shear_damping_factor, horizon / c, s.steps, s.rejected, s.rhs_evals,
        acc[0] / cnt, acc[1] / cnt, acc[2] / cnt, acc[3] / cnt, 100.0 * acc[4] / cnt, acc[5] / cnt
    );
}
