//! Shared by the tests that drive the built FMU binary through its C ABI:
//! `dlopen` the cdylib that cargo builds next to the test executable
//! (`target/<profile>/libbelt_drive.so`), look up every `fmi2...` symbol and
//! call it like an importer would. Also: an instance wrapper that records its
//! log, a small seeded PRNG for the fuzz tests, and the small fast drive the
//! reliability tests use.
//!
//! The logger here is a plain (non-variadic) `extern "C"` function: the FMU
//! always calls its logger with the finished message as the format string
//! (every `%` doubled) and no variadic arguments, so the fixed arguments are
//! passed exactly as for a non-variadic call and `message` can be read as is.
#![allow(dead_code)] // each test file uses a part of this module

use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::path::PathBuf;
use std::ptr;

use belt_drive::fmu::variables::{by_name, GUID};

pub const OK: c_int = 0;
pub const WARNING: c_int = 1;
pub const DISCARD: c_int = 2;
pub const ERROR: c_int = 3;
pub const FATAL: c_int = 4;
pub const PENDING: c_int = 5;
pub const CO_SIMULATION: c_int = 1;
pub const MODEL_EXCHANGE: c_int = 0;
pub const DO_STEP_STATUS: c_int = 0;
pub const PENDING_STATUS: c_int = 1;
pub const LAST_SUCCESSFUL_TIME: c_int = 2;
pub const TERMINATED: c_int = 3;

pub type Component = *mut c_void;
pub type State = *mut c_void;
pub type Logger =
    unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

#[repr(C)]
pub struct Callbacks {
    pub logger: Option<Logger>,
    pub allocate_memory: *const c_void,
    pub free_memory: *const c_void,
    pub step_finished: *const c_void,
    pub component_environment: *mut c_void,
}

/// (status, category, message) of each logger call.
pub type Log = RefCell<Vec<(c_int, String, String)>>;

pub unsafe extern "C" fn logger(
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

type Vrs = *const c_uint;

/// The library and every Co-Simulation function of FMI 2.0.
pub struct Fmi {
    pub handle: *mut c_void,
    pub get_types_platform: unsafe extern "C" fn() -> *const c_char,
    pub get_version: unsafe extern "C" fn() -> *const c_char,
    pub set_debug_logging:
        unsafe extern "C" fn(Component, c_int, usize, *const *const c_char) -> c_int,
    pub instantiate: unsafe extern "C" fn(
        *const c_char,
        c_int,
        *const c_char,
        *const c_char,
        *const Callbacks,
        c_int,
        c_int,
    ) -> Component,
    pub free_instance: unsafe extern "C" fn(Component),
    pub setup_experiment: unsafe extern "C" fn(Component, c_int, f64, f64, c_int, f64) -> c_int,
    pub enter_init: unsafe extern "C" fn(Component) -> c_int,
    pub exit_init: unsafe extern "C" fn(Component) -> c_int,
    pub terminate: unsafe extern "C" fn(Component) -> c_int,
    pub reset: unsafe extern "C" fn(Component) -> c_int,
    pub get_real: unsafe extern "C" fn(Component, Vrs, usize, *mut f64) -> c_int,
    pub get_integer: unsafe extern "C" fn(Component, Vrs, usize, *mut c_int) -> c_int,
    pub get_boolean: unsafe extern "C" fn(Component, Vrs, usize, *mut c_int) -> c_int,
    pub get_string: unsafe extern "C" fn(Component, Vrs, usize, *mut *const c_char) -> c_int,
    pub set_real: unsafe extern "C" fn(Component, Vrs, usize, *const f64) -> c_int,
    pub set_integer: unsafe extern "C" fn(Component, Vrs, usize, *const c_int) -> c_int,
    pub set_boolean: unsafe extern "C" fn(Component, Vrs, usize, *const c_int) -> c_int,
    pub set_string: unsafe extern "C" fn(Component, Vrs, usize, *const *const c_char) -> c_int,
    pub get_state: unsafe extern "C" fn(Component, *mut State) -> c_int,
    pub set_state: unsafe extern "C" fn(Component, State) -> c_int,
    pub free_state: unsafe extern "C" fn(Component, *mut State) -> c_int,
    pub state_size: unsafe extern "C" fn(Component, State, *mut usize) -> c_int,
    pub serialize: unsafe extern "C" fn(Component, State, *mut c_char, usize) -> c_int,
    pub deserialize: unsafe extern "C" fn(Component, *const c_char, usize, *mut State) -> c_int,
    pub directional_derivative:
        unsafe extern "C" fn(Component, Vrs, usize, Vrs, usize, *const f64, *mut f64) -> c_int,
    pub set_input_derivatives:
        unsafe extern "C" fn(Component, Vrs, usize, *const c_int, *const f64) -> c_int,
    pub get_output_derivatives:
        unsafe extern "C" fn(Component, Vrs, usize, *const c_int, *mut f64) -> c_int,
    pub do_step: unsafe extern "C" fn(Component, f64, f64, c_int) -> c_int,
    pub cancel_step: unsafe extern "C" fn(Component) -> c_int,
    pub get_status: unsafe extern "C" fn(Component, c_int, *mut c_int) -> c_int,
    pub get_real_status: unsafe extern "C" fn(Component, c_int, *mut f64) -> c_int,
    pub get_integer_status: unsafe extern "C" fn(Component, c_int, *mut c_int) -> c_int,
    pub get_boolean_status: unsafe extern "C" fn(Component, c_int, *mut c_int) -> c_int,
    pub get_string_status: unsafe extern "C" fn(Component, c_int, *mut *const c_char) -> c_int,
}

// SAFETY: the handle is only used for dlsym; the functions are plain C
// functions the FMU allows to be called from any thread (one thread per
// instance at a time).
unsafe impl Send for Fmi {}
unsafe impl Sync for Fmi {}

pub fn library_path() -> PathBuf {
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
pub const CS_FUNCTIONS: &[&str] = &[
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
    pub fn load() -> Fmi {
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
            handle,
            get_types_platform: f(sym("fmi2GetTypesPlatform")),
            get_version: f(sym("fmi2GetVersion")),
            set_debug_logging: f(sym("fmi2SetDebugLogging")),
            instantiate: f(sym("fmi2Instantiate")),
            free_instance: f(sym("fmi2FreeInstance")),
            setup_experiment: f(sym("fmi2SetupExperiment")),
            enter_init: f(sym("fmi2EnterInitializationMode")),
            exit_init: f(sym("fmi2ExitInitializationMode")),
            terminate: f(sym("fmi2Terminate")),
            reset: f(sym("fmi2Reset")),
            get_real: f(sym("fmi2GetReal")),
            get_integer: f(sym("fmi2GetInteger")),
            get_boolean: f(sym("fmi2GetBoolean")),
            get_string: f(sym("fmi2GetString")),
            set_real: f(sym("fmi2SetReal")),
            set_integer: f(sym("fmi2SetInteger")),
            set_boolean: f(sym("fmi2SetBoolean")),
            set_string: f(sym("fmi2SetString")),
            get_state: f(sym("fmi2GetFMUstate")),
            set_state: f(sym("fmi2SetFMUstate")),
            free_state: f(sym("fmi2FreeFMUstate")),
            state_size: f(sym("fmi2SerializedFMUstateSize")),
            serialize: f(sym("fmi2SerializeFMUstate")),
            deserialize: f(sym("fmi2DeSerializeFMUstate")),
            directional_derivative: f(sym("fmi2GetDirectionalDerivative")),
            set_input_derivatives: f(sym("fmi2SetRealInputDerivatives")),
            get_output_derivatives: f(sym("fmi2GetRealOutputDerivatives")),
            do_step: f(sym("fmi2DoStep")),
            cancel_step: f(sym("fmi2CancelStep")),
            get_status: f(sym("fmi2GetStatus")),
            get_real_status: f(sym("fmi2GetRealStatus")),
            get_integer_status: f(sym("fmi2GetIntegerStatus")),
            get_boolean_status: f(sym("fmi2GetBooleanStatus")),
            get_string_status: f(sym("fmi2GetStringStatus")),
        }
    }
}

/// The parameters of `parameters/<file>` (an .ssv file) as written.
pub fn ssv(file: &str) -> Vec<model_description::ssv::Parameter> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("parameters")
        .join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    model_description::ssv::read(&text).unwrap()
}

pub fn vr(name: &str) -> c_uint {
    by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

/// Small enough to keep the ABI tests quick (as in the FMPy tests).
pub const SHORT: &[(&str, i32)] = &[("belt.nBodies", 100), ("probe.body", 1)];

/// A fast drive for the reliability tests: 40 bodies on two 50 mm pulleys
/// 0.25 m apart, 300 N preload (the physics tests' `small_drive`), pulley 1
/// driven by the built-in -2 N m torque ramp, pulley 2 loaded by damping.
pub const FAST_INTS: &[(&str, i32)] = &[("belt.nBodies", 40), ("probe.body", 1)];
pub const FAST_REALS: &[(&str, f64)] = &[
    ("belt.preload", 300.0),
    ("pulley[1].radius", 0.05),
    ("pulley[2].radius", 0.05),
    ("pulley[2].x", 0.25),
    ("pulley[1].torqueRamp", -2.0),
    ("pulley[1].rampTime", 0.01),
    ("pulley[2].loadDamping", 0.05),
];

/// One instance with its own log.
pub struct Instance<'a> {
    pub fmi: &'a Fmi,
    pub c: Component,
    pub log: Box<Log>,
}

impl<'a> Instance<'a> {
    pub fn try_new(fmi: &'a Fmi, guid: &str, fmu_type: c_int) -> (Component, Box<Log>) {
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

    pub fn new(fmi: &'a Fmi) -> Self {
        let (c, log) = Self::try_new(fmi, GUID, CO_SIMULATION);
        assert!(!c.is_null(), "instantiate failed: {:?}", log.borrow());
        Instance { fmi, c, log }
    }

    /// Instantiated, the `SHORT` integers and `reals` set, initialized at t = 0.
    pub fn initialized(fmi: &'a Fmi, reals: &[(&str, f64)]) -> Self {
        Self::initialized_with(fmi, SHORT, reals)
    }

    /// The fast drive (`FAST_INTS`, `FAST_REALS`) with `reals` on top,
    /// initialized at t = 0.
    pub fn fast(fmi: &'a Fmi, reals: &[(&str, f64)]) -> Self {
        let all: Vec<(&str, f64)> = FAST_REALS.iter().chain(reals).copied().collect();
        Self::initialized_with(fmi, FAST_INTS, &all)
    }

    pub fn initialized_with(fmi: &'a Fmi, ints: &[(&str, i32)], reals: &[(&str, f64)]) -> Self {
        let i = Self::new(fmi);
        for (name, x) in ints {
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

    /// fmi2SetDebugLogging(true, categories): exactly these categories on.
    pub fn log_categories(&self, categories: &[&str]) {
        let names: Vec<CString> = categories
            .iter()
            .map(|c| CString::new(*c).unwrap())
            .collect();
        let ptrs: Vec<*const c_char> = names.iter().map(|c| c.as_ptr()).collect();
        let s = unsafe { (self.fmi.set_debug_logging)(self.c, 1, ptrs.len(), ptrs.as_ptr()) };
        assert_eq!(s, OK, "{:?}", self.log.borrow());
    }

    pub fn set_real(&self, name: &str, x: f64) -> c_int {
        unsafe { (self.fmi.set_real)(self.c, &vr(name), 1, &x) }
    }

    pub fn set_integer(&self, name: &str, x: i32) -> c_int {
        unsafe { (self.fmi.set_integer)(self.c, &vr(name), 1, &x) }
    }

    pub fn set_boolean(&self, name: &str, x: bool) -> c_int {
        let b = c_int::from(x);
        unsafe { (self.fmi.set_boolean)(self.c, &vr(name), 1, &b) }
    }

    /// Sets every parameter of `parameters/<file>` as an importer reads
    /// it from the file, each of which must be accepted.
    pub fn set_ssv(&self, file: &str) {
        for p in ssv(file) {
            let s = match p.ty.as_str() {
                "Real" => self.set_real(&p.name, p.value.parse().unwrap()),
                "Integer" => self.set_integer(&p.name, p.value.parse().unwrap()),
                "Boolean" => self.set_boolean(&p.name, p.value == "true" || p.value == "1"),
                t => panic!("{}: type {t}", p.name),
            };
            assert_eq!(s, OK, "{} = {}: {:?}", p.name, p.value, self.log.borrow());
        }
    }

    /// `fmi2SetupExperiment` at t = 0, `fmi2EnterInitializationMode` and
    /// `fmi2ExitInitializationMode`, each of which must succeed.
    pub fn initialize(&self) {
        // SAFETY: live instance.
        unsafe {
            assert_eq!((self.fmi.setup_experiment)(self.c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!((self.fmi.enter_init)(self.c), OK);
            assert_eq!((self.fmi.exit_init)(self.c), OK, "{:?}", self.log.borrow());
        }
    }

    /// `fmi2GetReal` of `names`, which must succeed.
    pub fn get(&self, names: &[&str]) -> Vec<f64> {
        let vrs: Vec<c_uint> = names.iter().map(|n| vr(n)).collect();
        let mut out = vec![f64::NAN; names.len()];
        let s = unsafe { (self.fmi.get_real)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        assert_eq!(s, OK, "{:?}", self.log.borrow());
        out
    }

    pub fn step(&self, t: f64, h: f64) -> c_int {
        unsafe { (self.fmi.do_step)(self.c, t, h, 0) }
    }

    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`: (status, time).
    pub fn last_successful_time(&self) -> (c_int, f64) {
        let mut t = f64::NAN;
        let s = unsafe { (self.fmi.get_real_status)(self.c, LAST_SUCCESSFUL_TIME, &mut t) };
        (s, t)
    }

    /// Whether a log line with this status contains `needle`.
    pub fn logged(&self, status: c_int, needle: &str) -> bool {
        self.log
            .borrow()
            .iter()
            .any(|(s, _, m)| *s == status && m.contains(needle))
    }

    /// The call returned fmi2Error and a log line with status fmi2Error
    /// containing `needle` arrived.
    pub fn assert_refused(&self, status: c_int, needle: &str) {
        assert_eq!(status, ERROR, "{:?}", self.log.borrow());
        let log = self.log.borrow();
        assert!(
            log.iter()
                .any(|(s, c, m)| *s == ERROR && c == "logStatusError" && m.contains(needle)),
            "no error log line containing {needle:?}: {log:?}"
        );
    }

    pub fn get_state(&self) -> State {
        let mut s: State = ptr::null_mut();
        assert_eq!(unsafe { (self.fmi.get_state)(self.c, &mut s) }, OK);
        assert!(!s.is_null());
        s
    }

    pub fn free_state(&self, mut s: State) {
        assert_eq!(unsafe { (self.fmi.free_state)(self.c, &mut s) }, OK);
    }

    pub fn serialize(&self, s: State) -> Vec<u8> {
        let mut size = 0;
        assert_eq!(unsafe { (self.fmi.state_size)(self.c, s, &mut size) }, OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            unsafe { (self.fmi.serialize)(self.c, s, bytes.as_mut_ptr().cast(), size) },
            OK
        );
        bytes
    }

    pub fn deserialize(&self, bytes: &[u8]) -> (c_int, State) {
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

/// SplitMix64: a small, seeded, reproducible generator (no crate needed).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    pub fn pick<'t, T>(&mut self, items: &'t [T]) -> &'t T {
        &items[self.below(items.len())]
    }
}

/// Iterations from the environment variable `var` (long runs), else `default`
/// (the bounded CI run).
pub fn iterations(var: &str, default: usize) -> usize {
    std::env::var(var)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// Seed from `BELT_FUZZ_SEED`, else the fixed CI seed.
pub fn seed(default: u64) -> u64 {
    std::env::var("BELT_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}
