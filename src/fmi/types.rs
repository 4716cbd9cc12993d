//! The C types of `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` (FMI 2.0
//! section 2.1.2 - 2.1.4), laid out for the C ABI.

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component`: an instance.
pub type Fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the importer's pointer handed back to its callbacks.
pub type Fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: a saved state.
pub type Fmi2FmuState = *mut c_void;
/// `fmi2ValueReference`.
pub type Fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type Fmi2Real = f64;
/// `fmi2Integer`.
pub type Fmi2Integer = c_int;
/// `fmi2Boolean`.
pub type Fmi2Boolean = c_int;
/// `fmi2Char`.
pub type Fmi2Char = c_char;
/// `fmi2String`.
pub type Fmi2String = *const Fmi2Char;
/// `fmi2Byte`.
pub type Fmi2Byte = c_char;

/// `fmi2True`.
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// `fmi2False`.
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`. Only ever produced by us (incoming enum values are taken
/// as `c_int` and checked, since an out-of-range Rust enum would be UB).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fmi2Status {
    /// `fmi2OK`.
    Ok = 0,
    /// `fmi2Warning`.
    Warning = 1,
    /// `fmi2Discard`.
    Discard = 2,
    /// `fmi2Error`.
    Error = 3,
    /// `fmi2Fatal`.
    Fatal = 4,
    /// `fmi2Pending`.
    Pending = 5,
}

impl Fmi2Status {
    /// The status's C name, e.g. `"fmi2OK"`.
    pub fn as_str(self) -> &'static str {
        match self {
            Fmi2Status::Ok => "fmi2OK",
            Fmi2Status::Warning => "fmi2Warning",
            Fmi2Status::Discard => "fmi2Discard",
            Fmi2Status::Error => "fmi2Error",
            Fmi2Status::Fatal => "fmi2Fatal",
            Fmi2Status::Pending => "fmi2Pending",
        }
    }
}

/// `fmi2Type` values (passed as `c_int`).
pub const FMI2_MODEL_EXCHANGE: c_int = 0;
/// `fmi2CoSimulation`.
pub const FMI2_CO_SIMULATION: c_int = 1;

/// `fmi2StatusKind` values (passed as `c_int`).
pub const FMI2_DO_STEP_STATUS: c_int = 0;
/// `fmi2PendingStatus`.
pub const FMI2_PENDING_STATUS: c_int = 1;
/// `fmi2LastSuccessfulTime`.
pub const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
/// `fmi2Terminated`.
pub const FMI2_TERMINATED: c_int = 3;

/// `fmi2CallbackLogger`: C-variadic (`const char* message, ...`). We always
/// call it with a message that is already formatted and has every `%`
/// doubled, and no variadic arguments, so a printf-style logger prints it
/// verbatim and a non-variadic logger can read `message` directly.
pub type Fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        Fmi2ComponentEnvironment,
        Fmi2String, // instanceName
        Fmi2Status,
        Fmi2String, // category
        Fmi2String, // message (printf format)
        ...
    ),
>;
/// `fmi2CallbackAllocateMemory` (never called).
pub type Fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
/// `fmi2CallbackFreeMemory` (never called).
pub type Fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
/// `fmi2StepFinished` (never called).
pub type Fmi2StepFinished = Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2Status)>;

/// `fmi2CallbackFunctions`. Copied by value in fmi2Instantiate (the importer
/// need not keep its struct alive). The memory functions are never used
/// (`canNotUseMemoryManagementFunctions="true"`), nor is `stepFinished`
/// (no asynchronous fmi2DoStep).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    /// The importer's logger (NULL: stay silent).
    pub logger: Fmi2CallbackLogger,
    /// Not used.
    pub allocate_memory: Fmi2CallbackAllocateMemory,
    /// Not used.
    pub free_memory: Fmi2CallbackFreeMemory,
    /// Not used.
    pub step_finished: Fmi2StepFinished,
    /// Handed back to the logger.
    pub component_environment: Fmi2ComponentEnvironment,
}
