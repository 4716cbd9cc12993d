//! Stepping past communication points (`Drive::advance`): with the inputs
//! held, the integrator's steps do not depend on the communication step; a
//! change of the inputs continues from the state shown at the point (no
//! output read there changes) and clips the next call's last step; no step
//! past a point has a ramp's start or end inside it.

#[path = "../examples/common/ssv.rs"]
mod ssv;

#[path = "../examples/common/accessory.rs"]
mod accessory;

use belt_drive::model::params::Method;
use belt_drive::{Drive, DriveParams, Inputs};

fn drives() -> Vec<(&'static str, DriveParams)> {
    let mut out = Vec::new();
    for method in [Method::Rkf45, Method::Rosenbrock] {
        let mut p = DriveParams::default();
        p.solver.method = method;
        out.push(("5PK", p));
        out.push(("acc4", accessory::at_rpm("acc4", 800.0, method)));
    }
    out
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// At every communication point of a run, the step taken past it and
/// retaken clipped (`Drive::materialise`) is, to the bit, the step a drive
/// that clips (look-ahead off) takes from the same state; so are the step
/// size and the continuation (the counters differ: they count the trials
/// past the point too). Some of these retakes follow rejected trials (the
/// parked Jacobian of the stiff method).
#[test]
fn materialising_gives_the_clipped_step() {
    for (name, p) in drives() {
        let mut a = Drive::new(&p, 0.0).expect("valid");
        let q = a.system().controlled_dim();
        a.advance(0.02).expect("runs");
        a.materialise();
        let (mut past, h) = (0, 1.7e-4);
        for k in 1..=60 {
            let t = 0.02 + k as f64 * h;
            let mut b = a.clone();
            b.set_look_ahead(false);
            a.advance(t).expect("runs");
            past += usize::from(a.integrator_time() > a.time());
            a.materialise();
            b.advance(t).expect("runs");
            assert_eq!(
                bits(&a.state()[..q]),
                bits(&b.state()[..q]),
                "{name} {:?} at {t}",
                p.solver.method
            );
            assert_eq!(a.next_step_size(), b.next_step_size(), "{name} at {t}");
            // the same continuation: both step past from here
            b.set_look_ahead(true);
            let (mut a2, mut b2) = (a.clone(), b);
            for j in 1..=3 {
                let t2 = t + j as f64 * 1e-3;
                a2.advance(t2).expect("runs");
                b2.advance(t2).expect("runs");
            }
            assert_eq!(
                bits(a2.state()),
                bits(b2.state()),
                "{name} continuation from {t}"
            );
        }
        assert!(past > 30, "{name}: only {past} of 60 points stepped past");
    }
}

/// A change of the inputs through `Drive::set_inputs` makes the call after
/// it clip its last step (the inputs may change again): a run whose input
/// changes at every point is, to the bit, a run that never steps past. Held
/// inputs set again change nothing.
#[test]
fn inputs_changed_at_every_point_give_the_clipped_run() {
    for (name, p) in drives() {
        let mut a = Drive::new(&p, 0.0).expect("valid");
        let mut b = a.clone();
        b.set_look_ahead(false);
        let mut c = a.clone();
        let np = p.pulleys.len();
        let load = |k: usize| {
            let mut i = Inputs::default();
            i.torque[np - 1] = 1e-3 * (k % 3) as f64;
            i
        };
        for k in 1..=40 {
            let t = k as f64 * 1e-3;
            for d in [&mut a, &mut b] {
                d.set_inputs(load(k));
                d.advance(t).expect("runs");
            }
            assert_eq!(bits(a.state()), bits(b.state()), "{name} at {t}");
            assert_eq!(a.integrator_time(), t, "{name}: clipped");
            // held inputs set again at every point: the run steps past
            c.set_inputs(Inputs::default());
            c.advance(t).expect("runs");
        }
        assert!(c.integrator_time() >= c.time());
        let mut d = Drive::new(&p, 0.0).expect("valid");
        d.advance(0.04).expect("runs");
        let mut e = Drive::new(&p, 0.0).expect("valid");
        for k in 1..=40 {
            e.advance(k as f64 * 1e-3).expect("runs");
        }
        assert_eq!(
            bits(c.state()),
            bits(e.state()),
            "{name}: setting held inputs"
        );
        assert_eq!(c.stats().steps, e.stats().steps, "{name}");
        assert_eq!(
            d.stats().steps,
            e.stats().steps,
            "{name}: one call or forty"
        );
    }
}

/// With the inputs held the integrator's steps do not depend on the
/// communication step: 0.1 ms and 1 ms steps take the same steps and show
/// the same state at the common points, to the bit (the state between
/// the integrator's steps is the same interpolant). The mean span tensions
/// over 0.1 s agree within 0.05 % (issue 33): they differ only by the
/// trapezoidal rule's extra nodes at the interpolated points.
#[test]
fn held_inputs_give_the_same_steps_at_any_communication_step() {
    for (name, p) in drives() {
        let np = p.pulleys.len();
        let (t0, t1) = (0.1, 0.2);
        let run = |h: f64| {
            let mut d = Drive::new(&p, 0.0).expect("valid");
            d.advance(t0).expect("runs");
            let s0 = d.stats();
            let n = ((t1 - t0) / h).round() as usize;
            let mut mean = vec![0.0; np];
            let mut at_ms = Vec::new();
            for k in 1..=n {
                // k / n is correctly rounded: the same number at the common points
                let t = t0 + (t1 - t0) * (k as f64 / n as f64);
                d.advance(t).expect("runs");
                let o = d.outputs();
                for (m, x) in mean.iter_mut().zip(&o.interval.span_mean_tension) {
                    *m += x / n as f64;
                }
                if k % (n / 100) == 0 {
                    let q = d.system().controlled_dim();
                    at_ms.push(bits(&d.state()[..q]));
                }
            }
            let s = d.stats();
            (mean, at_ms, s.steps - s0.steps, s.rejected - s0.rejected)
        };
        let (m1, s1, steps1, rej1) = run(1e-3);
        let (m2, s2, steps2, rej2) = run(1e-4);
        assert_eq!(
            (steps1, rej1),
            (steps2, rej2),
            "{name} {:?}",
            p.solver.method
        );
        assert!(s1 == s2, "{name}: states at the common points");
        for j in 0..np {
            let rel = (m2[j] / m1[j] - 1.0).abs();
            // issue 33: within 0.05 %
            assert!(
                rel < 5e-4,
                "{name} {:?} span {j}: {} vs {} ({rel:e})",
                p.solver.method,
                m1[j],
                m2[j]
            );
        }
    }
}

/// A state replaced at a communication point the integrator stepped past
/// (a tap on the belt, a perturbed copy restored with the integrator's
/// data) is the state the next call starts from: the step taken past, which
/// led to the old state, is dropped. Either way in gives the same bits, and
/// they differ from the run left alone. (A changed spring free angle acts
/// like a changed input: tests/tensioner.rs, the quasi-static slide.)
#[test]
fn a_replaced_state_is_not_the_step_past() {
    for (name, p) in drives() {
        let mut a = Drive::new(&p, 0.0).expect("valid");
        a.advance(0.0213).expect("runs");
        assert!(a.step_past().is_some(), "{name}: stepped past");
        let mut y = a.state().to_vec();
        y[2] += 1e-3 * (1.0 + y[2].abs());
        let (mut b, mut c, mut left) = (a.clone(), a.clone(), a.clone());
        assert!(b.set_state(&y));
        let (t, inputs, h, stats) = (a.time(), *a.inputs(), a.next_step_size(), a.stats());
        assert!(c.restore(t, &y, a.window(), inputs, h, stats, &a.integrator_data()));
        // the unchanged state restored keeps the step past
        let mut same = a.clone();
        let same_y = a.state().to_vec();
        assert!(same.restore(
            t,
            &same_y,
            a.window(),
            inputs,
            h,
            stats,
            &a.integrator_data()
        ));
        assert!(same.step_past().is_some(), "{name}: the step past kept");
        for x in [&mut b, &mut c, &mut left, &mut same] {
            x.advance(0.0227).expect("runs");
        }
        assert_eq!(bits(b.state()), bits(c.state()), "{name}");
        assert_ne!(bits(b.state()), bits(left.state()), "{name}");
        assert_eq!(bits(same.state()), bits(left.state()), "{name}");
    }
}

/// An input changed at a point the integrator stepped past leaves the
/// state shown there as it is, to the bit, and the counters too (the
/// outputs there depend on no input but through their declared direct
/// dependencies): the integration continues from that state, the
/// interpolant of the step past. That continuation differs from a run that
/// clipped its steps by the interpolant's error only: over 40 ms with four
/// changes the span tensions of both runs agree within 1e-3 of the largest,
/// 10 times the tolerance 1e-4 (measured: 6e-9 and 7e-7 with RKF45, 4e-5
/// and 1.4e-4 with the stiff method, on the 5PK and accessory drives).
#[test]
fn an_input_change_keeps_the_state_shown() {
    for (name, p) in drives() {
        let mut a = Drive::new(&p, 0.0).expect("valid");
        let mut b = a.clone();
        b.set_look_ahead(false);
        let np = p.pulleys.len();
        let mut load = Inputs::default();
        load.torque[np - 1] = -0.5;
        let (mut changed, mut worst) = (0, 0.0f64);
        for k in 1..=40 {
            let t = k as f64 * 1e-3;
            a.advance(t).expect("runs");
            b.advance(t).expect("runs");
            if k % 10 == 0 {
                // the speed-driven pulleys' speed states are their
                // prescriptions (outputs and contact read those)
                let shown = |d: &Drive| {
                    let mut y = bits(d.state());
                    for j in (0..np).filter(|&j| p.pulleys[j].speed_driven) {
                        y[d.system().state_layout().pulley(j).speed] = 0;
                    }
                    y
                };
                let (y, stats) = (shown(&a), a.stats());
                let past = a.step_past().is_some();
                load.torque[np - 1] = -load.torque[np - 1];
                a.set_inputs(load);
                b.set_inputs(load);
                assert_eq!(shown(&a), y, "{name} at {t}: the state shown");
                assert_eq!(a.stats(), stats, "{name} at {t}: the counters");
                assert!(a.step_past().is_none(), "{name} at {t}");
                changed += usize::from(past);
            }
            let (ta, tb) = (a.outputs().span_tension, b.outputs().span_tension);
            let scale = tb.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (x, z) in ta.iter().zip(&tb) {
                worst = worst.max((x - z).abs() / scale);
            }
        }
        assert!(
            changed >= 2,
            "{name}: only {changed} changes after a step past"
        );
        println!(
            "{name} {:?}: span tensions off the clipped run by {worst:.1e} of the largest",
            p.solver.method
        );
        assert!(worst < 1e-3, "{name} {:?}: {worst:e}", p.solver.method);
    }
}

/// A step past a communication point never has a ramp's start or end
/// inside it (the interpolant would cross the ramp's kink): on a drive
/// ramped over 0.1 s, the steps past the points around 0.1 s end at or
/// before it, or start at or after it.
#[test]
fn no_step_past_crosses_a_ramp_end() {
    for (name, p) in drives() {
        let ramp = p.pulleys[0].ramp_time;
        assert!(ramp > 0.0, "{name}: ramped");
        let mut a = Drive::new(&p, 0.0).expect("valid");
        let h = 1e-3;
        let n = (ramp / h).round() as usize;
        a.advance((n - 20) as f64 * h).expect("runs");
        let mut past = 0;
        for k in n - 19..=n + 20 {
            a.advance(k as f64 * h).expect("runs");
            if let Some((t_a, _)) = a.step_past() {
                past += 1;
                let t_b = a.integrator_time();
                assert!(
                    !(t_a < ramp && ramp < t_b),
                    "{name}: step {t_a}..{t_b} crosses {ramp}"
                );
            }
        }
        assert!(past > 10, "{name}: only {past} steps past");
    }
}

/// An interval starts from the values of the state it starts on. Each call
/// takes the values at its start from the end of the call before (the
/// state shown there); a state replaced in between (`Drive::set_state`), a
/// restored one, or tensioner springs moved (`Drive::set_arm_free_angles`)
/// is sampled afresh, and so is the mounted drive's. Checked on empty
/// intervals (the mounted drive's, and a call to the drive's own time),
/// whose outputs are the values at that instant: with the state held,
/// the same bits as a fresh sample of it; with the state replaced (the body
/// in the middle of span 1 moved 0.3 mm along the belt: its tension moves
/// by more than 10 %) or the springs turned (0.05 rad), the instantaneous
/// span tensions, smallest tension and
/// spring torques of the new state (the same SDEs by the same formulas, to
/// rounding: 1e-9 relative), where a value taken over from the call before
/// would be off by the change.
#[test]
fn an_interval_starts_from_the_state_it_is_given() {
    for method in [Method::Rkf45, Method::Rosenbrock] {
        let p = accessory::at_rpm("tens", 800.0, method);
        let mut a = Drive::new(&p, 0.0).expect("valid");
        let close = |x: f64, want: f64| (x - want).abs() <= 1e-9 * want.abs().max(1.0);
        // mounted: the values of the state the mounting settled, not of
        // the layout it started from
        let o = a.outputs();
        for k in 0..4 {
            assert!(
                close(o.interval.span_mean_tension[k], o.span_tension[k]),
                "{method:?} mounted, span {k}: {} vs {}",
                o.interval.span_mean_tension[k],
                o.span_tension[k]
            );
        }
        assert!(
            close(o.interval.belt_min_tension, o.min_tension),
            "{method:?} mounted"
        );
        a.advance(0.0213).expect("runs");
        let t = a.time();
        // held: the call's end sample against a fresh one
        let (mut held, mut fresh) = (a.clone(), a.clone());
        assert!(fresh.set_state(a.state()));
        held.advance(t).expect("runs");
        fresh.advance(t).expect("runs");
        assert_eq!(
            held.outputs().interval,
            fresh.outputs().interval,
            "{method:?}"
        );
        // replaced: the body nearest span 1's middle moved along the belt
        // by 0.3 mm
        let mut moved = a.clone();
        let mut y = a.state().to_vec();
        let mid = a.layout().span_between(0, 1).expect("span 1").midpoint();
        let n = a.system().n_bodies();
        let dist = |i: usize| {
            let b = belt_drive::model::state::BodyIndex::of(i);
            (y[b.x] - mid[0]).hypot(y[b.y] - mid[1])
        };
        let i = (0..n)
            .min_by(|&p, &q| dist(p).total_cmp(&dist(q)))
            .expect("bodies");
        let b = belt_drive::model::state::BodyIndex::of(i);
        let phi = y[b.angle];
        y[b.x] += 3e-4 * phi.cos();
        y[b.y] += 3e-4 * phi.sin();
        assert!(moved.set_state(&y));
        moved.advance(t).expect("runs");
        let before = a.outputs();
        let o = moved.outputs();
        assert!(
            close(o.interval.belt_min_tension, o.min_tension),
            "{method:?}: belt min {} vs {}",
            o.interval.belt_min_tension,
            o.min_tension,
        );
        assert!(
            (o.span_tension[0] - before.span_tension[0]).abs() > 0.1 * before.span_tension[0],
            "{method:?}: the move changes span 1's tension: {} vs {}",
            o.span_tension[0],
            before.span_tension[0]
        );
        for k in 0..4 {
            for got in [
                o.interval.span_mean_tension[k],
                o.interval.span_min_tension[k],
                o.interval.span_max_tension[k],
            ] {
                assert!(
                    close(got, o.span_tension[k]),
                    "{method:?} span {k}: {got} vs {}",
                    o.span_tension[k]
                );
            }
        }
        // the springs turned
        let mut turned = a.clone();
        let angles: Vec<f64> = a.arm_free_angles().iter().map(|x| x + 0.05).collect();
        assert!(turned.set_arm_free_angles(&angles));
        turned.advance(t).expect("runs");
        let o = turned.outputs();
        let j = 3;
        assert!(
            close(
                o.interval.arm_mean_spring_torque[j],
                o.pulleys[j].arm_spring_torque
            ) && (o.pulleys[j].arm_spring_torque - before.pulleys[j].arm_spring_torque).abs() > 1.0,
            "{method:?}: spring torque {} vs {} (before {})",
            o.interval.arm_mean_spring_torque[j],
            o.pulleys[j].arm_spring_torque,
            before.pulleys[j].arm_spring_torque
        );
    }
}
