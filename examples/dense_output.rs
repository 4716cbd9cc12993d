//! How accurate is the state the FMU shows at a communication point it
//! stepped past? At each communication point of a run (inputs held), the
//! drive's state there, the cubic Hermite interpolant of the integrator's
//! step across it, is compared with the same step retaken clipped to the
//! point (`Drive::materialise` on a copy: what a run that clips its steps
//! gets). Printed per component class: the largest difference in units of
//! the integrator's error weight `absTol + relTol |y|` (1 = one tolerance),
//! and the difference of the span tensions and belt torques against their
//! ripple (the spread of the instantaneous values over the run).
//!
//! `cargo run --profile ci --example dense_output -- [5pk|acc4|tens] [rpm=800]
//! [comm=1e-4] [rkf45]`

#[path = "common/ssv.rs"]
mod ssv;

#[path = "common/accessory.rs"]
mod accessory;

use belt_drive::drive::Drive;
use belt_drive::model::params::{DriveParams, Method};
use belt_drive::model::state::{body_component, BodyComponent};
use belt_drive::solver::rkf45::{OdeSystem, Rkf45};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let get = |k: &str, d: f64| {
        args.iter()
            .find_map(|a| a.strip_prefix(k).map(|v| v.parse().expect("number")))
            .unwrap_or(d)
    };
    let rpm = get("rpm=", 800.0);
    let comm = get("comm=", 1e-4);
    let method = if args.iter().any(|a| a == "rkf45") {
        Method::Rkf45
    } else {
        Method::Rosenbrock
    };
    let set = args
        .iter()
        .find(|a| !a.contains('=') && *a != "rkf45")
        .map_or("acc4", |s| s.as_str());
    let mut p: DriveParams = match set {
        "5pk" => DriveParams::default(),
        s => accessory::at_rpm(s, rpm, method),
    };
    p.solver.method = method;
    let (rel, abs) = (p.solver.rel_tol, p.solver.abs_tol);
    let mut d = Drive::new(&p, 0.0).expect("valid");
    let t0 = 0.3;
    d.advance(t0).expect("runs");
    let np = p.pulleys.len();
    let n_bodies = p.belt.n_bodies;
    let names = ["position", "angle", "velocity", "spin", "creep", "other"];
    let class = |k: usize| -> usize {
        if k >= 7 * n_bodies {
            return 5;
        }
        match body_component(k).1 {
            BodyComponent::X | BodyComponent::Y => 0,
            BodyComponent::Angle => 1,
            BodyComponent::Vx | BodyComponent::Vy => 2,
            BodyComponent::Spin => 3,
            BodyComponent::Creep => 4,
        }
    };
    let q = d.system().controlled_dim();
    let mut worst = [0.0f64; 6];
    let (mut span_diff, mut torque_diff) = (vec![0.0f64; np], vec![0.0f64; np]);
    let (mut span_lo, mut span_hi) = (vec![f64::INFINITY; np], vec![f64::NEG_INFINITY; np]);
    let (mut tq_lo, mut tq_hi) = (vec![f64::INFINITY; np], vec![f64::NEG_INFINITY; np]);
    let mut points = 0;
    let (mut ref_d, mut ref_c) = (vec![0.0f64; 2 * np], vec![0.0f64; 2 * np]);
    for k in 1..=((0.05 / comm).round() as usize) {
        d.advance(t0 + k as f64 * comm).expect("runs");
        if d.integrator_time() == d.time() {
            continue;
        }
        points += 1;
        let mut c = d.clone();
        c.materialise();
        // the reference: the step's start integrated tightly to the point
        let (t_a, y_a) = d.step_past().expect("stepped past");
        let mut y_ref = y_a.to_vec();
        let mut t = t_a;
        let mut rk = Rkf45::new(y_ref.len(), 1e-9, 1e-12, 1e-7, 10_000_000);
        let mut ws = d.system().workspace();
        rk.advance(d.system(), &mut ws, &mut t, &mut y_ref, d.time())
            .expect("reference");
        let mut r = d.clone();
        assert!(r.set_state(&y_ref));
        let or = r.outputs();
        for j in 0..np {
            for (x, e) in [(&d, &mut ref_d), (&c, &mut ref_c)] {
                let o = x.clone().outputs();
                e[j] = e[j].max((o.pulleys[j].belt_torque - or.pulleys[j].belt_torque).abs());
                e[np + j] = e[np + j].max((o.span_tension[j] - or.span_tension[j]).abs());
            }
        }
        let (a, b) = (d.state(), c.state());
        for i in 0..q {
            let w = abs + rel * a[i].abs().max(b[i].abs());
            let e = (a[i] - b[i]).abs() / w;
            worst[class(i)] = worst[class(i)].max(e);
        }
        let (oa, ob) = (d.clone().outputs(), c.outputs());
        for j in 0..np {
            span_diff[j] = span_diff[j].max((oa.span_tension[j] - ob.span_tension[j]).abs());
            let (x, y) = (oa.pulleys[j].belt_torque, ob.pulleys[j].belt_torque);
            torque_diff[j] = torque_diff[j].max((x - y).abs());
            span_lo[j] = span_lo[j].min(ob.span_tension[j]);
            span_hi[j] = span_hi[j].max(ob.span_tension[j]);
            tq_lo[j] = tq_lo[j].min(y);
            tq_hi[j] = tq_hi[j].max(y);
        }
    }
    println!("{set} {rpm} rpm {method:?} relTol {rel}: {points} points stepped past at {comm} s");
    for (n, w) in names.iter().zip(worst) {
        println!("  {n:9} largest |interpolant - clipped| = {w:8.3} tolerances");
    }
    for j in 0..np {
        println!(
            "  against a tight reference from the step's start: pulley {} belt torque interpolant {:9.3e} clipped {:9.3e}; span tension interpolant {:9.3e} clipped {:9.3e}",
            j + 1, ref_d[j], ref_c[j], ref_d[np + j], ref_c[np + j]
        );
    }
    for j in 0..np {
        println!(
            "  span {}: tension diff  {:9.3e} N of ripple {:9.3e} N; pulley {} belt torque diff {:9.3e} of ripple {:9.3e} N m",
            j + 1,
            span_diff[j],
            span_hi[j] - span_lo[j],
            j + 1,
            torque_diff[j],
            tq_hi[j] - tq_lo[j]
        );
        println!(
            "  pulley {} belt torque {:.4} N m",
            j + 1,
            d.clone().outputs().pulleys[j].belt_torque
        );
    }
}
