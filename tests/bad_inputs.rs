//! Bad inputs during a run, through the C ABI, on the fast 40-body drive:
//! NaN and infinite torque / reference speed, a torque far beyond what
//! friction can carry (gross slip), and a load step that throws the belt off
//! its track. The FMU keeps its last good state and says where it stands:
//! * a non-finite input is refused at fmi2SetReal with fmi2Error naming the
//!   variable; outputs (readable in the Error state) are unchanged, and
//!   fmi2SetFMUstate to a state saved before brings the instance back;
//! * a step the model cannot finish returns fmi2Discard with a logged
//!   reason, fmi2GetRealStatus(fmi2LastSuccessfulTime) is the start of that
//!   step, and the outputs are those of that time;
//! * a step the model can finish returns fmi2OK with finite outputs.
//!
//! Prints one line per case (the table in docs/reliability.md).
#![cfg(unix)]

mod abi;

use abi::*;

const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "pulley[1].angle",
    "span[1].tension",
    "span[2].tension",
    "belt.minTension",
    "belt.maxTension",
    "pulley[2].slip",
];

const H: f64 = 1e-3;

/// The fast drive after `steps` steps of `H`, with discard messages on.
fn running(fmi: &Fmi, steps: usize) -> (Instance<'_>, f64) {
    let i = Instance::fast(fmi, &[]);
    i.log_categories(&["logStatusDiscard"]);
    let mut t = 0.0;
    for _ in 0..steps {
        assert_eq!(i.step(t, H), OK, "{:?}", i.log.borrow());
        t += H;
    }
    (i, t)
}

fn status_name(s: i32) -> &'static str {
    [
        "fmi2OK",
        "fmi2Warning",
        "fmi2Discard",
        "fmi2Error",
        "fmi2Fatal",
        "fmi2Pending",
    ][s as usize]
}

#[test]
fn non_finite_inputs_are_refused_and_the_state_kept() {
    let fmi = Fmi::load();
    for (name, x) in [
        ("pulley[1].torque", f64::NAN),
        ("pulley[1].torque", f64::INFINITY),
        ("pulley[2].torque", -f64::INFINITY),
        ("pulley[1].omegaRef", f64::NAN),
        ("pulley[2].omegaRef", f64::INFINITY),
    ] {
        let (i, t) = running(&fmi, 5);
        let saved = i.get_state();
        let before = i.get(OUTPUTS);
        let s = i.set_real(name, x);
        i.assert_refused(s, &format!("{name} must be finite"));
        // Error state: outputs still readable and those of the last good state.
        assert_eq!(i.get(OUTPUTS), before);
        // The importer recovers by going back to the saved state.
        assert_eq!(unsafe { (fmi.set_state)(i.c, saved) }, OK);
        assert_eq!(i.last_successful_time(), (OK, t));
        assert_eq!(i.step(t, H), OK);
        i.free_state(saved);
        println!("{name} = {x}: fmi2SetReal returned fmi2Error, outputs unchanged, fmi2SetFMUstate recovers");
    }
    // Input derivatives too.
    let (i, _) = running(&fmi, 2);
    let (v, order, nan) = (vr("pulley[1].torque"), 1, f64::NAN);
    let s = unsafe { (fmi.set_input_derivatives)(i.c, &v, 1, &order, &nan) };
    i.assert_refused(s, "derivative must be finite");
}

/// Step until `n` steps are done or a step is not fmi2OK; check the
/// contract on the way. Returns (status of the last step, steps done).
fn run_and_check(i: &Instance, mut t: f64, n: usize) -> (i32, usize, f64) {
    for k in 0..n {
        let before = i.get(OUTPUTS);
        let s = i.step(t, H);
        match s {
            OK => {
                t += H;
                let y = i.get(OUTPUTS);
                assert!(y.iter().all(|x| x.is_finite()), "fmi2OK with {y:?}");
                assert_eq!(i.last_successful_time(), (OK, t));
            }
            DISCARD => {
                assert_eq!(i.last_successful_time(), (OK, t), "last good time kept");
                assert_eq!(i.get(OUTPUTS), before, "last good state kept");
                assert!(
                    i.logged(DISCARD, &format!("fmi2DoStep: step from t = {t}")),
                    "{:?}",
                    i.log.borrow()
                );
                // A discarded step can be followed by terminate (StepFailed).
                return (s, k, t);
            }
            other => panic!("fmi2DoStep returned {other}: {:?}", i.log.borrow()),
        }
    }
    (OK, n, t)
}

#[test]
fn overloads_are_simulated_or_discarded_with_the_last_good_state() {
    let fmi = Fmi::load();
    // Friction can carry at most about (T_tight - T_slack) r with
    // T_tight/T_slack = e^(mu*pi) ~ 27: some 30 N m on this 50 mm pulley at
    // 300 N preload. The cases go far beyond.
    let cases: &[(&str, &[(&str, f64)])] = &[
        (
            "drive torque 100 N m (gross slip)",
            &[("pulley[1].torque", -100.0)],
        ),
        ("drive torque 1e4 N m", &[("pulley[1].torque", -1e4)]),
        ("drive torque 1e8 N m", &[("pulley[1].torque", -1e8)]),
        (
            "load torque 1e6 N m on the driven pulley",
            &[("pulley[2].torque", 1e6)],
        ),
        (
            "opposing torques 1e5 N m",
            &[("pulley[1].torque", -1e5), ("pulley[2].torque", -1e5)],
        ),
        (
            "reference speed 1e6 rad/s (torque-driven: no effect)",
            &[("pulley[1].omegaRef", 1e6)],
        ),
        ("torque 1e300 N m", &[("pulley[1].torque", 1e300)]),
    ];
    for (what, inputs) in cases {
        let (i, t) = running(&fmi, 3);
        for (name, x) in *inputs {
            assert_eq!(i.set_real(name, *x), OK);
        }
        let (s, done, t_end) = run_and_check(&i, t, 20);
        let note = if s == DISCARD {
            let (_, _, m) = i
                .log
                .borrow()
                .iter()
                .rev()
                .find(|(s, _, _)| *s == DISCARD)
                .cloned()
                .unwrap();
            format!("after {done} good steps; last successful time {t_end}; log: {m}")
        } else {
            let y = i.get(&["pulley[1].omega", "pulley[2].slip"]);
            format!(
                "20 steps; pulley[1].omega = {:.4e} rad/s, pulley[2].slip = {:.3}",
                y[0], y[1]
            )
        };
        println!("{what}: {} {note}", status_name(s));
        if s == DISCARD {
            // StepFailed: fmi2Terminate is allowed.
            assert_eq!(unsafe { (fmi.terminate)(i.c) }, OK);
        }
    }
}

#[test]
fn speed_driven_pulley_with_a_huge_reference_speed() {
    let fmi = Fmi::load();
    let i = Instance::new(&fmi);
    for (n, x) in FAST_INTS {
        assert_eq!(i.set_integer(n, *x), OK);
    }
    for (n, x) in FAST_REALS {
        assert_eq!(i.set_real(n, *x), OK);
    }
    assert_eq!(i.set_boolean("pulley[1].speedDriven", true), OK);
    i.log_categories(&["logStatusDiscard"]);
    unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        assert_eq!((fmi.exit_init)(i.c), OK, "{:?}", i.log.borrow());
    }
    let (s, _, t) = run_and_check(&i, 0.0, 3);
    assert_eq!(s, OK);
    // A jump of the prescribed speed to 1e5 rad/s (5 km/s belt speed).
    assert_eq!(i.set_real("pulley[1].omegaRef", -1e5), OK);
    let (s, done, t_end) = run_and_check(&i, t, 5);
    println!(
        "speed-driven pulley, omegaRef jumps to -1e5 rad/s: {} after {done} steps at t = {t_end}",
        status_name(s)
    );
}
