//! The C types of `fmi2TypesPlatform.h` and `fmi2FunctionTypes.h` (FMI 2.0
//! section 2.1.2 - 2.1.4), laid out for the C ABI.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Fmi2Component = *mut c_void;
pub type Fmi2ComponentEnvironment = *mut c_void;
pub type Fmi2FmuState = *mut c_void;
pub type Fmi2ValueReference = c_uint;
pub type Fmi2Real = f64;
pub type Fmi2Integer = c_int;
pub type Fmi2Boolean = c_int;
pub type Fmi2Char = c_char;
pub type Fmi2String = *const Fmi2Char;
pub type Fmi2Byte = c_char;

pub const FMI2_TRUE: Fmi2Boolean = 1;
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// `fmi2Status`. Only ever produced by us (incoming enum values are taken
/// as `c_int` and checked, since an out-of-range Rust enum would be UB).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Fmi2Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

impl Fmi2Status {
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
pub const FMI2_CO_SIMULATION: c_int = 1;

/// `fmi2StatusKind` values (passed as `c_int`).
pub const FMI2_DO_STEP_STATUS: c_int = 0;
pub const FMI2_PENDING_STATUS: c_int = 1;
pub const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
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
pub type Fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
pub type Fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
pub type Fmi2StepFinished = Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2Status)>;

/// `fmi2CallbackFunctions`. Copied by value in fmi2Instantiate (the importer
/// need not keep its struct alive). The memory functions are never used
/// (`canNotUseMemoryManagementFunctions="true"`), nor is `stepFinished`
/// (no asynchronous fmi2DoStep).
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    pub logger: Fmi2CallbackLogger,
    pub allocate_memory: Fmi2CallbackAllocateMemory,
    pub free_memory: Fmi2CallbackFreeMemory,
    pub step_finished: Fmi2StepFinished,
    pub component_environment: Fmi2ComponentEnvironment,
}
