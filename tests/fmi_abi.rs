//! The built FMU binary through its C ABI: `dlopen` the cdylib that cargo
//! builds next to this test (`target/<profile>/libbelt_drive.so`), look up
//! the `fmi2...` symbols and call them like an importer would (loader and
//! instance wrapper in `tests/abi/mod.rs`).
#![cfg(unix)]

mod abi;

use std::ffi::{c_char, c_int, CStr, CString};
use std::ptr;

use abi::*;
use belt_drive::fmu::variables::GUID;

const OUTPUTS: &[&str] = &[
    "pulley[1].omega",
    "pulley[2].omega",
    "span[1].tension",
    "probe.sdeForce",
];

#[test]
fn exports_and_platform() {
    let fmi = Fmi::load();
    let sym = |name: &str| {
        let c = CString::new(name).unwrap();
        unsafe { libc::dlsym(fmi.handle, c.as_ptr()) }
    };
    let get_version: unsafe extern "C" fn() -> *const c_char =
        unsafe { std::mem::transmute(sym("fmi2GetVersion")) };
    let get_platform: unsafe extern "C" fn() -> *const c_char =
        unsafe { std::mem::transmute(sym("fmi2GetTypesPlatform")) };
    unsafe {
        assert_eq!(CStr::from_ptr(get_version()).to_str(), Ok("2.0"));
        assert_eq!(CStr::from_ptr(get_platform()).to_str(), Ok("default"));
    }
    assert!(
        sym("fmi2SetTime").is_null(),
        "Model Exchange functions are not exported"
    );
}

#[test]
fn instantiate_refusals_are_logged() {
    let fmi = Fmi::load();
    let (c, log) = Instance::try_new(
        &fmi,
        "{00000000-0000-0000-0000-000000000000}",
        CO_SIMULATION,
    );
    assert!(c.is_null());
    let lines = log.borrow();
    assert!(
        lines
            .iter()
            .any(|(s, _, m)| *s == ERROR && m.contains("fmuGUID") && m.contains(GUID)),
        "{lines:?}"
    );
    let (c, log) = Instance::try_new(&fmi, GUID, MODEL_EXCHANGE);
    assert!(c.is_null());
    assert!(log
        .borrow()
        .iter()
        .any(|(_, _, m)| m.contains("Co-Simulation only")));
}

#[test]
fn illegal_calls_are_refused_with_a_log_line() {
    let fmi = Fmi::load();
    // fmi2Error puts the instance into the error state: one instance per rule.
    let i = Instance::new(&fmi);
    i.assert_refused(i.step(0.0, 1e-3), "fmi2DoStep: illegal call sequence");

    let i = Instance::new(&fmi);
    i.assert_refused(i.set_real("pulley[1].omega", 1.0), "is an output");

    let i = Instance::new(&fmi);
    let x = 1.0;
    i.assert_refused(
        unsafe { (fmi.set_real)(i.c, &999_999, 1, &x) },
        "unknown value reference 999999",
    );

    let i = Instance::new(&fmi);
    let one = 1;
    i.assert_refused(
        unsafe { (fmi.set_integer)(i.c, &vr("gravity"), 1, &one) },
        "not a Integer variable",
    );

    let i = Instance::new(&fmi);
    i.assert_refused(
        unsafe { (fmi.set_real)(i.c, ptr::null(), 3, &x) },
        "vr[] is a NULL pointer",
    );

    let i = Instance::new(&fmi);
    i.assert_refused(
        unsafe { (fmi.set_real)(i.c, &vr("gravity"), 1, ptr::null()) },
        "value[] is a NULL pointer",
    );

    let i = Instance::initialized(&fmi, &[]);
    i.assert_refused(
        i.set_real("belt.preload", 100.0),
        "only be set in Instantiated or Initialization Mode",
    );

    let i = Instance::initialized(&fmi, &[]);
    i.assert_refused(i.step(0.5, 1e-3), "currentCommunicationPoint");

    let i = Instance::initialized(&fmi, &[]);
    let mut y = 0.0;
    i.assert_refused(
        unsafe { (fmi.get_real)(i.c, &vr("gravity"), 1, ptr::null_mut()) },
        "value[] is a NULL pointer",
    );
    assert_eq!(
        unsafe { (fmi.get_real)(i.c, ptr::null(), 0, &mut y) },
        OK,
        "nvr = 0 with NULL is fine"
    );

    let i = Instance::initialized(&fmi, &[]);
    i.assert_refused(unsafe { (fmi.cancel_step)(i.c) }, "fmi2CancelStep");

    let i = Instance::initialized(&fmi, &[]);
    let status = unsafe {
        (fmi.directional_derivative)(
            i.c,
            ptr::null(),
            0,
            ptr::null(),
            0,
            ptr::null(),
            ptr::null_mut(),
        )
    };
    i.assert_refused(status, "providesDirectionalDerivative");

    assert_eq!(
        unsafe { (fmi.do_step)(ptr::null_mut(), 0.0, 1e-3, 0) },
        ERROR,
        "NULL instance"
    );
}

#[test]
fn status_queries() {
    let fmi = Fmi::load();
    let i = Instance::initialized(&fmi, &[]);
    assert_eq!(i.step(0.0, 1e-3), OK);
    let mut t = 0.0;
    assert_eq!(
        unsafe { (fmi.get_real_status)(i.c, LAST_SUCCESSFUL_TIME, &mut t) },
        OK
    );
    assert_eq!(t, 1e-3);
    let mut st = -1;
    assert_eq!(
        unsafe { (fmi.get_status)(i.c, 0, &mut st) },
        DISCARD,
        "no asynchronous step to report"
    );
}

/// A valid but doubtful parameter (contact damping ramp far beyond the
/// penetration) initializes with fmi2OK and a fmi2Warning log line naming
/// the parameter, with logging off; the default drive logs no warning, nor
/// does the stiff method at relTol 1e-3.
#[test]
fn parameter_warning_reaches_the_logger() {
    let fmi = Fmi::load();
    let quiet = Instance::initialized(&fmi, &[]);
    assert!(!quiet.logged(1, ""), "{:?}", quiet.log.borrow());
    let i = Instance::initialized(&fmi, &[("contact.pMax", 5e-3)]);
    assert!(i.logged(1, "contact.pMax = 5e-3 m"), "{:?}", i.log.borrow());
    assert!(i.logged(1, "set contact.pMax to 0 (automatic"));
    // the stiff method at an importer's loose tolerance is not doubtful
    // (tests/defaults.rs measures it)
    let s = Instance::initialized_with(&fmi, &[("solver.method", 2)], &[("solver.relTol", 1e-3)]);
    assert!(!s.logged(1, ""), "{:?}", s.log.borrow());
}

#[test]
fn two_instances_with_different_parameters() {
    let fmi = Fmi::load();
    let a = Instance::initialized(&fmi, &[("belt.preload", 400.0)]);
    let b = Instance::initialized(&fmi, &[("belt.preload", 600.0)]);
    for k in 0..3 {
        let t = f64::from(k) * 5e-4;
        assert_eq!(a.step(t, 5e-4), OK);
        assert_eq!(b.step(t, 5e-4), OK);
    }
    assert_eq!(a.get(&["belt.preload"]), [400.0]);
    assert_eq!(b.get(&["belt.preload"]), [600.0]);
    let (ta, tb) = (
        a.get(&["span[1].tension"])[0],
        b.get(&["span[1].tension"])[0],
    );
    assert!(ta.is_finite() && tb.is_finite());
    assert_ne!(ta, tb, "the preload shows in the span tension");

    // The same parameters alone give the same numbers (no shared state).
    let c = Instance::initialized(&fmi, &[("belt.preload", 400.0)]);
    for k in 0..3 {
        assert_eq!(c.step(f64::from(k) * 5e-4, 5e-4), OK);
    }
    assert_eq!(c.get(OUTPUTS), a.get(OUTPUTS));
}

#[test]
fn get_set_state_is_bit_identical() {
    let fmi = Fmi::load();
    let i = Instance::initialized(&fmi, &[]);
    assert_eq!(i.step(0.0, 1e-3), OK);
    let mut s = i.get_state();
    let run = || -> Vec<Vec<f64>> {
        (0..2)
            .map(|k| {
                assert_eq!(i.step(1e-3 + f64::from(k) * 1e-3, 1e-3), OK);
                i.get(OUTPUTS)
            })
            .collect()
    };
    let first = run();
    assert_eq!(unsafe { (fmi.set_state)(i.c, s) }, OK);
    assert_eq!(run(), first);
    assert_eq!(unsafe { (fmi.free_state)(i.c, &mut s) }, OK);
    assert!(s.is_null(), "fmi2FreeFMUstate sets the pointer to NULL");
}

#[test]
fn serialized_state_round_trip_and_refusals() {
    let fmi = Fmi::load();
    let i = Instance::initialized(&fmi, &[]);
    assert_eq!(i.step(0.0, 1e-3), OK);
    let mut s = i.get_state();
    let bytes = i.serialize(s);
    assert_eq!(&bytes[..8], b"BELTFMU\0");
    assert_eq!(i.step(1e-3, 1e-3), OK);
    let expected = i.get(OUTPUTS);

    // Restore into a fresh instance and continue from there.
    let j = Instance::new(&fmi);
    let (status, mut s2) = j.deserialize(&bytes);
    assert_eq!(status, OK, "{:?}", j.log.borrow());
    assert_eq!(unsafe { (fmi.set_state)(j.c, s2) }, OK);
    assert_eq!(j.step(1e-3, 1e-3), OK);
    assert_eq!(j.get(OUTPUTS), expected);
    assert_eq!(j.serialize(s2), bytes, "serialization is deterministic");

    let mut corrupted = bytes.clone();
    let mid = corrupted.len() / 2;
    corrupted[mid] ^= 0xff;
    let k = Instance::new(&fmi);
    let (status, s3) = k.deserialize(&corrupted);
    k.assert_refused(status, "fmi2DeSerializeFMUstate");
    assert!(s3.is_null());

    let k = Instance::new(&fmi);
    let (status, s3) = k.deserialize(&bytes[..bytes.len() / 3]);
    k.assert_refused(status, "truncated");
    assert!(s3.is_null());

    unsafe {
        assert_eq!((fmi.free_state)(i.c, &mut s), OK);
        assert_eq!((fmi.free_state)(j.c, &mut s2), OK);
    }
}
/// fmi2SetDebugLogging through the C ABI: the listed categories (and only
/// they) are forwarded, logAll traces calls, loggingOn = false with no list
/// silences everything but errors, an unknown category is fmi2Error with a
/// message that lists the defined ones.
#[test]
fn debug_logging_honours_the_categories() {
    let fmi = Fmi::load();
    let set_logging = |i: &Instance, on: bool, categories: &[&str]| -> c_int {
        let names: Vec<CString> = categories
            .iter()
            .map(|c| CString::new(*c).unwrap())
            .collect();
        let ptrs: Vec<*const c_char> = names.iter().map(|c| c.as_ptr()).collect();
        let list = if ptrs.is_empty() {
            ptr::null()
        } else {
            ptrs.as_ptr()
        };
        // SAFETY: live instance; `ptrs` holds `len` valid C strings.
        unsafe { (fmi.set_debug_logging)(i.c, on as c_int, ptrs.len(), list) }
    };
    let take = |i: &Instance| std::mem::take(&mut *i.log.borrow_mut());
    let categories = |lines: &[(c_int, String, String)]| -> Vec<String> {
        lines.iter().map(|(_, c, _)| c.clone()).collect()
    };

    // Instantiated with loggingOn = false: nothing but errors.
    let i = Instance::new(&fmi);
    assert_eq!(i.set_integer("solver.maxSteps", 1), OK); // every step is discarded
    assert_eq!(set_logging(&i, true, &["logStatusDiscard"]), OK);
    for (name, x) in SHORT {
        assert_eq!(i.set_integer(name, *x), OK);
    }
    unsafe {
        assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi.enter_init)(i.c), OK);
        assert_eq!((fmi.exit_init)(i.c), OK);
    }
    assert_eq!(take(&i), vec![], "logEvents is off");
    assert_eq!(i.step(0.0, 1e-3), DISCARD);
    let lines = take(&i);
    assert_eq!(categories(&lines), ["logStatusDiscard"], "{lines:?}");
    assert_eq!(lines[0].0, DISCARD);

    // Exactly the listed categories: logEvents on, logStatusDiscard off
    // (fmi2Terminate is the call allowed after a discarded step).
    assert_eq!(set_logging(&i, true, &["logEvents"]), OK);
    assert_eq!(unsafe { (fmi.terminate)(i.c) }, OK);
    let lines = take(&i);
    assert_eq!(categories(&lines), ["logEvents"], "{lines:?}");
    assert!(lines[0].2.contains("terminated"));

    // logAll: a trace line per call, on top of the categories' messages.
    let i = Instance::initialized(&fmi, &[]);
    assert_eq!(set_logging(&i, true, &["logAll"]), OK);
    assert_eq!(i.step(0.0, 1e-3), OK);
    let lines = take(&i);
    assert!(
        lines
            .iter()
            .any(|(s, c, m)| *s == OK && c == "logAll" && m.contains("fmi2DoStep")),
        "{lines:?}"
    );
    // loggingOn = false with no list: all off (the call itself is still
    // traced: logAll was on when it came in).
    assert_eq!(set_logging(&i, false, &[]), OK);
    take(&i);
    assert_eq!(i.step(1e-3, 1e-3), OK);
    assert_eq!(take(&i), vec![]);
    // loggingOn = true with no list: all on.
    assert_eq!(set_logging(&i, true, &[]), OK);
    assert_eq!(unsafe { (fmi.terminate)(i.c) }, OK);
    let lines = take(&i);
    assert!(
        lines
            .iter()
            .any(|(s, c, m)| *s == OK && c == "logEvents" && m.contains("terminated")),
        "{lines:?}"
    );

    // An unknown category is refused; the message lists the defined ones.
    let j = Instance::new(&fmi);
    let status = set_logging(&j, true, &["logEvents", "logNoSuchThing"]);
    j.assert_refused(status, "unknown log category \"logNoSuchThing\"");
    j.assert_refused(status, "logStatusError");
}
