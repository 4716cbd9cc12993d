//! `cargo bench --bench stiff`: the stiff integrator (solver.method = 2):
//! cost of its kernels per body, real-time factor of the paper's 5PK drive
//! and the section-3 drive with headline outputs, scaling with body count,
//! and the paper's `kubas2014` law at its printed dv = 1e-5 m/s. Plain
//! timing; figures go to docs/benchmarks.md.
//!
//! Sections by name (`cargo bench --bench stiff -- 5pk scaling`); none runs
//! all but `kubas`, which takes over an hour and runs only when named.
//! Numbers restrict the scaling sections to those body counts, e.g. for
//! instruction counts of the integration alone:
//! `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*stiff*integrate*' <bench binary> scaling5pk 600`.

mod common;

#[path = "../examples/common/ssv.rs"]
#[allow(dead_code)]
mod ssv;

#[path = "../examples/common/accessory.rs"]
mod accessory;

use belt_drive::drive::Integrator;
use belt_drive::model::params::Method;
use belt_drive::model::system::{NoRecord, Workspace};
use belt_drive::solver::iteration_matrix::IterationMatrix;
use belt_drive::solver::jacobian::Jacobian;
use belt_drive::solver::rosenbrock::GAMMA;
use belt_drive::{Drive, DriveParams, FrictionLaw};
use common::{cpu_time, median};
use std::hint::black_box;
use std::time::Instant;

/// Median over 5 rounds of the CPU time per call of `f`.
fn time_per_call(reps: usize, mut f: impl FnMut()) -> f64 {
    median(
        (0..5)
            .map(|_| {
                let t = cpu_time();
                for _ in 0..reps {
                    f();
                }
                (cpu_time() - t) / reps as f64
            })
            .collect(),
    )
}

/// Kernel costs at `n` bodies (>= 89: the 5PK drive's 27 mm pulleys).
fn kernels(n: usize) {
    let mut p = DriveParams::kubas_section4();
    p.belt.n_bodies = n;
    p.probe_body = 0;
    p.solver.method = Method::Rosenbrock;
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    d.advance(0.05).expect("runs");
    let k = kernel_times(&d, 1e-5);
    let per = |x: f64| x * 1e9 / n as f64;
    println!(
        "n = {n:5}: ns per body: rhs {:.1}, jacobian {:.1} ({:.1} rhs), factor {:.1} ({:.1} rhs), solve {:.1} ({:.1} rhs)",
        per(k.rhs),
        per(k.jacobian),
        k.jacobian / k.rhs,
        per(k.factor),
        k.factor / k.rhs,
        per(k.solve),
        k.solve / k.rhs
    );
}

/// CPU time per call of each kernel of the stiff method [s].
struct KernelTimes {
    rhs: f64,
    /// The right-hand side with the energy sums (the energy check's).
    rhs_energy: f64,
    jacobian: f64,
    /// The factorization of I - c J.
    factor: f64,
    /// One stage solve.
    solve: f64,
}

/// [`KernelTimes`] at `d`'s state, with `c` the factorization's h gamma.
fn kernel_times(d: &Drive, c: f64) -> KernelTimes {
    let (sys, t) = (d.system(), d.time());
    let y = d.state();
    let n = sys.n_bodies();
    let mut dy = vec![0.0; y.len()];
    let mut jac = Jacobian::new(sys);
    let mut m = IterationMatrix::new(sys);
    let reps = (200_000 / n).max(20);
    let mut ws = Workspace::new();
    let rhs = time_per_call(reps, || {
        sys.rhs(&mut ws, t, black_box(y), &mut dy, &mut NoRecord)
    });
    let rhs_energy = time_per_call(reps, || {
        black_box(sys.rhs_energy(&mut ws, t, black_box(y), &mut dy));
    });
    let jacobian = time_per_call(reps, || sys.jacobian(t, black_box(y), &mut jac));
    let factor = time_per_call(reps, || {
        black_box(m.factor(sys, &jac, c));
    });
    let mut b = dy.clone();
    let solve = time_per_call(reps, || {
        b.copy_from_slice(&dy);
        m.solve(sys, &jac, &mut b);
    });
    KernelTimes {
        rhs,
        rhs_energy,
        jacobian,
        factor,
        solve,
    }
}

/// Kernel costs on an accessory set (`acc4`, `tens`) at crank speed `rpm`
/// with its loads held (examples/common/accessory.rs), 0.1 s after its
/// speed ramp: the kernels per body as [`kernels`], the right-hand side with
/// the energy sums (the energy check's), and what a step of the stiff
/// method costs in all over the next 10 ms, so that the share the kernels
/// leave to the rest of the step shows.
fn kernels_accessory(set: &str, rpm: f64) {
    let p = accessory::at_rpm(set, rpm, Method::Rosenbrock);
    let mut d = Drive::new(&p, 0.0).expect("valid drive");
    let t0 = 0.6;
    d.advance(t0).expect("runs");
    let n = d.system().n_bodies();
    // the factorization at the last step's h gamma
    let k = kernel_times(&d, d.stats().last_step * GAMMA);
    let before = d.stats();
    let c0 = cpu_time();
    for i in 1..=10 {
        d.advance(t0 + i as f64 * 1e-3).expect("runs");
    }
    let cpu = cpu_time() - c0;
    let after = d.stats();
    let trials = (after.steps + after.rejected - before.steps - before.rejected) as f64;
    let evals = (after.rhs_evals - before.rhs_evals) as f64;
    let per = |x: f64| x * 1e9 / n as f64;
    // per trial: one Jacobian, one factorization, four solves, the
    // right-hand sides counted (the first with the energy sums)
    let kernels =
        k.jacobian + k.factor + 4.0 * k.solve + (evals / trials - 1.0) * k.rhs + k.rhs_energy;
    let step = cpu / trials;
    println!(
        "{set} {rpm} rpm, {n} bodies: ns per body: rhs {:.1}, rhs with energy {:.1}, jacobian {:.1}, factor {:.1}, solve {:.1}; per trial step: kernels {:.0}, all {:.0} ({:.0} % outside the kernels; {:.0} trials)",
        per(k.rhs),
        per(k.rhs_energy),
        per(k.jacobian),
        per(k.factor),
        per(k.solve),
        per(kernels),
        per(step),
        100.0 * (1.0 - kernels / step),
        trials
    );
}

/// `d.advance(t_end)`, never inlined: the scope of the instruction counts
/// (`--toggle-collect='*stiff*integrate*'`), whatever the optimiser inlines
/// of `Drive::advance`.
#[inline(never)]
fn integrate(d: &mut Drive, t_end: f64) {
    d.advance(t_end).expect("runs");
}

/// Runs `p` for `horizon` s in 1 ms communication steps; prints the CPU
/// time, real-time factor, counts and the averages over the last quarter.
fn run(label: &str, p: &DriveParams, horizon: f64) {
    let mut d = Drive::new(p, 0.0).expect("valid drive");
    let t = Instant::now();
    let c0 = cpu_time();
    let steps = (horizon / 1e-3).round() as usize;
    let mut acc = [0.0; 4];
    let mut cnt = 0.0;
    for k in 1..=steps {
        integrate(&mut d, k as f64 * 1e-3);
        if k % (steps / 10).max(1) == 0 && k < steps {
            eprintln!(
                "  {label}: t = {:.3} s after {:.1} s wall, {} steps",
                k as f64 * 1e-3,
                t.elapsed().as_secs_f64(),
                d.stats().steps
            );
        }
        if k > steps * 3 / 4 {
            let o = d.outputs();
            acc[0] += o.pulleys[1].omega;
            acc[1] += o.span_tension[0];
            acc[2] += o.span_tension[1];
            acc[3] += o.pulleys[1].slip;
            cnt += 1.0;
        }
    }
    // CPU time of this thread (the wall time on an idle core)
    let cpu = cpu_time() - c0;
    let s = d.stats();
    let (jacs, facs) = match d.integrator() {
        Integrator::Rosenbrock(r) => (r.jacobians, r.factorizations),
        Integrator::Rkf45(_) => (0, 0),
    };
    println!(
        "{label}: CPU {cpu:.3} s, real-time factor {:.2}, {:.2} s per simulated s per 1000 bodies; steps {} ({:.0}/s), rejected {}, rhs {}, jacobians {jacs}, factorizations {facs}; last quarter: driven {:.4} rad/s, span 1 {:.2} N, span 2 {:.2} N, slip {:.4} %",
        horizon / cpu,
        cpu / horizon / p.belt.n_bodies as f64 * 1000.0,
        s.steps,
        s.steps as f64 / horizon,
        s.rejected,
        s.rhs_evals,
        acc[0] / cnt,
        acc[1] / cnt,
        acc[2] / cnt,
        100.0 * acc[3] / cnt
    );
}

/// Sections to run: every argument that is not a flag names one
/// (`kernels`, `5pk`, `s3`, `scaling` = `scaling5pk` + `scaling3`, `kubas`);
/// none runs all but `kubas` and `rkf45`. `--points=K` runs the `5pk`,
/// `rkf45` and `scaling` drives with K contact points along each body
/// (`contact.points`; without it, the drive's own); `--fmu-default` runs
/// the `5pk` and `rkf45` sections on the FMU's default drive instead of the
/// paper's section-4 set. `rkf45`: the 5PK drive
/// with RKF45 (solver.method = 1) at its default tolerances over 0-0.1 s
/// (`--horizon=T` s instead), for side-by-side step counts and CPU time.
fn main() {
    let quick = std::env::var("BELT_BENCH_QUICK").is_ok();
    let flag = |name: &str| -> Option<f64> {
        std::env::args().find_map(|a| {
            a.strip_prefix(name)
                .map(|k| k.parse().unwrap_or_else(|_| panic!("{name}VALUE")))
        })
    };
    let points = flag("--points=").map(|k| k as usize);
    // the `5pk` and `rkf45` drive: the paper's section-4 set, or with
    // `--fmu-default` the FMU's default drive (automatic contact damping
    // ramp, damper across the SDE gaps)
    let fmu_default = std::env::args().any(|a| a == "--fmu-default");
    let name_5pk = if fmu_default {
        "the FMU's default 5PK drive"
    } else {
        "the paper's 5PK drive (section-4 set)"
    };
    let drive_5pk = || {
        if fmu_default {
            DriveParams::default()
        } else {
            DriveParams::kubas_section4()
        }
    };
    let set_points = |p: &mut DriveParams| {
        if let Some(k) = points {
            p.contact.points = k;
        }
    };
    let picked: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    // numbers among the arguments restrict `scaling` to those body counts
    let counts: Vec<usize> = picked.iter().filter_map(|a| a.parse().ok()).collect();
    let want = |s: &str| picked.is_empty() || picked.iter().any(|a| a == s);
    if want("kernels") {
        println!("# stiff-method kernels (5PK drive at t = 0.05 s)");
        for n in [90usize, 150, 600, 1200] {
            kernels(n);
        }
        println!("# the same on the accessory sets at 6000 rpm, loads held, 0.1 s after the ramp");
        for set in ["acc4", "tens"] {
            kernels_accessory(set, 6000.0);
        }
    }
    let horizon = if quick { 0.2 } else { 2.0 };
    if want("5pk") {
        println!("# {name_5pk}, creep law, ROS34PW2, 0..{horizon} s");
        for tol in [1e-4, 1e-5] {
            let mut p = drive_5pk();
            p.solver.method = Method::Rosenbrock;
            p.solver.rel_tol = tol;
            set_points(&mut p);
            run(&format!("5PK, rtol {tol:e}"), &p, horizon);
        }
    }
    if want("s3") {
        println!("# section-3 drive, ROS34PW2 rtol 1e-5, 0..{horizon} s");
        let mut p = DriveParams::kubas_section3();
        p.solver.method = Method::Rosenbrock;
        p.solver.rel_tol = 1e-5;
        run("section 3", &p, horizon);
    }
    let scaling_horizon = if quick { 0.05 } else { 0.5 };
    // the 5PK layout needs >= 89 bodies (27 mm wraps); the section-3 drive
    // (81 mm pulleys) also runs the paper's 60
    for (section, name, base, sizes) in [
        (
            "scaling5pk",
            "5PK drive",
            DriveParams::kubas_section4(),
            &[90usize, 150, 300, 600, 1200][..],
        ),
        (
            "scaling3",
            "section-3 drive",
            DriveParams::kubas_section3(),
            &[60usize, 150, 300, 600, 1200][..],
        ),
    ] {
        if !(want("scaling") || picked.iter().any(|a| a == section)) {
            continue;
        }
        println!("# scaling: {name}, ROS34PW2 rtol 1e-4, 0..{scaling_horizon} s");
        for &n in sizes
            .iter()
            .filter(|n| counts.is_empty() || counts.contains(n))
        {
            let mut p = base.clone();
            p.belt.n_bodies = n;
            p.probe_body = 0;
            p.solver.method = Method::Rosenbrock;
            set_points(&mut p);
            run(&format!("n = {n}"), &p, scaling_horizon);
        }
    }
    if picked.iter().any(|a| a == "rkf45") {
        let horizon = flag("--horizon=").unwrap_or(0.1);
        println!("# {name_5pk}, creep law, RKF45 at its default tolerances, 0..{horizon} s");
        let mut p = drive_5pk();
        p.solver.method = Method::Rkf45;
        set_points(&mut p);
        run(
            &format!("5PK, {} contact points", p.contact.points),
            &p,
            horizon,
        );
    }
    if picked.iter().any(|a| a == "kubas") {
        println!("# kubas2014 law at the paper's dv = 1e-5 m/s, ROS34PW2 rtol 1e-4");
        let mut p = DriveParams::kubas_section4();
        p.friction.law = FrictionLaw::Kubas2014;
        p.friction.dv = 1e-5;
        p.solver.method = Method::Rosenbrock;
        run("kubas2014 dv 1e-5", &p, if quick { 0.02 } else { 2.0 });
    }
}
