//! `cargo bench --bench belt -- speeds [--quick]`: real-time factor against
//! crank speed on the accessory drives users build (issue 32), both methods
//! at relTol 1e-4, 1 ms communication steps, and the FMU's default 5PK drive
//! (docs/benchmarks.md, "Real-time factor against crank speed").
//!
//! `parameters/accessory-drive-4.ssv` and `parameters/accessory-drive-tensioner.ssv`
//! at 800, 2 000, 4 000 and 6 000 rpm: the crank is speed-driven to the
//! speed over a ramp shortened to 0.2 s (the sets ramp over 0.5 s; as
//! tests/defaults.rs does at 6 000 rpm), each load damping scaled by
//! 800 rpm / speed so that the load torques stay at their idle values, and
//! the run is timed over 0.3-0.4 s (0.1 s after the ramp). The 5PK drive
//! (`DriveParams::default()`, 0.7 m/s) is timed over the 0.1 s after its own
//! ramp and a 0.1 s settling. The time is the CPU time of the `advance`
//! calls of the timed window; steps and rejections are counted over it.

use super::common::cpu_time;
use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams};

#[path = "../../examples/common/ssv.rs"]
#[allow(dead_code)]
mod ssv;

#[path = "../../examples/common/accessory.rs"]
mod accessory;

/// Crank speeds of the accessory sets [rpm].
const SPEEDS: [f64; 4] = [800.0, 2000.0, 4000.0, 6000.0];
/// Communication step [s].
const COMM: f64 = 1e-3;

/// One timed run: real-time factor, accepted and rejected steps per
/// simulated second, belt speed [m/s].
struct Timed {
    rtf: f64,
    steps: f64,
    rejected: f64,
    belt_speed: f64,
}

/// Runs `p` to `t0` unmeasured, then times `window` s.
fn timed(p: &DriveParams, t0: f64, window: f64) -> Timed {
    let mut d = Drive::new(p, 0.0).expect("valid drive");
    let n0 = (t0 / COMM).round() as usize;
    for k in 1..=n0 {
        d.advance(k as f64 * COMM).expect("runs");
    }
    let s0 = d.stats();
    let n = (window / COMM).round() as usize;
    let mut cpu = 0.0;
    for k in 1..=n {
        let t = (n0 + k) as f64 * COMM;
        let c = cpu_time();
        d.advance(t).expect("runs");
        cpu += cpu_time() - c;
    }
    let s1 = d.stats();
    let o = d.outputs();
    Timed {
        rtf: window / cpu,
        steps: (s1.steps - s0.steps) as f64 / window,
        rejected: (s1.rejected - s0.rejected) as f64 / window,
        belt_speed: o.pulleys[0].omega.abs() * p.pulleys[0].radius,
    }
}

/// The accessory set `file` at `rpm` with `method` (see the module docs).
fn accessory(file: &str, rpm: f64, method: Method) -> DriveParams {
    let mut p = accessory::at_rpm(file, rpm, method);
    for q in &mut p.pulleys {
        q.ramp_time = 0.2;
    }
    p
}

pub fn bench_speeds(quick: bool) {
    let window = if quick { 0.01 } else { 0.1 };
    let methods = [("stiff", Method::Rosenbrock), ("RKF45", Method::Rkf45)];
    println!("## Real-time factor against crank speed (relTol 1e-4, 1 ms communication steps)");
    println!();
    println!(
        "`cargo bench --bench belt -- speeds`: the accessory sets with the load torques held at \
         their idle values, timed over {window} s after the ramp to speed (benches/speeds/mod.rs)."
    );
    println!();
    println!("| drive | method | 800 rpm | 2 000 rpm | 4 000 rpm | 6 000 rpm |");
    println!("|---|---|---|---|---|---|");
    let mut detail = Vec::new();
    for (name, file) in [
        ("accessory-drive-4", "accessory-drive-4.ssv"),
        ("accessory-drive-tensioner", "accessory-drive-tensioner.ssv"),
    ] {
        for (label, method) in methods {
            let mut row = format!("| {name} | {label} |");
            for rpm in SPEEDS {
                let r = timed(&accessory(file, rpm, method), 0.3, window);
                row.push_str(&format!(" {:.3} |", r.rtf));
                detail.push(format!(
                    "| {name} | {rpm:.0} | {:.1} | {label} | {:.3} | {:.0} | {:.0} ({:.1} %) |",
                    r.belt_speed,
                    r.rtf,
                    r.steps,
                    r.rejected,
                    100.0 * r.rejected / r.steps.max(1.0)
                ));
            }
            println!("{row}");
        }
    }
    // the FMU's default drive: 240 rpm on its 27 mm driver (0.7 m/s)
    for (label, method) in methods {
        let mut p = DriveParams::default();
        p.solver.method = method;
        p.solver.rel_tol = 1e-4;
        let ramp = p.pulleys.iter().map(|q| q.ramp_time).fold(0.0, f64::max);
        let r = timed(&p, ramp + 0.1, window);
        println!(
            "| 5PK (FMU default, {:.1} m/s) | {label} | {:.3} | | | |",
            r.belt_speed, r.rtf
        );
        detail.push(format!(
            "| 5PK (FMU default) | - | {:.1} | {label} | {:.3} | {:.0} | {:.0} ({:.1} %) |",
            r.belt_speed,
            r.rtf,
            r.steps,
            r.rejected,
            100.0 * r.rejected / r.steps.max(1.0)
        ));
    }
    println!();
    println!(
        "| drive | crank speed [rpm] | belt speed [m/s] | method | real-time factor | accepted steps per simulated s | rejected per simulated s (% of accepted) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for d in detail {
        println!("{d}");
    }
}
