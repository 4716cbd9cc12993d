//! Does a run's mean depend on the communication step? Means over
//! 0.6-0.8 s of a drive (an accessory set at a crank speed, loads at
//! their idle torques) with 1 ms and 20 us communication steps, each
//! integrator at one relTol, against a tight reference (the stiff method at
//! relTol 1e-7, 1 ms steps): mean speeds from the angles, mean hub forces
//! from the exact impulse means, mean span tensions from the interval
//! outputs (trapezoidal over the integrator's steps).
//!
//! `cargo run --profile ci --example comm_step -- [acc4|tens|5pk ...]
//! [rpm=800] [tol=1e-4] [comm=1e-3,2e-5] [stiff] [energy=off]`

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

use belt_drive::drive::Drive;
use belt_drive::model::params::{DriveParams, Method};

const T0: f64 = 0.6;
const T1: f64 = 0.8;

/// The drive `name`: `5pk` (the FMU's default) or an accessory set at
/// `rpm` (loads at their idle torques).
fn params(name: &str, rpm: f64) -> DriveParams {
    match name {
        "5pk" => DriveParams::default(),
        set => accessory::at_rpm(set, rpm, Method::Rosenbrock),
    }
}

struct Means {
    speed: Vec<f64>,
    hub: Vec<f64>,
    span: Vec<f64>,
    steps: u64,
}

struct Run {
    method: Method,
    tol: f64,
    comm: f64,
    energy: bool,
}

fn means(p: &DriveParams, r: &Run) -> Means {
    let mut p = p.clone();
    p.solver.method = r.method;
    p.solver.rel_tol = r.tol;
    let np = p.pulleys.len();
    let mut d = Drive::new(&p, 0.0).expect("valid");
    d.set_inputs(Default::default());
    d.set_energy_check(r.energy);
    d.advance(T0).expect("runs");
    let a0: Vec<f64> = (0..np).map(|j| d.outputs().pulleys[j].angle).collect();
    let n = ((T1 - T0) / r.comm).round() as usize;
    let mut span = vec![0.0; np];
    let mut hub = vec![[0.0; 2]; np];
    let s0 = d.stats().steps;
    for k in 1..=n {
        d.advance(T0 + k as f64 * r.comm).expect("runs");
        let o = d.outputs();
        for j in 0..np {
            span[j] += o.interval.span_mean_tension[j] / n as f64;
            hub[j][0] += o.pulleys[j].mean_hub_force[0] / n as f64;
            hub[j][1] += o.pulleys[j].mean_hub_force[1] / n as f64;
        }
    }
    let o = d.outputs();
    Means {
        speed: (0..np)
            .map(|j| (o.pulleys[j].angle - a0[j]) / (T1 - T0))
            .collect(),
        hub: hub.iter().map(|h| h[0].hypot(h[1])).collect(),
        span,
        steps: d.stats().steps - s0,
    }
}

fn percent(a: &[f64], r: &[f64]) -> Vec<f64> {
    a.iter()
        .zip(r)
        .map(|(a, r)| 100.0 * (a / r - 1.0))
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let tol: f64 = args
        .iter()
        .find_map(|a| {
            a.strip_prefix("tol=")
                .map(|v| v.parse().expect("tol=number"))
        })
        .unwrap_or(1e-4);
    let rpm: f64 = args
        .iter()
        .find_map(|a| {
            a.strip_prefix("rpm=")
                .map(|v| v.parse().expect("rpm=number"))
        })
        .unwrap_or(800.0);
    let only_stiff = args.iter().any(|a| a == "stiff");
    let energy = !args.iter().any(|a| a == "energy=off");
    let comms: Vec<f64> =
        args.iter()
            .find_map(|a| a.strip_prefix("comm="))
            .map_or(vec![1e-3, 2e-5], |v| {
                v.split(',')
                    .map(|c| c.parse().expect("comm=a,b,..."))
                    .collect()
            });
    let mut sets: Vec<String> = args
        .iter()
        .filter(|a| !a.contains('=') && *a != "stiff")
        .cloned()
        .collect();
    if sets.is_empty() {
        sets.push("acc4".to_string());
    }
    for s in &sets {
        let p = params(s, rpm);
        let reference = Run {
            method: Method::Rosenbrock,
            tol: 1e-7,
            comm: 1e-3,
            energy: true,
        };
        let r = means(&p, &reference);
        println!(
            "{s}: reference (stiff, relTol 1e-7): speeds {:.4?}\n  hubs {:.3?}\n  spans {:.3?}",
            r.speed, r.hub, r.span
        );
        for (method, name) in [(Method::Rosenbrock, "stiff"), (Method::Rkf45, "rkf45")] {
            if only_stiff && method == Method::Rkf45 {
                continue;
            }
            for &comm in &comms {
                let m = means(
                    &p,
                    &Run {
                        method,
                        tol,
                        comm,
                        energy,
                    },
                );
                println!(
                    "  {name} relTol {tol:e} comm {comm:e}: {} steps; speeds % {:+.4?}; hubs % {:+.3?}; \
                     spans % {:+.3?}",
                    m.steps,
                    percent(&m.speed, &r.speed),
                    percent(&m.hub, &r.hub),
                    percent(&m.span, &r.span)
                );
            }
        }
    }
}
