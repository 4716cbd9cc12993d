//! Stepping past communication points, through the C ABI of the built
//! library: what an importer sees. With the inputs held the FMU steps past
//! the points (its steps do not depend on the communication step); a saved
//! state carries the step taken past, so a restored run continues to the
//! bit; an input set to the value it holds changes nothing, and a changed
//! one drops the step past and continues from the state shown, identically
//! in a restored run.

mod abi;

use abi::*;

/// Every output the comparison reads.
const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "pulley[1].beltTorque",
    "pulley[2].meanBeltTorque",
    "pulley[1].meanDriveTorque",
    "span[1].tension",
    "span[1].meanTension",
    "span[2].maxTension",
    "solver.steps",
    "solver.rhsEvaluations",
];

/// The outputs after each of `n` communication steps of `h` from `t`,
/// with `before(k)` called before step k.
fn run(i: &Instance, t: f64, h: f64, n: usize, before: &mut dyn FnMut(usize)) -> Vec<u64> {
    let mut out = Vec::new();
    for k in 0..n {
        before(k);
        assert_eq!(i.step(t + k as f64 * h, h), OK);
        out.extend(i.get(OUTPUTS).iter().map(|x| x.to_bits()));
    }
    out
}

fn stiff(fmi: &Fmi) -> Instance<'_> {
    Instance::initialized_with(fmi, &[("solver.method", 2)], &[])
}

/// A state saved while the FMU is past the communication point (in
/// memory and serialized) continues, held or with an input changed right
/// after the restore, exactly as the run that was not saved.
#[test]
fn a_saved_state_continues_like_the_unsaved_run() {
    let fmi = Fmi::load();
    for method in [1, 2] {
        let a = Instance::initialized_with(&fmi, &[("solver.method", method)], &[]);
        let h = 1e-4;
        run(&a, 0.0, h, 37, &mut |_| {});
        let t = 37.0 * h;
        let s = a.get_state();
        let bytes = a.serialize(s);
        let b = Instance::new(&fmi);
        let (status, s2) = b.deserialize(&bytes);
        assert_eq!(status, OK);
        assert_eq!(unsafe { (fmi.set_state)(b.c, s2) }, OK);
        // an input change at the 5th point after the restore: the step
        // past is retaken clipped in both
        fn change(i: &Instance, k: usize) {
            if k == 5 {
                assert_eq!(i.set_real("pulley[2].torque", -0.5), OK);
            }
        }
        let held = run(&a, t, h, 20, &mut |k| change(&a, k));
        let restored = run(&b, t, h, 20, &mut |k| change(&b, k));
        let first = held.iter().zip(&restored).position(|(x, y)| x != y);
        assert!(
            held == restored,
            "method {method}: serialized state, first difference {:?}",
            first.map(|i| (i / OUTPUTS.len(), OUTPUTS[i % OUTPUTS.len()]))
        );
        // the in-memory state on the first instance
        assert_eq!(unsafe { (fmi.set_state)(a.c, s) }, OK);
        let again = run(&a, t, h, 20, &mut |k| change(&a, k));
        assert!(held == again, "method {method}: fmi2SetFMUstate");
        a.free_state(s);
        b.free_state(s2);
    }
}

/// An input set again to the value it holds leaves the step past valid:
/// the run is the run without the call, to the bit, steps included.
#[test]
fn an_input_set_to_its_value_changes_nothing() {
    let fmi = Fmi::load();
    let (a, b) = (stiff(&fmi), stiff(&fmi));
    assert_eq!(a.set_real("pulley[2].torque", 0.0), OK);
    let set = run(&a, 0.0, 1e-4, 50, &mut |_| {
        assert_eq!(a.set_real("pulley[2].torque", 0.0), OK);
    });
    let plain = run(&b, 0.0, 1e-4, 50, &mut |_| {});
    assert!(set == plain);
}

/// 0.1 ms and 1 ms communication steps: the same integrator steps (so the
/// same cost in steps) and mean span tensions within 0.05 % (issue 33),
/// both methods.
#[test]
fn short_communication_steps_take_the_same_steps() {
    let fmi = Fmi::load();
    for method in [1, 2] {
        let means = |h: f64| {
            let i = Instance::initialized_with(&fmi, &[("solver.method", method)], &[]);
            let n0 = (0.05 / h).round() as usize;
            run(&i, 0.0, h, n0, &mut |_| {});
            let steps0 = i.get(&["solver.steps"])[0];
            let n = (0.05 / h).round() as usize;
            let mut mean = [0.0; 2];
            for k in 0..n {
                assert_eq!(i.step(0.05 + k as f64 * h, h), OK);
                let o = i.get(&["span[1].meanTension", "span[2].meanTension"]);
                for (m, x) in mean.iter_mut().zip(o) {
                    *m += x / n as f64;
                }
            }
            (mean, i.get(&["solver.steps"])[0] - steps0)
        };
        let (m1, steps1) = means(1e-3);
        let (m2, steps2) = means(1e-4);
        // the same steps but where a step ends within 1e-12 of a point
        assert!(
            steps2 <= steps1 * 1.01,
            "method {method}: {steps2} steps at 0.1 ms, {steps1} at 1 ms"
        );
        for j in 0..2 {
            let rel = (m2[j] / m1[j] - 1.0).abs();
            assert!(
                rel < 5e-4,
                "method {method} span {}: {} vs {}",
                j + 1,
                m1[j],
                m2[j]
            );
        }
    }
}
