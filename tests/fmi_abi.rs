//! The built FMU binary through its C ABI: `dlopen` the cdylib that cargo
//! builds next to this test (`target/<profile>/libbelt_drive.so`), look up
//! the `fmi2...` symbols and call them like an importer would.
//!
//! The logger here is a plain (non-variadic) `extern "C"` function: the FMU
//! always calls its logger with the finished message as the format string
//! (every `%` doubled) and no variadic arguments, so the fixed arguments are
//! passed exactly as for a non-variadic call and `message` can be read as is.
#![cfg(unix)]

use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::path::PathBuf;
use std::ptr;

use belt_drive::variables::{by_name, GUID};

const OK: c_int = 0;
const DISCARD: c_int = 2;
const ERROR: c_int = 3;
const CO_SIMULATION: c_int = 1;
const MODEL_EXCHANGE: c_int = 0;
const LAST_SUCCESSFUL_TIME: c_int = 2;

type Component = *mut c_void;
type State = *mut c_void;
type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

#[repr(C)]
struct Callbacks {
    logger: Option<Logger>,
    allocate_memory: *const c_void,
    free_memory: *const c_void,
    step_finished: *const c_void,
    component_environment: *mut c_void,
}

/// (status, category, message) of each logger call.
type Log = RefCell<Vec<(c_int, String, String)>>;

unsafe extern "C" fn logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log` passed at instantiation; the FMU passes
    // valid C strings.
    let (log, category, message) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.borrow_mut().push((status, category, message));
}

/// The library and the functions used here.
struct Fmi {
    _handle: *mut c_void,
    instantiate: unsafe extern "C" fn(
        *const c_char,
        c_int,
        *const c_char,
        *const c_char,
        *const Callbacks,
        c_int,
        c_int,
    ) -> Component,
    free_instance: unsafe extern "C" fn(Component),
    set_debug_logging: unsafe extern "C" fn(Component, c_int, usize, *const *const c_char) -> c_int,
    terminate: unsafe extern "C" fn(Component) -> c_int,
    setup_experiment: unsafe extern "C" fn(Component, c_int, f64, f64, c_int, f64) -> c_int,
    enter_init: unsafe extern "C" fn(Component) -> c_int,
    exit_init: unsafe extern "C" fn(Component) -> c_int,
    get_real: unsafe extern "C" fn(Component, *const c_uint, usize, *mut f64) -> c_int,
    set_real: unsafe extern "C" fn(Component, *const c_uint, usize, *const f64) -> c_int,
    set_integer: unsafe extern "C" fn(Component, *const c_uint, usize, *const c_int) -> c_int,
    do_step: unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int,
    get_real_status: unsafe extern "C" fn(Component, c_int, *mut f64) -> c_int,
    get_status: unsafe extern "C" fn(Component, c_int, *mut c_int) -> c_int,
    get_state: unsafe extern "C" fn(Component, *mut State) -> c_int,
    set_state: unsafe extern "C" fn(Component, State) -> c_int,
    free_state: unsafe extern "C" fn(Component, *mut State) -> c_int,
    state_size: unsafe extern "C" fn(Component, State, *mut usize) -> c_int,
    serialize: unsafe extern "C" fn(Component, State, *mut c_char, usize) -> c_int,
    deserialize: unsafe extern "C" fn(Component, *const c_char, usize, *mut State) -> c_int,
    cancel_step: unsafe extern "C" fn(Component) -> c_int,
    directional_derivative: unsafe extern "C" fn(
        Component,
        *const c_uint,
        usize,
        *const c_uint,
        usize,
        *const f64,
        *mut f64,
    ) -> c_int,
}

fn library_path() -> PathBuf {
    let name = if cfg!(target_os = "macos") {
        "libbelt_drive.dylib"
    } else {
        "libbelt_drive.so"
    };
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("deps directory");
    [deps.join(name), deps.join("..").join(name)]
        .into_iter()
        .find(|p| p.exists())
        .unwrap_or_else(|| panic!("{name} not found next to {}", exe.display()))
}

/// Every function the standard requires of a Co-Simulation FMU.
const CS_FUNCTIONS: &[&str] = &[
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

impl Fmi {
    fn load() -> Fmi {
        let path = CString::new(library_path().to_string_lossy().as_bytes()).unwrap();
        // SAFETY: dlopen of our own library; its initialisers are Rust's.
        let handle = unsafe { libc::dlopen(path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
        assert!(!handle.is_null(), "dlopen {path:?} failed");
        let sym = |name: &str| -> *mut c_void {
            let c = CString::new(name).unwrap();
            // SAFETY: valid handle and C string.
            let p = unsafe { libc::dlsym(handle, c.as_ptr()) };
            assert!(!p.is_null(), "symbol {name} is not exported");
            p
        };
        for name in CS_FUNCTIONS {
            sym(name);
        }
        /// The symbol as the function-pointer type of the field it fills.
        fn f<F: Copy>(p: *mut c_void) -> F {
            assert_eq!(size_of::<F>(), size_of::<*mut c_void>());
            // SAFETY: `p` is the FMI 2.0 function of that name, whose C
            // prototype the field type `F` mirrors.
            unsafe { std::mem::transmute_copy(&p) }
        }
        Fmi {
            _handle: handle,
            instantiate: f(sym("fmi2Instantiate")),
            free_instance: f(sym("fmi2FreeInstance")),
            set_debug_logging: f(sym("fmi2SetDebugLogging")),
            terminate: f(sym("fmi2Terminate")),
            setup_experiment: f(sym("fmi2SetupExperiment")),
            enter_init: f(sym("fmi2EnterInitializationMode")),
            exit_init: f(sym("fmi2ExitInitializationMode")),
            get_real: f(sym("fmi2GetReal")),
            set_real: f(sym("fmi2SetReal")),
            set_integer: f(sym("fmi2SetInteger")),
            do_step: f(sym("fmi2DoStep")),
            get_real_status: f(sym("fmi2GetRealStatus")),
            get_status: f(sym("fmi2GetStatus")),
            get_state: f(sym("fmi2GetFMUstate")),
            set_state: f(sym("fmi2SetFMUstate")),
            free_state: f(sym("fmi2FreeFMUstate")),
            state_size: f(sym("fmi2SerializedFMUstateSize")),
            serialize: f(sym("fmi2SerializeFMUstate")),
            deserialize: f(sym("fmi2DeSerializeFMUstate")),
            cancel_step: f(sym("fmi2CancelStep")),
            directional_derivative: f(sym("fmi2GetDirectionalDerivative")),
        }
    }
}

fn vr(name: &str) -> c_uint {
    by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

/// One instance with its own log.
struct Instance<'a> {
    fmi: &'a Fmi,
    c: Component,
    log: Box<Log>,
}

/// Small enough to keep the test quick (as in the FMPy tests).
const SHORT: &[(&str, i32)] = &[("belt.nBodies", 100), ("probe.body", 1)];

impl<'a> Instance<'a> {
    fn try_new(fmi: &'a Fmi, guid: &str, fmu_type: c_int) -> (Component, Box<Log>) {
        let log = Box::new(Log::default());
        let cb = Callbacks {
            logger: Some(logger),
            allocate_memory: ptr::null(),
            free_memory: ptr::null(),
            step_finished: ptr::null(),
            component_environment: &*log as *const Log as *mut c_void,
        };
        let guid = CString::new(guid).unwrap();
        // SAFETY: valid arguments; `cb` may go away after the call.
        let c = unsafe {
            (fmi.instantiate)(
                c"abi".as_ptr(),
                fmu_type,
                guid.as_ptr(),
                ptr::null(),
                &cb,
                0,
                0,
            )
        };
        (c, log)
    }

    fn new(fmi: &'a Fmi) -> Self {
        let (c, log) = Self::try_new(fmi, GUID, CO_SIMULATION);
        assert!(!c.is_null(), "instantiate failed: {:?}", log.borrow());
        Instance { fmi, c, log }
    }

    /// Instantiated, parameters set, initialized at t = 0.
    fn initialized(fmi: &'a Fmi, reals: &[(&str, f64)]) -> Self {
        let i = Self::new(fmi);
        for (name, x) in SHORT {
            assert_eq!(i.set_integer(name, *x), OK);
        }
        for (name, x) in reals {
            assert_eq!(i.set_real(name, *x), OK);
        }
        // SAFETY (here and below): live instance, valid pointers.
        unsafe {
            assert_eq!((fmi.setup_experiment)(i.c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!((fmi.enter_init)(i.c), OK);
            assert_eq!((fmi.exit_init)(i.c), OK, "{:?}", i.log.borrow());
        }
        i
    }

    fn set_real(&self, name: &str, x: f64) -> c_int {
        unsafe { (self.fmi.set_real)(self.c, &vr(name), 1, &x) }
    }

    fn set_integer(&self, name: &str, x: i32) -> c_int {
        unsafe { (self.fmi.set_integer)(self.c, &vr(name), 1, &x) }
    }

    fn get(&self, names: &[&str]) -> Vec<f64> {
        let vrs: Vec<c_uint> = names.iter().map(|n| vr(n)).collect();
        let mut out = vec![f64::NAN; names.len()];
        let s = unsafe { (self.fmi.get_real)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        assert_eq!(s, OK, "{:?}", self.log.borrow());
        out
    }

    fn step(&self, t: f64, h: f64) -> c_int {
        unsafe { (self.fmi.do_step)(self.c, t, h, 0) }
    }

    /// The call returned fmi2Error and a log line with status fmi2Error
    /// containing `needle` arrived.
    fn assert_refused(&self, status: c_int, needle: &str) {
        assert_eq!(status, ERROR, "{:?}", self.log.borrow());
        let log = self.log.borrow();
        assert!(
            log.iter()
                .any(|(s, c, m)| *s == ERROR && c == "logStatusError" && m.contains(needle)),
            "no error log line containing {needle:?}: {log:?}"
        );
    }

    fn get_state(&self) -> State {
        let mut s: State = ptr::null_mut();
        assert_eq!(unsafe { (self.fmi.get_state)(self.c, &mut s) }, OK);
        assert!(!s.is_null());
        s
    }

    fn serialize(&self, s: State) -> Vec<u8> {
        let mut size = 0;
        assert_eq!(unsafe { (self.fmi.state_size)(self.c, s, &mut size) }, OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            unsafe { (self.fmi.serialize)(self.c, s, bytes.as_mut_ptr().cast(), size) },
            OK
        );
        bytes
    }

    fn deserialize(&self, bytes: &[u8]) -> (c_int, State) {
        let mut s: State = ptr::null_mut();
        let status =
            unsafe { (self.fmi.deserialize)(self.c, bytes.as_ptr().cast(), bytes.len(), &mut s) };
        (status, s)
    }
}

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        unsafe { (self.fmi.free_instance)(self.c) };
    }
}

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
        unsafe { libc::dlsym(fmi._handle, c.as_ptr()) }
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
