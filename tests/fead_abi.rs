//! The accessory-drive variables through the C ABI (the built library via
//! dlopen): a decoupler's states travel in a serialized FMU state and the
//! restored instance continues bit-identically; its outputs are wired; bad
//! decoupler and groove parameters are refused at initialization with the
//! parameter named.
#![cfg(unix)]

mod abi;

use abi::*;

/// The fast drive (its -2 N m torque ramp turns it clockwise) with a 40 deg
/// groove on pulley 1 and a decoupler on pulley 2 driving clockwise.
fn with_decoupler<'a>(fmi: &'a Fmi, damping: f64) -> (Instance<'a>, i32) {
    let i = Instance::new(fmi);
    for (n, x) in FAST_INTS {
        assert_eq!(i.set_integer(n, *x), OK);
    }
    for (n, x) in FAST_REALS {
        assert_eq!(i.set_real(n, *x), OK);
    }
    assert_eq!(i.set_boolean("pulley[2].decoupler", true), OK);
    assert_eq!(i.set_boolean("pulley[2].decoupler.clockwise", true), OK);
    assert_eq!(i.set_real("pulley[2].decoupler.damping", damping), OK);
    assert_eq!(i.set_real("pulley[2].rotor.inertia", 2e-3), OK);
    assert_eq!(i.set_real("pulley[1].grooveAngle", 0.698), OK);
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    (i, s)
}

const OUTPUTS: &[&str] = &[
    "pulley[2].omega",
    "pulley[2].rotor.omega",
    "pulley[2].decoupler.torque",
    "span[1].midDeflection",
    "span[1].midDeflectionRate",
    "span[2].midDeflection",
];

#[test]
fn decoupler_state_travels_in_a_serialized_state() {
    let fmi = Fmi::load();
    let (a, s) = with_decoupler(&fmi, 0.02);
    assert_eq!(s, OK, "{:?}", a.log.borrow());
    for k in 0..10 {
        assert_eq!(a.step(f64::from(k) * 1e-3, 1e-3), OK);
    }
    // the drive turns clockwise and the clutch drives the rotor: both
    // negative, the clutch transmits torque, the span is measured
    let out = a.get(OUTPUTS);
    println!("after 10 ms: {OUTPUTS:?} = {out:?}");
    assert!(out[0] < 0.0 && out[1] < 0.0, "{out:?}");
    assert!(out[2] > 0.0, "{out:?}");
    assert!(
        out[3].is_finite() && out[3] != 0.0 && out[3].abs() < 1e-3,
        "{out:?}"
    );
    let st = a.get_state();
    let bytes = a.serialize(st);
    a.free_state(st);
    assert_eq!(a.step(0.01, 1e-3), OK);
    let expected = a.get(OUTPUTS);
    // into an initialized instance of the plain fast drive (no decoupler):
    // the state restores the decoupler with its twist and rotor speed
    let b = Instance::fast(&fmi, &[]);
    assert_eq!(b.step(0.0, 1e-3), OK);
    let (status, s2) = b.deserialize(&bytes);
    assert_eq!(status, OK, "{:?}", b.log.borrow());
    assert_eq!(unsafe { (fmi.set_state)(b.c, s2) }, OK);
    assert_eq!(b.step(0.01, 1e-3), OK);
    assert_eq!(b.get(OUTPUTS), expected, "continues bit-identically");
    b.free_state(s2);
}

fn refused_naming(i: &Instance, status: i32, parameter: &str) {
    assert_eq!(status, ERROR);
    let log = i.log.borrow();
    assert!(
        log.iter()
            // `name: message` or `name must be ...` (src/fmu/names.rs,
            // render_error): the parameter is the subject, not only mentioned
            .any(|(s, _, m)| *s == ERROR
                && (m.contains(&format!("{parameter}:"))
                    || m.contains(&format!("{parameter} must be")))),
        "no error naming {parameter}: {log:?}"
    );
}

#[test]
fn bad_decoupler_and_groove_parameters_are_refused_by_name() {
    let fmi = Fmi::load();
    // the decoupler's spring relaxes through its damper: 0 is refused
    let (i, s) = with_decoupler(&fmi, 0.0);
    refused_naming(&i, s, "pulley[2].decoupler.damping");
    // a 1 deg groove would multiply mu by 115
    let i = Instance::new(&fmi);
    for (n, x) in FAST_INTS {
        assert_eq!(i.set_integer(n, *x), OK);
    }
    for (n, x) in FAST_REALS {
        assert_eq!(i.set_real(n, *x), OK);
    }
    assert_eq!(i.set_real("pulley[1].grooveAngle", 0.0175), OK);
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    refused_naming(&i, s, "pulley[1].grooveAngle");
}
