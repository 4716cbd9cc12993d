//! The stiff method's energy check on three drives (docs/model.md, "The
//! energy check"): steps, mean speeds, span tensions and drive torques over
//! the window, the energy balance's drift over it (input less dissipated
//! less the change of the stored energy, from the outputs), and the trial
//! steps rejected on their energy residual alone.
//!
//! `cargo run --profile ci --example stiff_energy -- DRIVE [METHOD] [RELTOL] [POINTS] [off]`
//! with DRIVE `sixty` (the 60-body drive of tests/defaults.rs, 0.3-0.5 s),
//! `heavy` (the heavy belt of tests/python/test_mean_forces.py, 0.2-0.3 s),
//! `5pk` (the FMU's default drive, 0.35-0.6 s), `accessory`
//! (parameters/accessory-drive-4.ssv as tests/defaults.rs runs it, 0.4-0.6
//! s) or `tensioner`
//! (parameters/accessory-drive-tensioner.ssv as it ships, 0.6-0.8 s, as
//! tests/python/test_tensioner.py); METHOD 1 (RKF45) or 2 (the stiff
//! method, default); RELTOL 1e-4 by default; POINTS the contact points
//! along a body (`-` or absent: the drive's own); `off` runs the stiff
//! method without its energy check. Further arguments `shear=F` and
//! `bend=B` set `belt.shearDampingFactor` and `belt.bendingDamping`.
use belt_drive::drive::Integrator;
use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams, Inputs};

#[path = "common/heavy_belt.rs"]
mod heavy_belt;
#[path = "common/sixty_body.rs"]
mod sixty_body;
#[path = "common/ssv.rs"]
mod ssv;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let name = a.first().map_or("sixty", String::as_str);
    let method = if a.get(1).map(String::as_str) == Some("1") {
        Method::Rkf45
    } else {
        Method::Rosenbrock
    };
    let tol: f64 = a.get(2).map_or(1e-4, |v| v.parse().unwrap());
    let (mut p, t0, t1) = match name {
        "sixty" => (sixty_body::sixty_body_drive(), 0.3, 0.5),
        "heavy" => (heavy_belt::heavy_belt_drive(), 0.2, 0.3),
        "5pk" => (DriveParams::default(), 0.35, 0.6),
        "accessory" => {
            // as tests/defaults.rs runs it: the crank ramp shortened to 0.2 s
            let mut p = ssv::from_ssv("accessory-drive-4.ssv");
            p.solver.max_steps = DriveParams::default().solver.max_steps;
            for q in &mut p.pulleys {
                q.ramp_time = 0.2;
            }
            (p, 0.4, 0.6)
        }
        "tensioner" => {
            let mut p = ssv::from_ssv("accessory-drive-tensioner.ssv");
            // the set's step guard is the FMU's per-communication-step bound
            p.solver.max_steps = DriveParams::default().solver.max_steps;
            (p, 0.6, 0.8)
        }
        _ => panic!("drive"),
    };
    if let Some(k) = a.get(3).filter(|k| k.as_str() != "-") {
        p.contact.points = k.parse().unwrap();
    }
    for v in &a {
        if let Some(f) = v.strip_prefix("shear=") {
            p.belt.shear_damping_factor = f.parse().unwrap();
        } else if let Some(b) = v.strip_prefix("bend=") {
            p.belt.bending_damping = b.parse().unwrap();
        }
    }
    p.solver.method = method;
    p.solver.rel_tol = tol;
    let mut d = Drive::new(&p, 0.0).expect("valid");
    d.set_energy_check(a.get(4).map(String::as_str) != Some("off"));
    d.set_inputs(Inputs::default());
    d.advance(t0).unwrap();
    let np = p.pulleys.len();
    let o0 = d.outputs();
    let n = ((t1 - t0) / 1e-3f64).round() as usize;
    let mut st = vec![0.0; np];
    let mut dt = vec![0.0; np];
    let mut sl = vec![0.0; np];
    let mut last = o0.clone();
    for k in 1..=n {
        d.advance(t0 + k as f64 * 1e-3).unwrap();
        last = d.outputs();
        for j in 0..np {
            st[j] += last.span_tension[j] / n as f64;
            dt[j] += last.pulleys[j].mean_drive_torque / n as f64;
            sl[j] += 100.0 * last.pulleys[j].slip / n as f64;
        }
    }
    let om: Vec<f64> = (0..np)
        .map(|j| (last.pulleys[j].angle - o0.pulleys[j].angle) / (t1 - t0))
        .collect();
    let bal = |o: &belt_drive::Outputs| {
        o.energy_input - o.energy_dissipated - o.kinetic_energy - o.potential_energy
    };
    let s = d.stats();
    print!(
        "{name}, {method:?} at {tol:e}: {} steps, {} rejected | speeds {:.4?} rad/s | span tensions {:.3?} N | slips {:.4?} % | mean drive torques {:.4?} N m | balance drift {:.4} W",
        s.steps,
        s.rejected,
        om,
        st,
        sl,
        dt,
        (bal(&last) - bal(&o0)) / (t1 - t0)
    );
    if let Integrator::Rosenbrock(r) = d.integrator() {
        print!(
            " | jacobians {}, rejected on the energy residual {}",
            r.jacobians, r.energy_rejections
        );
    }
    let e = d.system().stored_energy(d.state());
    println!(" | belt's stored energy {:.4} J", e.belt);
}
