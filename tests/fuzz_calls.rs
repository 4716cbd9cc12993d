//! Call-sequence fuzzing through the C ABI: random sequences of FMI 2.0 calls
//! with random arguments (NULL pointers, unknown and mistyped value
//! references, lengths that overflow, wrong buffer sizes, foreign FMU-state
//! pointers, NaN and infinite reals) on the built library.
//!
//! The oracle is an independent copy of the Co-Simulation state table of
//! FMI 2.0 section 4.2.4 and of the variable rules. After every call:
//! * the status is fmi2OK, fmi2Warning, fmi2Discard or fmi2Error (never
//!   fmi2Fatal or fmi2Pending; the process is still alive);
//! * a call the table forbids in the current state returns fmi2Error with a
//!   log line naming the function and "illegal call sequence";
//! * every fmi2Error comes with a log line of status fmi2Error that starts
//!   with the function name; no message mentions a Rust panic;
//! * fmi2Set* returns fmi2Error exactly when a value reference is unknown,
//!   of another type, not settable, or set in a state where it is fixed;
//! * nothing is written past `nvr` elements of an output buffer;
//! * fmi2GetRealStatus(fmi2LastSuccessfulTime) equals the time the oracle
//!   tracks (advanced by successful fmi2DoStep, restored by fmi2SetFMUstate).
//!
//! Bounded run in CI (fixed seed); long runs: `BELT_FUZZ_ITERS=<sequences>`
//! (and `BELT_FUZZ_SEED=<seed>`), e.g.
//! `BELT_FUZZ_ITERS=20000 cargo test --release --test fuzz_calls -- --nocapture`.
#![cfg(unix)]

mod abi;

use std::ffi::{c_char, c_int, c_uint, c_void, CString};
use std::ptr;

use abi::*;
use belt_drive::fmu::variables::{Causality, VarInfo, VarType, Variability, GUID, VARIABLES};

/// CI: sequences and calls per sequence.
const CI_SEQUENCES: usize = 300;
const CALLS_PER_SEQUENCE: usize = 60;
const CI_SEED: u64 = 0x6265_6c74_6675_7a7a;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Instantiated,
    Initialization,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
}
use Mode::*;

/// The FMI 2.0 Co-Simulation state table (section 4.2.4), without the
/// StepInProgress / StepCanceled columns (no asynchronous steps).
fn allowed(function: &str, m: Mode) -> bool {
    match function {
        "fmi2SetDebugLogging"
        | "fmi2Reset"
        | "fmi2GetFMUstate"
        | "fmi2SetFMUstate"
        | "fmi2FreeFMUstate"
        | "fmi2SerializedFMUstateSize"
        | "fmi2SerializeFMUstate"
        | "fmi2DeSerializeFMUstate" => true,
        "fmi2SetupExperiment" | "fmi2EnterInitializationMode" => m == Instantiated,
        "fmi2ExitInitializationMode" => m == Initialization,
        "fmi2Terminate" => matches!(m, StepComplete | StepFailed),
        "fmi2GetReal"
        | "fmi2GetInteger"
        | "fmi2GetBoolean"
        | "fmi2GetString"
        | "fmi2GetDirectionalDerivative" => m != Instantiated,
        "fmi2SetReal"
        | "fmi2SetInteger"
        | "fmi2SetBoolean"
        | "fmi2SetString"
        | "fmi2SetRealInputDerivatives" => {
            matches!(m, Instantiated | Initialization | StepComplete)
        }
        "fmi2GetRealOutputDerivatives" => {
            matches!(m, StepComplete | StepFailed | Terminated | Error)
        }
        "fmi2DoStep" => m == StepComplete,
        "fmi2CancelStep" => false,
        "fmi2GetStatus"
        | "fmi2GetRealStatus"
        | "fmi2GetIntegerStatus"
        | "fmi2GetBooleanStatus"
        | "fmi2GetStringStatus" => {
            matches!(m, StepComplete | StepFailed | Terminated)
        }
        other => panic!("no table row for {other}"),
    }
}

/// Whether fmi2Set<ty> of `vr` must be refused in mode `m` (for values
/// that pass the set-time checks).
fn set_refused(ty: VarType, vr: c_uint, m: Mode) -> bool {
    let Some(v) = VARIABLES.iter().find(|v| v.vr == vr) else {
        return true;
    };
    if v.ty != ty || v.variability == Variability::Constant {
        return true;
    }
    match v.causality {
        Causality::Input => false,
        Causality::Parameter => m == StepComplete && v.variability != Variability::Tunable,
        _ => true,
    }
}

/// One FMU state the fuzzer holds, with the oracle's view of it.
struct Held {
    s: *mut c_void,
    mode: Mode,
    time: f64,
}

/// A serialized state and the oracle's view of it.
struct Blob {
    bytes: Vec<u8>,
    mode: Mode,
    time: f64,
}

struct Fuzzer<'a> {
    fmi: &'a Fmi,
    rng: Rng,
    inst: Instance<'a>,
    mode: Mode,
    time: f64,
    stop: Option<f64>,
    states: Vec<Held>,
    blobs: Vec<Blob>,
    /// Zeroed memory passed as a "foreign" fmi2FMUstate.
    foreign: Vec<u64>,
    calls: usize,
    statuses: [usize; 6],
    illegal: usize,
}

const CATEGORIES: &[&str] = &[
    "logEvents",
    "logStatusWarning",
    "logStatusDiscard",
    "logStatusError",
    "logStatusFatal",
    "logAll",
    "logBogus",
];

impl<'a> Fuzzer<'a> {
    fn new(fmi: &'a Fmi, seed: u64) -> Self {
        Fuzzer {
            fmi,
            rng: Rng::new(seed),
            inst: Instance::new(fmi),
            mode: Instantiated,
            time: 0.0,
            stop: None,
            states: Vec::new(),
            blobs: Vec::new(),
            foreign: vec![0; 4096],
            calls: 0,
            statuses: [0; 6],
            illegal: 0,
        }
    }

    fn c(&self) -> *mut c_void {
        self.inst.c
    }

    // -- random arguments ---------------------------------------------------

    /// A variable of type `ty`, or any variable if there is none (String).
    fn var_of(&mut self, ty: VarType) -> &'static VarInfo {
        let of_type: Vec<&VarInfo> = VARIABLES.iter().filter(|v| v.ty == ty).collect();
        if of_type.is_empty() {
            return self.rng.pick(VARIABLES);
        }
        of_type[self.rng.below(of_type.len())]
    }

    /// A value reference: mostly of type `ty`, sometimes of another type,
    /// unknown, or extreme.
    fn vr(&mut self, ty: VarType) -> c_uint {
        match self.rng.below(20) {
            0 => self.rng.next_u64() as c_uint,
            1 => *self.rng.pick(&[0, 9, 27, 99, 999_999, c_uint::MAX]),
            2 | 3 => self.rng.pick(VARIABLES).vr,
            _ => self.var_of(ty).vr,
        }
    }

    fn vrs(&mut self, ty: VarType) -> Vec<c_uint> {
        let n = *self.rng.pick(&[0, 1, 1, 1, 2, 3, 5]);
        (0..n).map(|_| self.vr(ty)).collect()
    }

    /// A real for variable `vr`: near its start value for parameters (so a
    /// valid set stays cheap to simulate), anything for inputs, sometimes
    /// non-finite or extreme.
    fn real_for(&mut self, vr: c_uint) -> f64 {
        if self.rng.chance(0.1) {
            return *self
                .rng
                .pick(&[f64::NAN, f64::INFINITY, -f64::INFINITY, -1.0, 0.0, 1e300]);
        }
        let start = VARIABLES
            .iter()
            .find(|v| v.vr == vr)
            .and_then(|v| match v.start {
                belt_drive::fmu::variables::Start::Real(x) => Some((x, v.causality)),
                _ => None,
            });
        match start {
            Some((_, Causality::Input)) => 20.0 * (self.rng.unit() - 0.5),
            Some((x, _)) => x * (0.7 + 0.6 * self.rng.unit()),
            None => self.rng.unit(),
        }
    }

    fn int_for(&mut self, vr: c_uint) -> c_int {
        if vr == abi::vr("belt.nBodies") {
            return *self.rng.pick(&[3, 10, 20, 40, 0, -1, 100_000, c_int::MAX]);
        }
        if vr == abi::vr("solver.maxSteps") {
            return *self.rng.pick(&[1, 10, 100_000, 0, -5]);
        }
        match self.rng.below(6) {
            0 => *self.rng.pick(&[0, -1, c_int::MIN, c_int::MAX]),
            _ => 1 + self.rng.below(3) as c_int,
        }
    }

    /// Set the fast drive (as an importer configures an instance) and
    /// switch on the discard messages.
    fn baseline(&mut self) {
        self.inst.log_categories(&["logStatusDiscard"]);
        for (name, x) in FAST_INTS {
            self.inst.set_integer(name, *x);
        }
        for (name, x) in FAST_REALS {
            self.inst.set_real(name, *x);
        }
        self.calls += FAST_INTS.len() + FAST_REALS.len();
    }

    // -- the oracle -----------------------------------------------------------

    /// Check the outcome of one call of `function` and update the oracle.
    /// `well_formed`: the pointer and length arguments are valid, so an
    /// illegal call must be refused for its state. Returns the status.
    fn check(
        &mut self,
        function: &str,
        status: c_int,
        log_from: usize,
        well_formed: bool,
    ) -> c_int {
        self.calls += 1;
        assert!(
            matches!(status, OK | WARNING | DISCARD | ERROR),
            "{function} returned status {status}"
        );
        self.statuses[status as usize] += 1;
        let log = self.inst.log.borrow();
        let new = &log[log_from.min(log.len())..];
        for (_, _, m) in new {
            assert!(!m.contains("panic"), "{function}: {m}");
        }
        let legal = allowed(function, self.mode);
        if !legal {
            self.illegal += 1;
            assert_eq!(
                status, ERROR,
                "{function} in state {:?}: {new:?}",
                self.mode
            );
            if well_formed {
                assert!(
                    new.iter().any(|(s, _, m)| *s == ERROR
                        && m.starts_with(function)
                        && m.contains("illegal call sequence")),
                    "{function} in state {:?} refused without naming the rule: {new:?}",
                    self.mode
                );
            }
        }
        if status == ERROR {
            assert!(
                new.iter().any(|(s, c, m)| *s == ERROR
                    && c == "logStatusError"
                    && m.starts_with(function)),
                "{function} returned fmi2Error without an error log line: {new:?}"
            );
            self.mode = Error;
        }
        status
    }

    fn log_len(&self) -> usize {
        self.inst.log.borrow().len()
    }

    // -- the calls ------------------------------------------------------------

    fn step(&mut self) {
        // An importer recovers from fmi2Error with fmi2Reset or by going
        // back to a saved state; do that often so sequences go on.
        if self.mode == Error && self.rng.chance(0.5) {
            let n0 = self.log_len();
            if !self.states.is_empty() && self.rng.chance(0.5) {
                let k = self.rng.below(self.states.len());
                let s = unsafe { (self.fmi.set_state)(self.c(), self.states[k].s) };
                assert_eq!(self.check("fmi2SetFMUstate", s, n0, true), OK);
                (self.mode, self.time) = (self.states[k].mode, self.states[k].time);
            } else {
                let s = unsafe { (self.fmi.reset)(self.c()) };
                assert_eq!(self.check("fmi2Reset", s, n0, true), OK);
                (self.mode, self.time, self.stop) = (Instantiated, 0.0, None);
                self.baseline();
            }
            return;
        }
        let op = self.rng.below(36);
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        match op {
            0 => {
                let on = self.rng.below(2) as c_int;
                let names: Vec<CString> = (0..self.rng.below(3))
                    .map(|_| CString::new(*self.rng.pick(CATEGORIES)).unwrap())
                    .collect();
                let mut ptrs: Vec<*const c_char> = names.iter().map(|s| s.as_ptr()).collect();
                let null_entry = self.rng.chance(0.1) && !ptrs.is_empty();
                if null_entry {
                    ptrs[0] = ptr::null();
                }
                let null_array = self.rng.chance(0.1) && !ptrs.is_empty();
                let p = if null_array {
                    ptr::null()
                } else {
                    ptrs.as_ptr()
                };
                let s = unsafe { (fmi.set_debug_logging)(c, on, ptrs.len(), p) };
                self.check("fmi2SetDebugLogging", s, n0, !null_array && !null_entry);
            }
            1 => {
                let tol_def = self.rng.below(2) as c_int;
                let tol = *self.rng.pick(&[1e-4, 1e-3, 0.0, -1.0, f64::NAN]);
                let start = *self
                    .rng
                    .pick(&[0.0, 0.0, 0.0, 1.5, -2.0, f64::NAN, f64::INFINITY]);
                let stop_def = self.rng.below(2) as c_int;
                let stop = start + *self.rng.pick(&[1e-3, 1.0, -1.0, f64::NAN]);
                let s = unsafe { (fmi.setup_experiment)(c, tol_def, tol, start, stop_def, stop) };
                if self.check("fmi2SetupExperiment", s, n0, true) == OK {
                    self.time = start;
                    self.stop = (stop_def != 0).then_some(stop);
                }
            }
            2 | 3 => {
                let s = unsafe { (fmi.enter_init)(c) };
                if self.check("fmi2EnterInitializationMode", s, n0, true) == OK {
                    self.mode = Initialization;
                }
            }
            4 | 5 => {
                let s = unsafe { (fmi.exit_init)(c) };
                if self.check("fmi2ExitInitializationMode", s, n0, true) == OK {
                    self.mode = StepComplete;
                }
            }
            6 => {
                let s = unsafe { (fmi.terminate)(c) };
                if self.check("fmi2Terminate", s, n0, true) == OK {
                    self.mode = Terminated;
                }
            }
            7 => {
                let s = unsafe { (fmi.reset)(c) };
                if self.check("fmi2Reset", s, n0, true) == OK {
                    self.mode = Instantiated;
                    self.time = 0.0;
                    self.stop = None;
                    if self.rng.chance(0.8) {
                        self.baseline();
                    }
                }
            }
            8..=11 => self.get_values(op - 8),
            12..=15 => self.set_values(op - 12),
            16 | 17 => self.get_state(),
            18 => self.set_state(),
            19 => self.free_state(),
            20 => self.serialize(),
            21 => self.deserialize(),
            22 => {
                let s = unsafe {
                    (fmi.directional_derivative)(
                        c,
                        ptr::null(),
                        0,
                        ptr::null(),
                        0,
                        ptr::null(),
                        ptr::null_mut(),
                    )
                };
                self.check("fmi2GetDirectionalDerivative", s, n0, true);
                assert_eq!(s, ERROR, "providesDirectionalDerivative=false");
            }
            23 | 24 => self.derivatives(op == 23),
            25..=28 => self.do_step(),
            29 => {
                let s = unsafe { (fmi.cancel_step)(c) };
                self.check("fmi2CancelStep", s, n0, true);
            }
            30..=32 => self.status(),
            33 => self.null_instance(),
            34 => self.reinstantiate(),
            _ => {
                if self.mode == Instantiated {
                    self.baseline();
                }
            }
        }
    }

    fn get_values(&mut self, which: usize) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let ty = [
            VarType::Real,
            VarType::Integer,
            VarType::Boolean,
            VarType::String,
        ][which];
        let vrs = self.vrs(ty);
        let n = vrs.len();
        let null_vr = n > 0 && self.rng.chance(0.05);
        let null_val = n > 0 && self.rng.chance(0.05);
        // Lengths that overflow the byte count are refused before any read.
        let huge = self.rng.chance(0.03);
        let nvr = if huge { usize::MAX / 2 } else { n };
        let vp = if null_vr { ptr::null() } else { vrs.as_ptr() };
        let wf = !null_vr && !null_val && !huge;
        // 8-byte aligned storage for n elements of up to 8 bytes, plus canaries.
        let mut buf = vec![u64::from_ne_bytes([0x5a; 8]); n + 2];
        let out = if null_val {
            ptr::null_mut()
        } else {
            buf.as_mut_ptr()
        };
        let size = [8, 4, 4, 8][which];
        let (name, s) = unsafe {
            match which {
                0 => ("fmi2GetReal", (fmi.get_real)(c, vp, nvr, out.cast())),
                1 => ("fmi2GetInteger", (fmi.get_integer)(c, vp, nvr, out.cast())),
                2 => ("fmi2GetBoolean", (fmi.get_boolean)(c, vp, nvr, out.cast())),
                _ => ("fmi2GetString", (fmi.get_string)(c, vp, nvr, out.cast())),
            }
        };
        // SAFETY: reading our own initialised buffer as bytes.
        let bytes = unsafe { std::slice::from_raw_parts(buf.as_ptr().cast::<u8>(), buf.len() * 8) };
        assert!(
            bytes[n * size..].iter().all(|&b| b == 0x5a),
            "{name} wrote past nvr = {n}"
        );
        let unknown = vrs
            .iter()
            .any(|&r| !VARIABLES.iter().any(|v| v.vr == r && v.ty == ty));
        let s = self.check(name, s, n0, wf);
        if wf && allowed(name, self.mode) && unknown {
            assert_eq!(s, ERROR, "{name} of {vrs:?} must be refused");
        }
    }

    fn set_values(&mut self, which: usize) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let ty = [
            VarType::Real,
            VarType::Integer,
            VarType::Boolean,
            VarType::String,
        ][which];
        let vrs = self.vrs(ty);
        let n = vrs.len();
        let null_vr = n > 0 && self.rng.chance(0.05);
        let null_val = n > 0 && self.rng.chance(0.05);
        let huge = self.rng.chance(0.03);
        let nvr = if huge { usize::MAX / 2 } else { n };
        let vp = if null_vr { ptr::null() } else { vrs.as_ptr() };
        let mut wf = !null_vr && !null_val && !huge;
        let mode = self.mode;
        let mut expect_error = vrs.iter().any(|&r| set_refused(ty, r, mode));
        let (name, s) = match which {
            0 => {
                let vals: Vec<f64> = vrs.iter().map(|&r| self.real_for(r)).collect();
                // Inputs must be finite (checked at set time).
                expect_error |= vrs.iter().zip(&vals).any(|(&r, x)| {
                    !x.is_finite()
                        && VARIABLES
                            .iter()
                            .any(|v| v.vr == r && v.causality == Causality::Input)
                });
                let p = if null_val { ptr::null() } else { vals.as_ptr() };
                ("fmi2SetReal", unsafe { (fmi.set_real)(c, vp, nvr, p) })
            }
            1 => {
                let vals: Vec<c_int> = vrs.iter().map(|&r| self.int_for(r)).collect();
                let p = if null_val { ptr::null() } else { vals.as_ptr() };
                ("fmi2SetInteger", unsafe {
                    (fmi.set_integer)(c, vp, nvr, p)
                })
            }
            2 => {
                let vals: Vec<c_int> = vrs
                    .iter()
                    .map(|_| *self.rng.pick(&[0, 1, 1, 7, -1]))
                    .collect();
                let p = if null_val { ptr::null() } else { vals.as_ptr() };
                ("fmi2SetBoolean", unsafe {
                    (fmi.set_boolean)(c, vp, nvr, p)
                })
            }
            _ => {
                let text = CString::new("text").unwrap();
                let mut vals: Vec<*const c_char> = vec![text.as_ptr(); n];
                if n > 0 && self.rng.chance(0.2) {
                    vals[0] = ptr::null();
                    expect_error = true;
                    wf = false;
                }
                let p = if null_val { ptr::null() } else { vals.as_ptr() };
                ("fmi2SetString", unsafe { (fmi.set_string)(c, vp, nvr, p) })
            }
        };
        let legal = allowed(name, self.mode);
        let s = self.check(name, s, n0, wf);
        if wf && legal {
            assert_eq!(
                s == ERROR,
                expect_error,
                "{name} of {vrs:?} in {mode:?}: {:?}",
                self.inst.log.borrow().last()
            );
        }
    }

    fn record_state(&mut self, s: *mut c_void) {
        let (mode, time) = (self.mode, self.time);
        match self.states.iter_mut().find(|h| h.s == s) {
            Some(h) => (h.mode, h.time) = (mode, time),
            None => self.states.push(Held { s, mode, time }),
        }
    }

    fn get_state(&mut self) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let before = self.mode;
        if self.rng.chance(0.05) {
            let s = unsafe { (fmi.get_state)(c, ptr::null_mut()) };
            self.check("fmi2GetFMUstate", s, n0, false);
            return;
        }
        let reuse = !self.states.is_empty() && self.rng.chance(0.3);
        let mut s: *mut c_void = if reuse {
            self.states[self.rng.below(self.states.len())].s
        } else {
            ptr::null_mut()
        };
        let st = unsafe { (fmi.get_state)(c, &mut s) };
        if self.check("fmi2GetFMUstate", st, n0, true) == OK {
            self.mode = before;
            self.record_state(s);
        } else {
            assert!(reuse || s.is_null());
        }
    }

    /// A held state, NULL, or a pointer this instance never handed out.
    fn some_state(&mut self) -> (*mut c_void, Option<usize>) {
        match self.rng.below(10) {
            0 => (ptr::null_mut(), None),
            1 => (self.foreign.as_mut_ptr().cast(), None),
            _ if !self.states.is_empty() => {
                let k = self.rng.below(self.states.len());
                (self.states[k].s, Some(k))
            }
            _ => (ptr::null_mut(), None),
        }
    }

    fn set_state(&mut self) {
        let n0 = self.log_len();
        let (s, k) = self.some_state();
        let st = unsafe { (self.fmi.set_state)(self.c(), s) };
        if self.check("fmi2SetFMUstate", st, n0, true) == OK {
            let h = &self.states[k.expect("only held states are accepted")];
            (self.mode, self.time) = (h.mode, h.time);
        } else {
            assert!(k.is_none(), "a held state was refused");
        }
    }

    fn free_state(&mut self) {
        let n0 = self.log_len();
        if self.rng.chance(0.1) {
            let st = unsafe { (self.fmi.free_state)(self.c(), ptr::null_mut()) };
            assert_eq!(self.check("fmi2FreeFMUstate", st, n0, true), OK);
            return;
        }
        let before = self.mode;
        let (mut s, k) = self.some_state();
        let st = unsafe { (self.fmi.free_state)(self.c(), &mut s) };
        if self.check("fmi2FreeFMUstate", st, n0, true) == OK {
            assert!(s.is_null(), "fmi2FreeFMUstate sets the pointer to NULL");
            if let Some(k) = k {
                self.states.swap_remove(k);
            }
            self.mode = before;
        } else {
            assert!(k.is_none(), "a held state could not be freed");
        }
    }

    fn serialize(&mut self) {
        let (fmi, c) = (self.fmi, self.c());
        let before = self.mode;
        let (s, k) = self.some_state();
        let n0 = self.log_len();
        let mut size = usize::MAX;
        let null_size = self.rng.chance(0.05);
        let psize = if null_size {
            ptr::null_mut()
        } else {
            &mut size
        };
        let st = unsafe { (fmi.state_size)(c, s, psize) };
        if self.check("fmi2SerializedFMUstateSize", st, n0, !null_size) != OK {
            return;
        }
        self.mode = before;
        let held = &self.states[k.expect("a size for a held state only")];
        let (mode, time) = (held.mode, held.time);
        let n0 = self.log_len();
        let wrong = self.rng.chance(0.1);
        let len = if wrong {
            size + 1 - 2 * self.rng.below(2)
        } else {
            size
        };
        let mut bytes = vec![0u8; len];
        let null_buf = self.rng.chance(0.05);
        let p = if null_buf {
            ptr::null_mut()
        } else {
            bytes.as_mut_ptr().cast()
        };
        let st = unsafe { (fmi.serialize)(c, s, p, len) };
        if self.check("fmi2SerializeFMUstate", st, n0, !null_buf) == OK {
            assert!(!wrong && !null_buf);
            self.mode = before;
            self.blobs.push(Blob { bytes, mode, time });
        } else {
            assert!(wrong || null_buf, "serializing a held state failed");
        }
    }

    fn deserialize(&mut self) {
        let (fmi, c) = (self.fmi, self.c());
        let before = self.mode;
        let n0 = self.log_len();
        // A valid blob, or a damaged one (truncated, bit flip, random).
        let (bytes, intact, view) = if self.blobs.is_empty() || self.rng.chance(0.1) {
            let n = self.rng.below(64);
            (
                (0..n).map(|_| self.rng.next_u64() as u8).collect(),
                false,
                None,
            )
        } else {
            let b = &self.blobs[self.rng.below(self.blobs.len())];
            let mut bytes = b.bytes.clone();
            let view = Some((b.mode, b.time));
            match self.rng.below(4) {
                0 => {
                    let keep = self.rng.below(bytes.len());
                    bytes.truncate(keep);
                    (bytes, false, view)
                }
                1 => {
                    let i = self.rng.below(bytes.len());
                    bytes[i] ^= 1 << self.rng.below(8);
                    (bytes, false, view)
                }
                _ => (bytes, true, view),
            }
        };
        let null_bytes = self.rng.chance(0.05);
        let p = if null_bytes {
            ptr::null()
        } else {
            bytes.as_ptr().cast()
        };
        let reuse = !self.states.is_empty() && self.rng.chance(0.3);
        let mut s: *mut c_void = if reuse {
            self.states[self.rng.below(self.states.len())].s
        } else {
            ptr::null_mut()
        };
        let old = s;
        let st = unsafe { (fmi.deserialize)(c, p, bytes.len(), &mut s) };
        if self.check("fmi2DeSerializeFMUstate", st, n0, !null_bytes) == OK {
            assert!(intact && !null_bytes, "damaged serialized state accepted");
            self.mode = before;
            let (mode, time) = view.expect("intact blob");
            match self.states.iter_mut().find(|h| h.s == s) {
                Some(h) => (h.mode, h.time) = (mode, time),
                None => self.states.push(Held { s, mode, time }),
            }
        } else {
            assert_eq!(s, old, "a refused deserialization leaves *FMUstate alone");
            assert!(
                !intact || null_bytes || !allowed("fmi2DeSerializeFMUstate", before),
                "an intact serialized state was refused: {:?}",
                self.inst.log.borrow().last()
            );
        }
    }

    fn derivatives(&mut self, set: bool) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let vrs = self.vrs(VarType::Real);
        let n = vrs.len();
        let orders: Vec<c_int> = (0..n)
            .map(|_| *self.rng.pick(&[1, 1, 1, 0, 2, -1]))
            .collect();
        if set {
            let vals: Vec<f64> = (0..n)
                .map(|_| *self.rng.pick(&[0.0, 10.0, -5.0, f64::NAN]))
                .collect();
            let s = unsafe {
                (fmi.set_input_derivatives)(c, vrs.as_ptr(), n, orders.as_ptr(), vals.as_ptr())
            };
            self.check("fmi2SetRealInputDerivatives", s, n0, true);
        } else {
            let mut out = vec![0.0; n + 1];
            out[n] = 12345.0;
            let s = unsafe {
                (fmi.get_output_derivatives)(c, vrs.as_ptr(), n, orders.as_ptr(), out.as_mut_ptr())
            };
            assert_eq!(out[n], 12345.0, "wrote past nvr");
            self.check("fmi2GetRealOutputDerivatives", s, n0, true);
        }
    }

    fn do_step(&mut self) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let t = match self.rng.below(10) {
            0 => self.time + 1e-3,
            1 => f64::NAN,
            _ => self.time,
        };
        let h = *self.rng.pick(&[
            1e-4,
            1e-4,
            1e-4,
            2e-4,
            5e-5,
            0.0,
            -1e-4,
            f64::NAN,
            f64::INFINITY,
        ]);
        let s = unsafe { (fmi.do_step)(c, t, h, self.rng.below(2) as c_int) };
        let legal = allowed("fmi2DoStep", self.mode);
        match self.check("fmi2DoStep", s, n0, true) {
            OK => {
                assert!(legal && h > 0.0 && t == self.time);
                self.time += h;
            }
            DISCARD => {
                // whatever fmi2SetDebugLogging switched: a discard's reason
                // is always forwarded
                assert!(self.inst.logged(DISCARD, "fmi2DoStep: step from"));
                self.mode = StepFailed;
            }
            ERROR => {}
            other => panic!("fmi2DoStep returned {other}"),
        }
        let _ = self.stop;
    }

    fn status(&mut self) {
        let (fmi, c, n0) = (self.fmi, self.c(), self.log_len());
        let before = self.mode;
        let kind = *self.rng.pick(&[
            DO_STEP_STATUS,
            PENDING_STATUS,
            LAST_SUCCESSFUL_TIME,
            LAST_SUCCESSFUL_TIME,
            TERMINATED,
            7,
            -1,
        ]);
        let null = self.rng.chance(0.05);
        match self.rng.below(5) {
            0 => {
                let mut v: c_int = -1;
                let p = if null { ptr::null_mut() } else { &mut v };
                let s = unsafe { (fmi.get_status)(c, kind, p) };
                self.check("fmi2GetStatus", s, n0, !null);
            }
            1 => {
                let mut v = f64::NAN;
                let p = if null { ptr::null_mut() } else { &mut v };
                let s = unsafe { (fmi.get_real_status)(c, kind, p) };
                if self.check("fmi2GetRealStatus", s, n0, !null) == OK {
                    assert_eq!(kind, LAST_SUCCESSFUL_TIME);
                    assert_eq!(v, self.time, "fmi2LastSuccessfulTime");
                }
            }
            2 => {
                let mut v: c_int = -1;
                let p = if null { ptr::null_mut() } else { &mut v };
                let s = unsafe { (fmi.get_integer_status)(c, kind, p) };
                self.check("fmi2GetIntegerStatus", s, n0, !null);
            }
            3 => {
                let mut v: c_int = -1;
                let p = if null { ptr::null_mut() } else { &mut v };
                let s = unsafe { (fmi.get_boolean_status)(c, kind, p) };
                if self.check("fmi2GetBooleanStatus", s, n0, !null) == OK {
                    assert_eq!((kind, v), (TERMINATED, 0));
                }
            }
            _ => {
                let mut v: *const c_char = ptr::null();
                let p = if null { ptr::null_mut() } else { &mut v };
                let s = unsafe { (fmi.get_string_status)(c, kind, p) };
                self.check("fmi2GetStringStatus", s, n0, !null);
            }
        }
        if self.mode != Error {
            self.mode = before;
        }
    }

    /// Any function with a NULL instance: fmi2Error (nothing to log to).
    fn null_instance(&mut self) {
        let fmi = self.fmi;
        let n = ptr::null_mut();
        let mut x = 0.0;
        let mut s: *mut c_void = ptr::null_mut();
        let st = unsafe {
            match self.rng.below(8) {
                0 => (fmi.do_step)(n, 0.0, 1e-3, 0),
                1 => (fmi.get_real)(n, &1, 1, &mut x),
                2 => (fmi.set_real)(n, &10, 1, &x),
                3 => (fmi.get_state)(n, &mut s),
                4 => (fmi.exit_init)(n),
                5 => (fmi.reset)(n),
                6 => (fmi.get_real_status)(n, LAST_SUCCESSFUL_TIME, &mut x),
                _ => {
                    (fmi.free_instance)(n);
                    ERROR
                }
            }
        };
        assert_eq!(st, ERROR);
        self.calls += 1;
    }

    /// Free the instance (sometimes leaving its states for fmi2FreeInstance
    /// to free) and start a new one.
    fn reinstantiate(&mut self) {
        let free = self.rng.chance(0.5);
        self.finish(free);
        self.inst = Instance::new(self.fmi);
        self.calls += 1;
        self.mode = Instantiated;
        self.time = 0.0;
        self.stop = None;
        if self.rng.chance(0.8) {
            self.baseline();
        }
    }

    /// Free the held states (or leave them to fmi2FreeInstance).
    fn finish(&mut self, free_states: bool) {
        if free_states {
            for h in std::mem::take(&mut self.states) {
                let mut s = h.s;
                let st = unsafe { (self.fmi.free_state)(self.c(), &mut s) };
                assert_eq!(st, OK, "{:?}", self.inst.log.borrow().last());
                self.calls += 1;
            }
        }
        self.states.clear();
    }
}

/// Also exercise fmi2Instantiate with bad arguments.
fn bad_instantiations(fmi: &Fmi, rng: &mut Rng) -> usize {
    let log = Box::new(Log::default());
    let cb = Callbacks {
        logger: Some(logger),
        allocate_memory: ptr::null(),
        free_memory: ptr::null(),
        step_finished: ptr::null(),
        component_environment: &*log as *const Log as *mut c_void,
    };
    let guid = CString::new(GUID).unwrap();
    let mut n = 0;
    for _ in 0..20 {
        let name = *rng.pick(&[c"ok".as_ptr(), c"".as_ptr(), c"  ".as_ptr(), ptr::null()]);
        let ty = *rng.pick(&[CO_SIMULATION, MODEL_EXCHANGE, 7, -1]);
        let g = *rng.pick(&[guid.as_ptr(), c"{nope}".as_ptr(), ptr::null()]);
        let callbacks: *const Callbacks = if rng.chance(0.1) { ptr::null() } else { &cb };
        let c = unsafe { (fmi.instantiate)(name, ty, g, ptr::null(), callbacks, 0, 1) };
        let valid = name == c"ok".as_ptr()
            && ty == CO_SIMULATION
            && g == guid.as_ptr()
            && !callbacks.is_null();
        assert_eq!(
            !c.is_null(),
            valid,
            "fmi2Instantiate accepted/refused wrongly"
        );
        if !valid && !callbacks.is_null() {
            assert!(
                log.borrow()
                    .last()
                    .is_some_and(|(s, _, m)| *s == ERROR && m.starts_with("fmi2Instantiate")),
                "refused without a log line"
            );
        }
        unsafe { (fmi.free_instance)(c) };
        n += 1;
    }
    n
}

#[test]
fn fuzzed_call_sequences() {
    let fmi = Fmi::load();
    let sequences = iterations("BELT_FUZZ_ITERS", CI_SEQUENCES);
    let seed = seed(CI_SEED);
    let started = std::time::Instant::now();
    let mut rng = Rng::new(seed ^ 0x1234);
    let mut total = 0;
    let mut statuses = [0; 6];
    let mut illegal = 0;
    for k in 0..sequences {
        let mut f = Fuzzer::new(&fmi, seed.wrapping_add(k as u64));
        if f.rng.chance(0.8) {
            f.baseline();
        }
        for _ in 0..CALLS_PER_SEQUENCE {
            f.step();
        }
        let leave = f.rng.chance(0.3);
        f.finish(!leave);
        total += f.calls;
        illegal += f.illegal;
        for (a, b) in statuses.iter_mut().zip(f.statuses) {
            *a += b;
        }
        if k % 20 == 0 {
            total += bad_instantiations(&fmi, &mut rng);
        }
    }
    println!(
        "fuzz_calls: seed {seed}, {sequences} sequences, {total} FMI calls, {} of them checked by the oracle ({illegal} in an illegal state) in {:.1} s; statuses OK {} / Discard {} / Error {}",
        statuses.iter().sum::<usize>(),
        started.elapsed().as_secs_f64(),
        statuses[0],
        statuses[2],
        statuses[3]
    );
    assert!(statuses[OK as usize] > 0 && statuses[ERROR as usize] > 0);
}
