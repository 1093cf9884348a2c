//! C types of the FMI 2.0 headers (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`).

use std::ffi::{c_char, c_int, c_uint, c_void};

/// fmi2Component
pub type Fmi2Component = *mut c_void;
/// fmi2ComponentEnvironment
pub type Fmi2ComponentEnvironment = *mut c_void;
/// fmi2FMUstate
pub type Fmi2FmuState = *mut c_void;
/// fmi2ValueReference
pub type Fmi2ValueReference = c_uint;
/// fmi2Real
pub type Fmi2Real = f64;
/// fmi2Integer
pub type Fmi2Integer = c_int;
/// fmi2Boolean
pub type Fmi2Boolean = c_int;
/// fmi2String
pub type Fmi2String = *const c_char;
/// fmi2Byte
pub type Fmi2Byte = c_char;
/// fmi2Status (an enum in C, passed as int)
pub type Fmi2Status = c_int;
/// fmi2Type
pub type Fmi2Type = c_int;
/// fmi2StatusKind
pub type Fmi2StatusKind = c_int;

/// fmi2OK
pub const FMI2_OK: Fmi2Status = 0;
/// fmi2Warning
pub const FMI2_WARNING: Fmi2Status = 1;
/// fmi2Discard
pub const FMI2_DISCARD: Fmi2Status = 2;
/// fmi2Error
pub const FMI2_ERROR: Fmi2Status = 3;
/// fmi2Fatal
pub const FMI2_FATAL: Fmi2Status = 4;
/// fmi2CoSimulation
pub const FMI2_COSIMULATION: Fmi2Type = 1;
/// fmi2True
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// fmi2False
pub const FMI2_FALSE: Fmi2Boolean = 0;

/// fmi2CallbackLogger: C-variadic.
pub type Fmi2CallbackLogger = unsafe extern "C" fn(
    Fmi2ComponentEnvironment,
    Fmi2String,
    Fmi2Status,
    Fmi2String,
    Fmi2String,
    ...
);

/// fmi2CallbackFunctions
#[repr(C)]
pub struct Fmi2CallbackFunctions {
    /// logger
    pub logger: Option<Fmi2CallbackLogger>,
    /// allocateMemory (unused: flexfmu allocates with Rust's allocator)
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// freeMemory (unused)
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// stepFinished (unused: no asynchronous steps)
    pub step_finished: Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2Status)>,
    /// componentEnvironment, passed back to the logger
    pub component_environment: Fmi2ComponentEnvironment,
}

/// Maps a safe status to the C value.
pub fn to_c(status: crate::logging::Status) -> Fmi2Status {
    use crate::logging::Status;
    match status {
        Status::Ok => FMI2_OK,
        Status::Warning => FMI2_WARNING,
        Status::Discard => FMI2_DISCARD,
        Status::Error => FMI2_ERROR,
        Status::Fatal => FMI2_FATAL,
    }
}
