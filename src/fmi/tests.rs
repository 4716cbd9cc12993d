//! Plumbing tests through the pointer-level API with a mock model that has
//! its own small variable table, so they depend on no real model.
//! (`tests/fmi_abi.rs` exercises the exported symbols of the built library
//! with the real model.)

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::ptr;

use super::api::{self, Transition};
use super::description::{Causality, ModelDescription, Start, VarType, Variability};
use super::logging::{missing_categories, PLUMBING_CATEGORIES};
use super::model::{FmuModel, StepError};
use super::state::{fnv1a_64, Snapshot};
use super::types::*;

// -- Mock model -------------------------------------------------------------

type VarInfo = super::description::VarInfo<()>;

const MOCK_GUID: &str = "{5d0c9a1e-7b42-8e61-9f03-2c4b6a8d0e17}";

/// A variable of the mock's table.
const fn var(
    vr: u32,
    name: &'static str,
    ty: VarType,
    causality: Causality,
    variability: Variability,
    start: Start,
) -> VarInfo {
    VarInfo {
        vr,
        name,
        var: (),
        index: 0,
        ty,
        causality,
        variability,
        start,
        min: None,
        max: None,
        description: "mock variable",
        unit: "",
    }
}

use Causality::{Input, Output, Parameter};
use Variability::{Continuous, Fixed};

/// The mock's variables, in value-reference order.
static MOCK_VARIABLES: [VarInfo; 8] = [
    var(
        1,
        "nPulleys",
        VarType::Integer,
        Parameter,
        Fixed,
        Start::Integer(2),
    ),
    var(
        10,
        "gravity",
        VarType::Real,
        Parameter,
        Fixed,
        Start::Real(9.81),
    ),
    var(
        11,
        "belt.preload",
        VarType::Real,
        Parameter,
        Fixed,
        Start::Real(500.0),
    ),
    var(
        120,
        "pulley[1].torque",
        VarType::Real,
        Input,
        Continuous,
        Start::Real(0.0),
    ),
    var(
        220,
        "pulley[2].torque",
        VarType::Real,
        Input,
        Continuous,
        Start::Real(0.0),
    ),
    var(
        312,
        "pulley[3].backSide",
        VarType::Boolean,
        Parameter,
        Fixed,
        Start::Boolean(false),
    ),
    var(
        1001,
        "belt.minTension",
        VarType::Real,
        Output,
        Continuous,
        Start::None,
    ),
    var(
        1101,
        "pulley[1].omega",
        VarType::Real,
        Output,
        Continuous,
        Start::None,
    ),
];

static MOCK: ModelDescription<()> = ModelDescription {
    model_identifier: "Mock",
    guid: MOCK_GUID,
    log_categories: &PLUMBING_CATEGORIES,
    variables: &MOCK_VARIABLES,
    by_vr: &[
        (1, 0),
        (10, 1),
        (11, 2),
        (120, 3),
        (220, 4),
        (312, 5),
        (1001, 6),
        (1101, 7),
    ],
    by_name: &[
        ("belt.minTension", 6),
        ("belt.preload", 2),
        ("gravity", 1),
        ("nPulleys", 0),
        ("pulley[1].omega", 7),
        ("pulley[1].torque", 3),
        ("pulley[2].torque", 4),
        ("pulley[3].backSide", 5),
    ],
};

const MAGIC: &[u8; 8] = &Mock::STATE_MAGIC;

fn by_name(name: &str) -> Option<&'static VarInfo> {
    MOCK.by_name(name)
}

#[test]
fn mock_table_is_consistent() {
    MOCK.validate().unwrap();
    assert!(missing_categories(MOCK.log_categories).is_empty());
    assert_eq!(
        MOCK.lookup(VarType::Real, 220).unwrap().name,
        "pulley[2].torque"
    );
    assert!(MOCK.lookup(VarType::Integer, 220).is_none());
    assert!(MOCK.by_vr(2).is_none() && MOCK.by_name("belt").is_none());
}

#[test]
fn broken_indices_are_found() {
    let unsorted = ModelDescription {
        by_vr: &[(10, 1), (1, 0)],
        by_name: &[("gravity", 1), ("nPulleys", 0)],
        variables: &MOCK_VARIABLES[..2],
        ..MOCK
    };
    assert!(unsorted.validate().unwrap_err().contains("not ascending"));
    let wrong = ModelDescription {
        by_vr: &[(1, 1), (10, 0)],
        by_name: &[("gravity", 1), ("nPulleys", 0)],
        variables: &MOCK_VARIABLES[..2],
        ..MOCK
    };
    assert!(wrong
        .validate()
        .unwrap_err()
        .contains("indexes the wrong variable"));
}

/// Stores parameters/inputs by value reference; outputs are `t + vr/1000`.
/// `gravity < 0` makes do_step panic, `gravity == 0` fail, `h > 0.1` discard.
#[derive(Clone, Debug, PartialEq)]
struct Mock {
    t: f64,
    reals: BTreeMap<u32, f64>,
    ints: BTreeMap<u32, i32>,
    bools: BTreeMap<u32, bool>,
}

fn vr(name: &str) -> u32 {
    by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

impl FmuModel for Mock {
    type Var = ();
    const STATE_MAGIC: [u8; 8] = *b"MOCKFMU\0";

    fn description() -> &'static ModelDescription<()> {
        &MOCK
    }

    fn new() -> Self {
        let mut m = Mock {
            t: 0.0,
            reals: BTreeMap::new(),
            ints: BTreeMap::new(),
            bools: BTreeMap::new(),
        };
        for v in MOCK.variables {
            match v.start {
                Start::Real(x) => drop(m.reals.insert(v.vr, x)),
                Start::Integer(x) => drop(m.ints.insert(v.vr, x)),
                Start::Boolean(x) => drop(m.bools.insert(v.vr, x)),
                _ => {}
            }
        }
        m
    }
    fn get_real(&mut self, v: &VarInfo) -> Result<f64, String> {
        if v.causality == Causality::Output {
            return Ok(self.t + f64::from(v.vr) / 1000.0);
        }
        self.reals
            .get(&v.vr)
            .copied()
            .ok_or_else(|| "no value".into())
    }
    fn set_real(&mut self, v: &VarInfo, value: f64) -> Result<(), String> {
        if value.is_nan() {
            return Err("NaN is not allowed".into());
        }
        self.reals.insert(v.vr, value);
        Ok(())
    }
    fn get_integer(&mut self, v: &VarInfo) -> Result<i32, String> {
        self.ints
            .get(&v.vr)
            .copied()
            .ok_or_else(|| "no value".into())
    }
    fn set_integer(&mut self, v: &VarInfo, value: i32) -> Result<(), String> {
        self.ints.insert(v.vr, value);
        Ok(())
    }
    fn get_boolean(&mut self, v: &VarInfo) -> Result<bool, String> {
        self.bools
            .get(&v.vr)
            .copied()
            .ok_or_else(|| "no value".into())
    }
    fn set_boolean(&mut self, v: &VarInfo, value: bool) -> Result<(), String> {
        self.bools.insert(v.vr, value);
        Ok(())
    }
    fn setup_experiment(&mut self, _tolerance: Option<f64>, start_time: f64) {
        self.t = start_time;
    }
    fn initialize(&mut self) -> Result<Vec<String>, String> {
        let n = self.ints[&vr("nPulleys")];
        if !(2..=6).contains(&n) {
            return Err(format!("nPulleys = {n} is outside 2..6"));
        }
        Ok(if self.reals[&vr("gravity")] == 0.0 {
            vec!["gravity = 0: weightless".into()]
        } else {
            Vec::new()
        })
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), StepError> {
        assert_eq!(t, self.t, "plumbing passes the model's own time");
        let g = self.reals[&vr("gravity")];
        if g < 0.0 {
            panic!("negative gravity");
        }
        if g == 0.0 {
            return Err(StepError::Error("zero gravity".into()));
        }
        if h > 0.1 {
            return Err(StepError::Discard("step larger than 0.1 (100%)".into()));
        }
        self.t += h;
        Ok(())
    }
    fn set_input_derivative(
        &mut self,
        _v: &VarInfo,
        order: i32,
        _value: f64,
    ) -> Result<(), String> {
        (order == 1)
            .then_some(())
            .ok_or_else(|| format!("order {order} > 1"))
    }
    fn get_output_derivative(&mut self, _v: &VarInfo, order: i32) -> Result<f64, String> {
        (order == 1)
            .then_some(42.0)
            .ok_or_else(|| format!("order {order} > 1"))
    }
    fn serialize(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.t.to_le_bytes());
        for (k, x) in &self.reals {
            out.extend_from_slice(&k.to_le_bytes());
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    fn deserialize(bytes: &[u8]) -> Result<Self, String> {
        let mut m = Mock::new();
        if bytes.len() < 8 || !(bytes.len() - 8).is_multiple_of(12) {
            return Err("bad length".into());
        }
        m.t = f64::from_le_bytes(bytes[..8].try_into().map_err(|_| "t")?);
        for chunk in bytes[8..].chunks_exact(12) {
            let k = u32::from_le_bytes(chunk[..4].try_into().map_err(|_| "k")?);
            let x = f64::from_le_bytes(chunk[4..].try_into().map_err(|_| "x")?);
            m.reals.insert(k, x);
        }
        Ok(m)
    }
}

// -- Test harness -----------------------------------------------------------

#[derive(Debug, Clone)]
struct Line {
    status: c_int,
    category: String,
    message: String,
}

type Log = RefCell<Vec<Line>>;

/// A non-variadic logger: our plumbing passes the formatted message as the
/// format string with no variadic arguments, so this is ABI-compatible on
/// the supported platforms (fixed arguments are passed identically).
unsafe extern "C" fn test_logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: env is the &Log given at instantiation; strings are valid C strings.
    let (log, category, message) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(category).to_string_lossy().into_owned(),
            CStr::from_ptr(message).to_string_lossy().into_owned(),
        )
    };
    log.borrow_mut().push(Line {
        status,
        category,
        message,
    });
}

type PlainLogger =
    unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

fn callbacks(log: &Log) -> Fmi2CallbackFunctions {
    // SAFETY: same size (function pointers); see `test_logger`.
    let logger = unsafe {
        std::mem::transmute::<PlainLogger, unsafe extern "C" fn(_, _, _, _, _, ...)>(test_logger)
    };
    Fmi2CallbackFunctions {
        logger: Some(logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: log as *const Log as *mut c_void,
    }
}

struct Fmu {
    c: Fmi2Component,
    log: Box<Log>,
}

const OK: Fmi2Status = Fmi2Status::Ok;
const ERR: Fmi2Status = Fmi2Status::Error;

impl Fmu {
    fn try_new(guid: &str, ty: c_int, logging_on: bool) -> (Fmi2Component, Box<Log>) {
        let log = Box::new(Log::default());
        let cb = callbacks(&log);
        let name = CString::new("inst").unwrap();
        let guid = CString::new(guid).unwrap();
        let c = unsafe {
            api::instantiate::<Mock>(
                name.as_ptr(),
                ty,
                guid.as_ptr(),
                ptr::null(),
                &cb,
                0,
                c_int::from(logging_on),
            )
        };
        (c, log)
    }
    fn new() -> Fmu {
        let (c, log) = Self::try_new(MOCK_GUID, FMI2_CO_SIMULATION, false);
        assert!(!c.is_null());
        Fmu { c, log }
    }
    fn initialized() -> Fmu {
        let f = Fmu::new();
        assert_eq!(f.setup(0.0, None), OK);
        assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
        assert_eq!(f.tr(Transition::ExitInitializationMode), OK);
        f
    }
    fn setup(&self, start: f64, stop: Option<f64>) -> Fmi2Status {
        unsafe {
            api::setup_experiment::<Mock>(
                self.c,
                0,
                0.0,
                start,
                c_int::from(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        }
    }
    fn tr(&self, t: Transition) -> Fmi2Status {
        unsafe { api::transition::<Mock>(self.c, t) }
    }
    fn step(&self, t: f64, h: f64) -> Fmi2Status {
        unsafe { api::do_step::<Mock>(self.c, t, h) }
    }
    fn get_r(&self, name: &str) -> (Fmi2Status, f64) {
        let mut x = f64::NAN;
        let s = unsafe { api::get_real::<Mock>(self.c, &vr(name), 1, &mut x) };
        (s, x)
    }
    fn set_r(&self, name: &str, x: f64) -> Fmi2Status {
        unsafe { api::set_real::<Mock>(self.c, &vr(name), 1, &x) }
    }
    fn set_i(&self, name: &str, x: i32) -> Fmi2Status {
        unsafe { api::set_integer::<Mock>(self.c, &vr(name), 1, &x) }
    }
    fn lines(&self) -> Vec<Line> {
        self.log.borrow().clone()
    }
    /// The last logged message; asserts it is an fmi2Error containing `needle`.
    fn assert_error_logged(&self, needle: &str) {
        let lines = self.lines();
        let last = lines.last().expect("a log line");
        assert_eq!(last.status, ERR as c_int, "{last:?}");
        assert_eq!(last.category, "logStatusError");
        assert!(
            last.message.contains(needle),
            "expected {needle:?} in {:?}",
            last.message
        );
    }
    fn mode(&self) -> super::instance::Mode {
        // SAFETY: test-only peek at our own instance.
        unsafe {
            (*(self.c as *mut super::instance::Instance<Mock>))
                .plumbing
                .mode
        }
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { api::free_instance::<Mock>(self.c) };
    }
}

// -- Tests --------------------------------------------------------------------

#[test]
fn happy_path() {
    let f = Fmu::new();
    assert_eq!(f.set_i("nPulleys", 3), OK);
    assert_eq!(f.setup(1.0, Some(2.0)), OK);
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(
        f.set_r("belt.preload", 600.0),
        OK,
        "parameters settable in Initialization Mode"
    );
    assert_eq!(f.get_r("belt.preload"), (OK, 600.0));
    assert_eq!(f.tr(Transition::ExitInitializationMode), OK);
    assert_eq!(
        f.set_r("pulley[1].torque", 2.0),
        OK,
        "inputs settable after initialization"
    );
    assert_eq!(f.step(1.0, 0.05), OK);
    assert_eq!(
        f.step(1.05 + 1e-12, 0.05),
        OK,
        "rounding-level mismatch tolerated"
    );
    let (s, x) = f.get_r("belt.minTension");
    assert_eq!(s, OK);
    assert!((x - (1.1 + 1.001)).abs() < 1e-12);
    let mut t = 0.0;
    assert_eq!(
        unsafe { api::get_real_status::<Mock>(f.c, FMI2_LAST_SUCCESSFUL_TIME, &mut t) },
        OK
    );
    assert!((t - 1.1).abs() < 1e-12);
    assert_eq!(f.tr(Transition::Terminate), OK);
    assert_eq!(f.step(1.1, 0.05), ERR);
    f.assert_error_logged("illegal call sequence");
}

#[test]
fn instantiate_refusals_are_logged() {
    let (c, log) = Fmu::try_new(
        "{00000000-0000-0000-0000-000000000000}",
        FMI2_CO_SIMULATION,
        false,
    );
    assert!(c.is_null());
    assert!(
        log.borrow()[0].message.contains("does not match"),
        "{:?}",
        log.borrow()
    );
    let (c, log) = Fmu::try_new(MOCK_GUID, FMI2_MODEL_EXCHANGE, false);
    assert!(c.is_null());
    assert!(log.borrow()[0].message.contains("Co-Simulation only"));
    let cb = callbacks(&log);
    let guid = CString::new(MOCK_GUID).unwrap();
    let c =
        unsafe { api::instantiate::<Mock>(ptr::null(), 1, guid.as_ptr(), ptr::null(), &cb, 0, 0) };
    assert!(c.is_null());
    assert!(log
        .borrow()
        .last()
        .unwrap()
        .message
        .contains("instanceName"));
    let c = unsafe {
        api::instantiate::<Mock>(
            c"x".as_ptr(),
            1,
            guid.as_ptr(),
            ptr::null(),
            ptr::null(),
            0,
            0,
        )
    };
    assert!(c.is_null(), "NULL callbacks");
}

#[test]
fn illegal_sequence_enters_error_state_and_reset_recovers() {
    let f = Fmu::new();
    assert_eq!(f.step(0.0, 0.01), ERR);
    f.assert_error_logged("fmi2DoStep: illegal call sequence: not allowed in state Instantiated");
    assert_eq!(f.mode(), super::instance::Mode::Error);
    assert_eq!(
        f.tr(Transition::EnterInitializationMode),
        ERR,
        "Error state is sticky"
    );
    assert_eq!(f.tr(Transition::Reset), OK);
    assert_eq!(f.mode(), super::instance::Mode::Instantiated);
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    let (c, _) = (f.c, ());
    assert_eq!(unsafe { api::cancel_step::<Mock>(c) }, ERR);
    f.assert_error_logged("StepInProgress");
    assert_eq!(
        unsafe { api::get_directional_derivative::<Mock>(ptr::null_mut()) },
        ERR,
        "NULL instance"
    );
}

#[test]
fn variable_rules() {
    let f = Fmu::initialized();
    assert_eq!(f.set_r("belt.minTension", 1.0), ERR);
    f.assert_error_logged("is an output and cannot be set");
    let f = Fmu::initialized();
    assert_eq!(f.set_r("gravity", 1.0), ERR);
    f.assert_error_logged("only be set in Instantiated or Initialization Mode");
    let f = Fmu::initialized();
    let x = 1.0;
    assert_eq!(unsafe { api::set_real::<Mock>(f.c, &999_999, 1, &x) }, ERR);
    f.assert_error_logged("unknown value reference 999999");
    let f = Fmu::initialized();
    let mut i = 0;
    assert_eq!(
        unsafe { api::get_integer::<Mock>(f.c, &vr("gravity"), 1, &mut i) },
        ERR
    );
    f.assert_error_logged("is the Real variable \"gravity\", not a Integer variable");
    let f = Fmu::initialized();
    let mut y = 0.0;
    assert_eq!(
        unsafe { api::get_real::<Mock>(f.c, ptr::null(), 2, &mut y) },
        ERR
    );
    f.assert_error_logged("vr[] is a NULL pointer but its length is 2");
    let f = Fmu::initialized();
    assert_eq!(
        unsafe { api::get_real::<Mock>(f.c, &vr("gravity"), 1, ptr::null_mut()) },
        ERR
    );
    f.assert_error_logged("value[] is a NULL pointer");
    let f = Fmu::initialized();
    assert_eq!(
        unsafe { api::get_real::<Mock>(f.c, ptr::null(), 0, ptr::null_mut()) },
        OK,
        "nvr = 0"
    );
    assert_eq!(
        unsafe { api::set_string::<Mock>(f.c, &1, 1, &c"x".as_ptr()) },
        ERR
    );
    f.assert_error_logged("not a String variable");
    let f = Fmu::initialized();
    assert_eq!(f.set_r("pulley[2].torque", f64::NAN), ERR);
    f.assert_error_logged("\"pulley[2].torque\" (vr 220): NaN is not allowed");
    let f = Fmu::new();
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(f.set_i("nPulleys", 9), OK);
    assert_eq!(f.tr(Transition::ExitInitializationMode), ERR);
    f.assert_error_logged("nPulleys = 9 is outside 2..6");
    // a model's warning is logged with status fmi2Warning even with
    // logging off, and initialization still succeeds
    let f = Fmu::new();
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(f.set_r("gravity", 0.0), OK);
    assert_eq!(f.tr(Transition::ExitInitializationMode), OK);
    let last = f.lines().pop().expect("a warning");
    assert_eq!(last.status, 1, "{last:?}");
    assert_eq!(last.category, "logStatusWarning");
    assert_eq!(last.message, "gravity = 0: weightless");
    let f = Fmu::new();
    let mut b = 7;
    assert_eq!(
        unsafe { api::set_boolean::<Mock>(f.c, &vr("pulley[3].backSide"), 1, &1) },
        OK
    );
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(
        unsafe { api::get_boolean::<Mock>(f.c, &vr("pulley[3].backSide"), 1, &mut b) },
        OK
    );
    assert_eq!(b, FMI2_TRUE);
}

#[test]
fn derivatives() {
    let f = Fmu::initialized();
    let (v, o, x) = (vr("pulley[1].torque"), 1, 3.0);
    assert_eq!(
        unsafe { api::set_real_input_derivatives::<Mock>(f.c, &v, 1, &o, &x) },
        OK
    );
    let mut d = 0.0;
    assert_eq!(
        unsafe {
            api::get_real_output_derivatives::<Mock>(f.c, &vr("pulley[1].omega"), 1, &o, &mut d)
        },
        OK
    );
    assert_eq!(d, 42.0);
    assert_eq!(
        unsafe { api::get_real_output_derivatives::<Mock>(f.c, &v, 1, &o, &mut d) },
        ERR
    );
    f.assert_error_logged("is not an output");
    let f = Fmu::initialized();
    assert_eq!(
        unsafe { api::set_real_input_derivatives::<Mock>(f.c, &vr("gravity"), 1, &o, &x) },
        ERR
    );
    f.assert_error_logged("is not an input");
}

#[test]
fn step_checks() {
    let f = Fmu::initialized();
    assert_eq!(f.step(0.5, 0.01), ERR);
    f.assert_error_logged("currentCommunicationPoint = 0.5 differs from the FMU's current time 0");
    for h in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let f = Fmu::initialized();
        assert_eq!(f.step(0.0, h), ERR);
        f.assert_error_logged("communicationStepSize");
    }
    let f = Fmu::new();
    assert_eq!(f.setup(0.0, Some(0.05)), OK);
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(f.tr(Transition::ExitInitializationMode), OK);
    assert_eq!(f.step(0.0, 0.05), OK, "exactly to stopTime");
    assert_eq!(f.step(0.05, 0.01), ERR);
    f.assert_error_logged("stopTime");
}

#[test]
fn discard_keeps_last_good_time_and_state_restores() {
    let f = Fmu::initialized();
    assert_eq!(f.step(0.0, 0.1), OK);
    let mut s: Fmi2FmuState = ptr::null_mut();
    assert_eq!(unsafe { api::get_fmu_state::<Mock>(f.c, &mut s) }, OK);
    assert_eq!(f.step(0.1, 0.5), Fmi2Status::Discard);
    assert_eq!(f.mode(), super::instance::Mode::StepFailed);
    let lines = f.lines();
    assert_eq!(
        lines.len(),
        1,
        "a discard is logged with logging off: {lines:?}"
    );
    assert_eq!(
        (lines[0].status, lines[0].category.as_str()),
        (Fmi2Status::Discard as c_int, "logStatusDiscard")
    );
    assert!(
        lines[0].message.contains("discarded"),
        "{}",
        lines[0].message
    );
    let mut t = 0.0;
    assert_eq!(
        unsafe { api::get_real_status::<Mock>(f.c, FMI2_LAST_SUCCESSFUL_TIME, &mut t) },
        OK
    );
    assert_eq!(t, 0.1);
    let mut term = 7;
    assert_eq!(
        unsafe { api::get_boolean_status::<Mock>(f.c, FMI2_TERMINATED, &mut term) },
        OK
    );
    assert_eq!(term, FMI2_TRUE, "after a discard the instance asks to stop");
    let mut st = OK;
    assert_eq!(
        unsafe {
            api::get_unavailable_status::<Mock, _>(
                f.c,
                "fmi2GetStatus",
                FMI2_DO_STEP_STATUS,
                &mut st,
            )
        },
        Fmi2Status::Discard
    );
    assert_eq!(
        f.get_r("belt.minTension").1,
        0.1 + 1.001,
        "outputs still readable"
    );
    // Recover with the saved state and retry with a smaller step.
    assert_eq!(unsafe { api::set_fmu_state::<Mock>(f.c, s) }, OK);
    assert_eq!(f.mode(), super::instance::Mode::StepComplete);
    assert_eq!(f.step(0.1, 0.05), OK);
    assert_eq!(
        unsafe { api::get_boolean_status::<Mock>(f.c, FMI2_TERMINATED, &mut term) },
        OK
    );
    assert_eq!(term, FMI2_FALSE, "restored and stepping again");
    assert_eq!(unsafe { api::free_fmu_state::<Mock>(f.c, &mut s) }, OK);
    assert!(s.is_null());
    assert_eq!(
        unsafe { api::free_fmu_state::<Mock>(f.c, &mut s) },
        OK,
        "NULL state ignored"
    );
}

#[test]
fn discard_is_logged_and_percent_is_escaped() {
    let f = Fmu::initialized();
    let cats = [c"logStatusDiscard".as_ptr()];
    assert_eq!(
        unsafe { api::set_debug_logging::<Mock>(f.c, 1, 1, cats.as_ptr()) },
        OK
    );
    assert_eq!(f.step(0.0, 0.5), Fmi2Status::Discard);
    let last = f.lines().pop().unwrap();
    assert_eq!(
        (last.status, last.category.as_str()),
        (Fmi2Status::Discard as c_int, "logStatusDiscard")
    );
    assert!(
        last.message.contains("(100%%)"),
        "'%' doubled for printf: {}",
        last.message
    );
    let bad = [c"logNoSuchThing".as_ptr()];
    assert_eq!(
        unsafe { api::set_debug_logging::<Mock>(f.c, 1, 1, bad.as_ptr()) },
        ERR
    );
    f.assert_error_logged("unknown log category \"logNoSuchThing\"");
    let f = Fmu::initialized();
    assert_eq!(
        unsafe { api::set_debug_logging::<Mock>(f.c, 1, 1, ptr::null()) },
        ERR
    );
    f.assert_error_logged("categories[] is a NULL pointer");
}

#[test]
fn panic_becomes_error() {
    let f = Fmu::new();
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(f.set_r("gravity", -1.0), OK);
    assert_eq!(f.tr(Transition::ExitInitializationMode), OK);
    assert_eq!(f.step(0.0, 0.01), ERR);
    f.assert_error_logged("internal error (Rust panic: negative gravity)");
    assert_eq!(f.tr(Transition::Reset), OK);
    assert_eq!(
        f.get_r("gravity").0,
        ERR,
        "GetReal not allowed in Instantiated"
    );
    assert_eq!(f.tr(Transition::Reset), OK);
    assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    assert_eq!(
        f.get_r("gravity"),
        (OK, 9.81),
        "reset restored start values"
    );
}

#[test]
fn instances_are_independent() {
    let (a, b) = (Fmu::new(), Fmu::new());
    for f in [&a, &b] {
        assert_eq!(f.tr(Transition::EnterInitializationMode), OK);
    }
    assert_eq!(a.set_r("belt.preload", 100.0), OK);
    assert_eq!(b.set_r("belt.preload", 200.0), OK);
    assert_eq!(a.get_r("belt.preload").1, 100.0);
    assert_eq!(b.get_r("belt.preload").1, 200.0);
    assert_eq!(a.step(0.0, 0.1), ERR);
    assert!(
        b.lines().is_empty(),
        "errors go to the right instance's logger"
    );
    assert_eq!(b.tr(Transition::ExitInitializationMode), OK);
}

fn serialized(f: &Fmu, s: Fmi2FmuState) -> Vec<u8> {
    let mut size = 0;
    assert_eq!(
        unsafe { api::serialized_fmu_state_size::<Mock>(f.c, s, &mut size) },
        OK
    );
    let mut bytes = vec![0u8; size];
    assert_eq!(
        unsafe { api::serialize_fmu_state::<Mock>(f.c, s, bytes.as_mut_ptr().cast(), size) },
        OK
    );
    bytes
}

fn deserialize(f: &Fmu, bytes: &[u8], s: &mut Fmi2FmuState) -> Fmi2Status {
    unsafe { api::deserialize_fmu_state::<Mock>(f.c, bytes.as_ptr().cast(), bytes.len(), s) }
}

#[test]
fn serialization_round_trip_and_refusals() {
    let f = Fmu::initialized();
    assert_eq!(f.set_r("pulley[1].torque", 1.5), OK);
    assert_eq!(f.step(0.0, 0.1), OK);
    let mut s: Fmi2FmuState = ptr::null_mut();
    assert_eq!(unsafe { api::get_fmu_state::<Mock>(f.c, &mut s) }, OK);
    let bytes = serialized(&f, s);
    assert_eq!(&bytes[..8], MAGIC);
    let wrong = bytes.len() + 1;
    assert_eq!(
        unsafe { api::serialize_fmu_state::<Mock>(f.c, s, vec![0i8; wrong].as_mut_ptr(), wrong) },
        ERR
    );
    f.assert_error_logged("fmi2SerializedFMUstateSize");

    // Into another instance: identical model and plumbing.
    let g = Fmu::new();
    let mut s2: Fmi2FmuState = ptr::null_mut();
    assert_eq!(deserialize(&g, &bytes, &mut s2), OK);
    assert_eq!(unsafe { api::set_fmu_state::<Mock>(g.c, s2) }, OK);
    // SAFETY: test-only peeks at our own objects.
    unsafe {
        let (a, b) = (
            &*(s as *const Snapshot<Mock>),
            &*(s2 as *const Snapshot<Mock>),
        );
        assert_eq!(a.model, b.model);
        assert_eq!(a.plumbing, b.plumbing);
    }
    assert_eq!(g.step(0.1, 0.1), OK);
    assert_eq!(g.get_r("pulley[1].torque").1, 1.5);
    // Reusing an existing state object.
    let before = s2;
    assert_eq!(deserialize(&g, &bytes, &mut s2), OK);
    assert_eq!(s2, before);

    let refuse = |bytes: &[u8], needle: &str| {
        let h = Fmu::new();
        let mut s3: Fmi2FmuState = ptr::null_mut();
        assert_eq!(deserialize(&h, bytes, &mut s3), ERR, "{needle}");
        assert!(s3.is_null());
        h.assert_error_logged(needle);
    };
    for n in [0, 7, 12, bytes.len() / 2, bytes.len() - 1] {
        refuse(&bytes[..n], "truncated");
    }
    let mut bad = bytes.clone();
    *bad.last_mut().unwrap() ^= 1;
    refuse(&bad, "checksum mismatch");
    let mut bad = bytes.clone();
    let mid = bad.len() - 20;
    bad[mid] ^= 0x10;
    refuse(&bad, "checksum mismatch");
    let mut bad = bytes.clone();
    bad[0] = b'X';
    refuse(&bad, "bad magic");
    let mut bad = bytes.clone();
    bad[8] = 2;
    refuse(&bad, "format version 2");
    // A foreign GUID with a valid checksum.
    let mut bad = bytes[..bytes.len() - 8].to_vec();
    bad[17] = if bad[17] == b'0' { b'1' } else { b'0' };
    let sum = fnv1a_64(&bad);
    bad.extend_from_slice(&sum.to_le_bytes());
    refuse(&bad, "belongs to the model description with GUID");
    let mut extra = bytes.clone();
    extra.push(0);
    refuse(&extra, "unexpected bytes");

    // A state belongs to the instance that made it (FMI 2.0 section 2.1.8):
    // another instance refuses it without dereferencing it.
    let h = Fmu::new();
    assert_eq!(unsafe { api::set_fmu_state::<Mock>(h.c, s2) }, ERR);
    h.assert_error_logged("not a live FMU state of this instance");
    assert_eq!(unsafe { api::free_fmu_state::<Mock>(f.c, &mut s2) }, ERR);
    assert!(!s2.is_null(), "a refused free leaves the pointer alone");

    assert_eq!(unsafe { api::free_fmu_state::<Mock>(f.c, &mut s) }, OK);
    assert_eq!(unsafe { api::free_fmu_state::<Mock>(g.c, &mut s2) }, OK);
}

/// The plumbing reaches no other part of the crate: every `crate::` path
/// in `src/fmi/` stays inside `crate::fmi` (the model comes in through
/// `FmuModel` only).
#[test]
fn plumbing_depends_on_no_model() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/fmi");
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "rs") || path.ends_with("tests.rs") {
            continue;
        }
        files += 1;
        let text = std::fs::read_to_string(&path).unwrap();
        for (i, line) in text.lines().enumerate() {
            for (at, _) in line.match_indices("crate::") {
                let rest = &line[at + "crate::".len()..];
                assert!(
                    rest.starts_with("fmi") || rest.starts_with("export_fmi2_co_simulation"),
                    "{}:{}: {line}",
                    path.display(),
                    i + 1
                );
            }
        }
    }
    assert!(files >= 9, "{files} files read");
}
