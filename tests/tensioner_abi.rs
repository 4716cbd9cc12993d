//! The tensioner arm through the C ABI (the built library via dlopen): the
//! tensioner parameter set runs, the arm's states and the spring's mounted
//! free angle travel in a serialized FMU state (the restored instance
//! continues bit-identically), a state of the previous snapshot version is
//! refused with a clear message, and bad arm parameters are refused at
//! initialization with the parameter named.
#![cfg(unix)]

mod abi;

use abi::*;

const ARM: &[&str] = &[
    "pulley[4].arm.angle",
    "pulley[4].arm.omega",
    "pulley[4].arm.springTorque",
    "pulley[4].arm.freeAngle",
    "pulley[4].hubForce.x",
    "pulley[4].hubForce.y",
    "pulley[3].rotor.omega",
    "span[4].tension",
];

/// An instance with every parameter of `parameters/accessory-drive-tensioner.ssv`
/// set as an importer would, initialized at t = 0.
fn tensioner_set(fmi: &Fmi) -> Instance<'_> {
    let i = Instance::new(fmi);
    i.set_ssv("accessory-drive-tensioner.ssv");
    i.initialize();
    i
}

#[test]
fn tensioner_set_runs_and_its_arm_travels_in_a_serialized_state() {
    let fmi = Fmi::load();
    let a = tensioner_set(&fmi);
    let at_rest = a.get(ARM);
    println!("mounted: {ARM:?} = {at_rest:?}");
    // mounted at rest: the spring wound up to balance the belt, the arm
    // where it was placed
    assert_eq!(at_rest[0], 0.0);
    assert!(at_rest[3].abs() > 0.1, "{at_rest:?}");
    // spring torque -k (angle - free angle), k = 40 N m/rad
    assert!((at_rest[2] + 40.0 * (at_rest[0] - at_rest[3])).abs() < 1e-9);
    for k in 0..20 {
        assert_eq!(
            a.step(f64::from(k) * 1e-3, 1e-3),
            OK,
            "{:?}",
            a.log.borrow()
        );
    }
    let out = a.get(ARM);
    println!("after 20 ms: {out:?}");
    assert!(out.iter().all(|x| x.is_finite()));
    // the arm moves as the crank spins up (but not by a jolt: < 0.05 rad)
    assert!(out[0] != 0.0 && out[0].abs() < 0.05, "{out:?}");
    assert_eq!(out[3], at_rest[3], "the free angle is a constant");
    let st = a.get_state();
    let bytes = a.serialize(st);
    a.free_state(st);
    assert_eq!(a.step(0.02, 1e-3), OK);
    let expected = a.get(ARM);
    // into an initialized instance of the plain fast drive (no arm): the
    // state restores the arm's angle, rate and the spring's free angle
    let b = Instance::fast(&fmi, &[]);
    assert_eq!(b.step(0.0, 1e-3), OK);
    let (status, s2) = b.deserialize(&bytes);
    assert_eq!(status, OK, "{:?}", b.log.borrow());
    assert_eq!(unsafe { (fmi.set_state)(b.c, s2) }, OK);
    assert_eq!(b.step(0.02, 1e-3), OK);
    assert_eq!(b.get(ARM), expected, "continues bit-identically");
    b.free_state(s2);
}

/// FNV-1a 64, the FMU state's checksum (src/fmi/state.rs).
fn fnv1a_64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A state written by the previous snapshot version (6: six pulley slots and
/// no arm stops among the parameters; 5 no interval outputs in the integrator
/// data; 4 no first stage of the stiff method; 3 had no impulse states behind
/// the mean force outputs, 2 no tensioner free angles either) is refused
/// with a message saying so, not misread.
#[test]
fn a_state_of_the_previous_version_is_refused() {
    let fmi = Fmi::load();
    let a = Instance::fast(&fmi, &[]);
    assert_eq!(a.step(0.0, 1e-3), OK);
    let st = a.get_state();
    let mut bytes = a.serialize(st);
    a.free_state(st);
    // model bytes after magic (8), format (4), GUID (4 + n), mode (1),
    // time (8), stop time (1 + 8), model length (8); they start with the
    // snapshot version
    let guid_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let model = 16 + guid_len + 1 + 8 + 9 + 8;
    assert_eq!(
        u32::from_le_bytes(bytes[model..model + 4].try_into().unwrap()),
        7
    );
    bytes[model..model + 4].copy_from_slice(&6u32.to_le_bytes());
    let n = bytes.len() - 8;
    let sum = fnv1a_64(&bytes[..n]);
    bytes[n..].copy_from_slice(&sum.to_le_bytes());
    let (status, _) = a.deserialize(&bytes);
    assert_eq!(status, ERROR);
    assert!(
        a.logged(ERROR, "model state version 6 is not supported (expected 7)"),
        "{:?}",
        a.log.borrow()
    );
}

/// The fast drive with an arm on pulley 2 (pivot 80 mm above its centre)
/// and one arm parameter `(name, value)` set on top; the status of
/// fmi2ExitInitializationMode.
fn with_arm<'a>(fmi: &'a Fmi, bad: (&str, f64)) -> (Instance<'a>, i32) {
    let i = Instance::new(fmi);
    for (n, x) in FAST_INTS {
        assert_eq!(i.set_integer(n, *x), OK);
    }
    for (n, x) in FAST_REALS {
        assert_eq!(i.set_real(n, *x), OK);
    }
    assert_eq!(i.set_boolean("pulley[2].tensioner", true), OK);
    assert_eq!(i.set_real("pulley[2].arm.pivot.x", 0.25), OK);
    assert_eq!(i.set_real("pulley[2].arm.pivot.y", 0.08), OK);
    assert_eq!(i.set_real(bad.0, bad.1), OK);
    let s = unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        (fmi.exit_init)(i.c)
    };
    (i, s)
}

#[test]
fn bad_arm_parameters_are_refused_by_name() {
    let fmi = Fmi::load();
    // a valid arm initializes and runs
    let (i, s) = with_arm(&fmi, ("pulley[2].arm.friction", 0.5));
    assert_eq!(s, OK, "{:?}", i.log.borrow());
    assert_eq!(i.step(0.0, 1e-3), OK);
    for (name, value, named) in [
        ("pulley[2].arm.inertia", 0.0, "pulley[2].arm.inertia"),
        ("pulley[2].arm.stiffness", 0.0, "pulley[2].arm.stiffness"),
        ("pulley[2].arm.damping", -0.1, "pulley[2].arm.damping"),
        ("pulley[2].arm.friction", -1.0, "pulley[2].arm.friction"),
        ("pulley[2].arm.hubFriction", -0.1, "pulley[2].arm.hubFriction"),
        // a hub-load friction coefficient without its radius
        ("pulley[2].arm.hubFriction", 0.3, "pulley[2].arm.frictionRadius"),
        ("pulley[2].arm.pivot.x", f64::NAN, "pulley[2].arm.pivot.x"),
        ("pulley[2].arm.pivot.y", 2e3, "pulley[2].arm.pivot.y"),
        // the pivot at the pulley centre: no arm
        ("pulley[2].arm.pivot.y", 0.0, "pulley[2].arm.pivot.x"),
    ] {
        let (i, s) = with_arm(&fmi, (name, value));
        assert_eq!(s, ERROR, "{name} = {value}");
        assert!(
            i.log
                .borrow()
                .iter()
                .any(|(st, _, m)| *st == ERROR && m.contains(named)),
            "{name} = {value}: no error naming {named}: {:?}",
            i.log.borrow()
        );
    }
}
