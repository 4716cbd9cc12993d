//! The Floquet analysis' convergence in the substeps of its variational
//! integration (docs/modes.md, "Convergence in the substeps"): the drive
//! run up and settled once, then analysed at each substep count; prints
//! every mode below 2 kHz (frequency, damping ratio, label, energy shares).
//!
//! ```text
//! cargo run --profile ci --features modes --example floquet_substeps -- heavy 0 - 64,128,256
//! cargo run --profile ci --features modes --example floquet_substeps -- \
//!     parameters/accessory-drive-4.ssv 84 - 64,128,256 solver.method=2
//! ```
//!
//! Arguments: `heavy` (the heavy-belt test drive of tests/modes.rs at 140
//! rad/s), `light` (the light two-pulley drive, crank speed-driven) or an
//! .ssv file; the crank speed [rad/s] (ignored for `heavy`); the time of the
//! run-up (`-`: the ramp time + 0.3 s, 0.6 s for `heavy`); the substep
//! counts; then NAME=VALUE settings (FMU names for an .ssv; `creepMax`,
//! `creepDampingTime`, `n`, `method`, `load` for the test drives).
use belt_drive::model::params::Method;
use belt_drive::modes::{adapter, floquet, params, Options};
use belt_drive::DriveParams;

#[path = "common/heavy_running.rs"]
mod heavy_running;
use heavy_running::heavy_running as heavy;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut p, at) = if args[0] == "heavy" {
        (heavy(120, Method::Rosenbrock), 0.6)
    } else if args[0] == "light" {
        let mut p = DriveParams::kubas_section4();
        p.pulleys[0].radius = 0.04;
        p.pulleys[0].torque_ramp = 0.0;
        p.pulleys[0].inertia = 2e-3;
        p.pulleys[0].speed_driven = true;
        p.pulleys[0].omega_ramp = -args[1].parse::<f64>().unwrap();
        p.pulleys[0].ramp_time = 0.1;
        p.pulleys[1].radius = 0.025;
        p.pulleys[1].x = 0.35;
        p.pulleys[1].inertia = 5e-4;
        p.pulleys[1].load_damping = 0.0;
        p.belt.n_bodies = 120;
        p.belt.preload = 300.0;
        p.belt.mass_per_length = 0.2;
        p.belt.ea = 1.5e5;
        p.probe_body = 0;
        p.solver.method = Method::Rosenbrock;
        (p, 0.4)
    } else {
        let sets: Vec<String> = args[4..].to_vec();
        let mut p = params::drive_params(Some(std::path::Path::new(&args[0])), &sets).unwrap();
        let w: f64 = args[1].parse().unwrap();
        // the crank's speed, in the direction the set drives it
        p.pulleys[0].omega_ramp = w.copysign(p.pulleys[0].omega_ramp);
        let at = p.pulleys[0].ramp_time + 0.3;
        (p, at)
    };
    if args[0] == "heavy" || args[0] == "light" {
        for s in &args[4..] {
            let (k, v) = s.split_once('=').unwrap();
            match k {
                "creepMax" => p.friction.creep_max = v.parse().unwrap(),
                "creepDampingTime" => p.friction.creep_damping_time = v.parse().unwrap(),
                "n" => p.belt.n_bodies = v.parse().unwrap(),
                "method" => {
                    p.solver.method = if v == "1" {
                        Method::Rkf45
                    } else {
                        Method::Rosenbrock
                    }
                }
                "load" => p.pulleys[1].load_damping = v.parse().unwrap(),
                _ => panic!("{k}"),
            }
        }
    }
    let at: f64 = if args[2] == "-" {
        at
    } else {
        args[2].parse().unwrap()
    };
    let subs: Vec<usize> = args[3].split(',').map(|x| x.parse().unwrap()).collect();
    let t0 = std::time::Instant::now();
    let mut run = adapter::build(&p).unwrap();
    adapter::run_to(&mut run, at).unwrap();
    let (d, defects) = floquet::settled(&run).unwrap();
    eprintln!("settled {defects:?} in {:.1} s", t0.elapsed().as_secs_f64());
    for &n in &subs {
        let t1 = std::time::Instant::now();
        let m = floquet::floquet_settled(&d, defects.clone(), &Options::default(), n).unwrap();
        let o = m.orbit.clone().unwrap();
        println!(
            "# substeps {n}: {:.1} s, defect {:.2e}, period {:.5e}, T {:.2?}, v {:.3}",
            t1.elapsed().as_secs_f64(),
            o.defect(),
            o.period,
            o.span_tension,
            o.belt_speed
        );
        let law = |f: f64| std::f64::consts::PI * f * p.belt.axial_damping / p.belt.ea;
        for x in m
            .modes
            .iter()
            .filter(|x| matches!(x.part, belt_drive::modes::Part::PulleyRotation(_)))
            .take(3)
        {
            println!(
                "ROT {n} {:10.4} zeta {:+.4e} law {:.4e} ({:+.1} %)",
                x.frequency_hz,
                x.damping_ratio,
                law(x.frequency_hz),
                100.0 * (x.damping_ratio / law(x.frequency_hz) - 1.0)
            );
        }
        for x in m.modes.iter().take(40) {
            println!(
                "{n} {:10.4} {:+.4e} {} {:.2} | {}",
                x.frequency_hz,
                x.damping_ratio,
                x.part.describe(),
                x.share,
                x.shares
                    .iter()
                    .take(6)
                    .map(|(p, e)| format!("{} {:.0}%", p.describe(), 100.0 * e))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
}
