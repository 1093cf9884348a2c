//! The 34 exported FMI 2.0 Co-Simulation functions. Each one: checks the component handle and
//! pointer arguments, runs the safe implementation inside `catch_unwind`, and returns the
//! status as the C enum. No global mutable state: everything lives in the instance.
#![allow(non_snake_case)]
#![allow(clippy::missing_safety_doc)]

use super::logger::c_sink;
use super::state_machine::Call;
use super::types::*;
use crate::instance::{Instance, StatusKind, resource_dir_from_uri};
use crate::logging::Status;
use crate::variables::{Value, VarType};
use std::ffi::{CStr, c_char, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr;

/// Marks a live component handle ("flexfmu2"); zeroed when the instance is freed so that a
/// stale or foreign pointer is rejected instead of used.
const MAGIC: u64 = 0x666c_6578_666d_7532;

#[repr(C)]
struct Handle {
    magic: u64,
    inst: Instance,
}

/// The live handle behind `c`, if it is one.
///
/// SAFETY: `c` is null or a pointer returned by fmi2Instantiate; a freed or foreign pointer
/// is detected through the magic number as far as reading 8 bytes from it is possible.
unsafe fn handle<'a>(c: Fmi2Component) -> Option<&'a mut Handle> {
    if c.is_null() || !(c as usize).is_multiple_of(std::mem::align_of::<Handle>()) {
        return None;
    }
    let h = c as *mut Handle;
    // SAFETY: non-null and aligned; the importer passes what fmi2Instantiate returned.
    unsafe {
        if ptr::read_volatile(&(*h).magic) != MAGIC {
            return None;
        }
        Some(&mut *h)
    }
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".into()
    }
}

/// Runs `f` on the instance behind `c`, converting a panic into fmi2Fatal.
fn guarded(c: Fmi2Component, f: impl FnOnce(&mut Instance) -> Status) -> Fmi2Status {
    // SAFETY: see `handle`.
    let Some(h) = (unsafe { handle(c) }) else {
        return FMI2_ERROR;
    };
    match catch_unwind(AssertUnwindSafe(|| f(&mut h.inst))) {
        Ok(s) => to_c(s),
        Err(p) => {
            let text = panic_text(p.as_ref());
            let _ = catch_unwind(AssertUnwindSafe(|| {
                h.inst.fatal(format!("internal error (panic): {text}"))
            }));
            FMI2_FATAL
        }
    }
}

/// A slice from a C array; `None` if the pointer is null while `n > 0` or `n` is absurd.
///
/// SAFETY: a non-null `p` points to `n` valid elements (the FMI contract).
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    if p.is_null() || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: as documented.
    Some(unsafe { std::slice::from_raw_parts(p, n) })
}

/// Mutable variant of [`slice`].
///
/// SAFETY: a non-null `p` points to `n` writable elements.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        return Some(&mut []);
    }
    if p.is_null() || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: as documented.
    Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A C string as UTF-8 (lossy), `None` for null.
///
/// SAFETY: a non-null `s` is a valid NUL-terminated string.
unsafe fn text<'a>(s: *const c_char) -> Option<std::borrow::Cow<'a, str>> {
    if s.is_null() {
        None
    } else {
        // SAFETY: as documented.
        Some(unsafe { CStr::from_ptr(s) }.to_string_lossy())
    }
}

fn null_args(inst: &mut Instance, call: Call) -> Status {
    inst.error(format!(
        "{}: a required pointer argument is NULL",
        call.name()
    ))
}

fn status_kind(kind: Fmi2StatusKind) -> Option<StatusKind> {
    match kind {
        0 => Some(StatusKind::DoStepStatus),
        1 => Some(StatusKind::PendingStatus),
        2 => Some(StatusKind::LastSuccessfulTime),
        3 => Some(StatusKind::Terminated),
        _ => None,
    }
}

// ---------------------------------------------------------------------------------------------
// Inquiry, creation and destruction
// ---------------------------------------------------------------------------------------------

/// fmi2GetTypesPlatform
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// fmi2GetVersion
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// fmi2SetDebugLogging
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n_categories: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract for the categories array.
        let Some(cats) = (unsafe { slice(categories, n_categories) }) else {
            return null_args(inst, Call::SetDebugLogging);
        };
        let mut names = Vec::with_capacity(cats.len());
        for &p in cats {
            // SAFETY: each entry is a C string or NULL.
            match unsafe { text(p) } {
                Some(s) => names.push(s.into_owned()),
                None => return null_args(inst, Call::SetDebugLogging),
            }
        }
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        inst.set_debug_logging(logging_on != FMI2_FALSE, &refs)
    })
}

/// fmi2Instantiate (Co-Simulation only). Returns NULL, after logging why, on any problem.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: Fmi2String,
    fmu_type: Fmi2Type,
    guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let run = || -> Fmi2Component {
        if functions.is_null() {
            return ptr::null_mut();
        }
        // SAFETY: non-null; the importer passes a valid struct that outlives the instance.
        let cb = unsafe { &*functions };
        // SAFETY: FMI contract: C strings or NULL.
        let name = unsafe { text(instance_name) }.map(|s| s.into_owned());
        // SAFETY: the callbacks stay valid while the instance lives (FMI contract).
        let mut sink = unsafe {
            c_sink(
                cb.logger,
                cb.component_environment,
                name.as_deref().unwrap_or(""),
            )
        };
        let mut fail = |msg: String| -> Fmi2Component {
            sink(
                Status::Error,
                "logStatusError",
                &format!("fmi2Instantiate: {msg}"),
            );
            ptr::null_mut()
        };
        let Some(name) = name else {
            return fail("instanceName is NULL".into());
        };
        if fmu_type != FMI2_COSIMULATION {
            return fail(format!(
                "fmuType = {fmu_type}: this FMU implements Co-Simulation only (fmi2CoSimulation = 1)"
            ));
        }
        // SAFETY: as above.
        let Some(guid) = (unsafe { text(guid) }) else {
            return fail("fmuGUID is NULL".into());
        };
        // SAFETY: as above.
        let Some(uri) = (unsafe { text(resource_location) }) else {
            return fail(
                "fmuResourceLocation is NULL; flexfmu reads its scene from resources/scene.toml"
                    .into(),
            );
        };
        let dir = match resource_dir_from_uri(&uri) {
            Ok(d) => d,
            Err(e) => return fail(e),
        };
        // SAFETY: as above.
        let inst_sink = unsafe { c_sink(cb.logger, cb.component_environment, &name) };
        match Instance::new(&name, &guid, &dir, logging_on != FMI2_FALSE, inst_sink) {
            Ok(inst) => Box::into_raw(Box::new(Handle { magic: MAGIC, inst })) as *mut c_void,
            Err(e) => fail(e),
        }
    };
    catch_unwind(AssertUnwindSafe(run)).unwrap_or(ptr::null_mut())
}

/// fmi2FreeInstance
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    // SAFETY: see `handle`.
    if let Some(h) = unsafe { handle(c) } {
        h.magic = 0;
        // SAFETY: the pointer came from Box::into_raw in fmi2Instantiate and is freed once
        // (the magic is now zero).
        let boxed = unsafe { Box::from_raw(c as *mut Handle) };
        let _ = catch_unwind(AssertUnwindSafe(move || drop(boxed)));
    }
}

// ---------------------------------------------------------------------------------------------
// Initialization, termination, reset
// ---------------------------------------------------------------------------------------------

/// fmi2SetupExperiment
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    tolerance_defined: Fmi2Boolean,
    tolerance: Fmi2Real,
    start_time: Fmi2Real,
    stop_time_defined: Fmi2Boolean,
    stop_time: Fmi2Real,
) -> Fmi2Status {
    guarded(c, |inst| {
        inst.setup_experiment(
            (tolerance_defined != FMI2_FALSE).then_some(tolerance),
            start_time,
            (stop_time_defined != FMI2_FALSE).then_some(stop_time),
        )
    })
}

/// fmi2EnterInitializationMode
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    guarded(c, |inst| inst.enter_initialization_mode())
}

/// fmi2ExitInitializationMode
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    guarded(c, |inst| inst.exit_initialization_mode())
}

/// fmi2Terminate
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    guarded(c, |inst| inst.terminate())
}

/// fmi2Reset
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    guarded(c, |inst| inst.reset())
}

// ---------------------------------------------------------------------------------------------
// Getting and setting variable values
// ---------------------------------------------------------------------------------------------

fn get_values<T>(
    c: Fmi2Component,
    call: Call,
    ty: VarType,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut T,
    conv: fn(Value) -> T,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: `vr` and `value` hold `nvr` elements.
        let (Some(vrs), Some(out)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(value, nvr) })
        else {
            return null_args(inst, call);
        };
        inst.get(call, ty, vrs, &mut |i, v| out[i] = conv(v))
    })
}

fn set_values<T: Copy>(
    c: Fmi2Component,
    call: Call,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const T,
    conv: fn(T) -> Value,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: `vr` and `value` hold `nvr` elements.
        let (Some(vrs), Some(vals)) = (unsafe { slice(vr, nvr) }, unsafe { slice(value, nvr) })
        else {
            return null_args(inst, call);
        };
        let vals: Vec<Value> = vals.iter().map(|&v| conv(v)).collect();
        inst.set(call, vrs, &vals)
    })
}

fn real_of(v: Value) -> f64 {
    match v {
        Value::Real(x) => x,
        _ => f64::NAN,
    }
}
fn int_of(v: Value) -> Fmi2Integer {
    match v {
        Value::Integer(x) => x,
        _ => 0,
    }
}
fn bool_of(v: Value) -> Fmi2Boolean {
    match v {
        Value::Boolean(true) => FMI2_TRUE,
        _ => FMI2_FALSE,
    }
}

/// fmi2GetReal
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    get_values(c, Call::GetReal, VarType::Real, vr, nvr, value, real_of)
}

/// fmi2GetInteger
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    get_values(
        c,
        Call::GetInteger,
        VarType::Integer,
        vr,
        nvr,
        value,
        int_of,
    )
}

/// fmi2GetBoolean
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    get_values(
        c,
        Call::GetBoolean,
        VarType::Boolean,
        vr,
        nvr,
        value,
        bool_of,
    )
}

/// fmi2GetString: this FMU has no String variables.
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract.
        let (Some(vrs), Some(_)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(value, nvr) })
        else {
            return null_args(inst, Call::GetString);
        };
        inst.no_strings(Call::GetString, vrs)
    })
}

/// fmi2SetReal
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Real,
) -> Fmi2Status {
    set_values(c, Call::SetReal, vr, nvr, value, Value::Real)
}

/// fmi2SetInteger
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Integer,
) -> Fmi2Status {
    set_values(c, Call::SetInteger, vr, nvr, value, Value::Integer)
}

/// fmi2SetBoolean
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    set_values(c, Call::SetBoolean, vr, nvr, value, |b| {
        Value::Boolean(b != FMI2_FALSE)
    })
}

/// fmi2SetString: this FMU has no String variables.
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract.
        let (Some(vrs), Some(_)) = (unsafe { slice(vr, nvr) }, unsafe { slice(value, nvr) }) else {
            return null_args(inst, Call::SetString);
        };
        inst.no_strings(Call::SetString, vrs)
    })
}

// ---------------------------------------------------------------------------------------------
// FMU state and derivatives
// ---------------------------------------------------------------------------------------------

/// Marks a live FMU state ("flexstat"); zeroed when freed.
const STATE_MAGIC: u64 = 0x666c_6578_7374_6174;

/// An FMU state handed to the importer: the serialized bytes.
#[repr(C)]
struct StateBox {
    magic: u64,
    bytes: Vec<u8>,
}

/// The live state behind `p`, if it is one.
///
/// SAFETY: `p` is null or a pointer returned by fmi2GetFMUstate / fmi2DeSerializeFMUstate; a
/// freed or foreign pointer is detected through the magic number as far as reading 8 bytes
/// from it is possible.
unsafe fn state_box<'a>(p: Fmi2FmuState) -> Option<&'a mut StateBox> {
    if p.is_null() || !(p as usize).is_multiple_of(std::mem::align_of::<StateBox>()) {
        return None;
    }
    let b = p as *mut StateBox;
    // SAFETY: non-null and aligned; the importer passes what we returned.
    unsafe {
        if ptr::read_volatile(&(*b).magic) != STATE_MAGIC {
            return None;
        }
        Some(&mut *b)
    }
}

fn bad_state(inst: &mut Instance, call: Call) -> Status {
    inst.error(format!(
        "{}: the FMUstate argument is not a live FMU state of flexfmu",
        call.name()
    ))
}

/// fmi2GetFMUstate: a new state, or the given one updated in place.
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    guarded(c, |inst| {
        if state.is_null() {
            return null_args(inst, Call::GetFmuState);
        }
        let bytes = match inst.save_fmu_state(Call::GetFmuState) {
            Ok(b) => b,
            Err(s) => return s,
        };
        // SAFETY: non-null out-pointer (FMI contract).
        let existing = unsafe { *state };
        if existing.is_null() {
            let b = Box::new(StateBox {
                magic: STATE_MAGIC,
                bytes,
            });
            // SAFETY: as above.
            unsafe { *state = Box::into_raw(b) as Fmi2FmuState };
            return Status::Ok;
        }
        // SAFETY: see `state_box`.
        match unsafe { state_box(existing) } {
            Some(b) => {
                b.bytes = bytes;
                Status::Ok
            }
            None => bad_state(inst, Call::GetFmuState),
        }
    })
}

/// fmi2SetFMUstate
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: see `state_box`.
        match unsafe { state_box(state) } {
            Some(b) => {
                let bytes = std::mem::take(&mut b.bytes);
                let s = inst.restore_fmu_state(&bytes);
                b.bytes = bytes;
                s
            }
            None => bad_state(inst, Call::SetFmuState),
        }
    })
}

/// fmi2FreeFMUstate: frees the state and sets `*state` to NULL (a NULL state is a no-op).
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    guarded(c, |inst| {
        if let Err(s) = inst.check(Call::FreeFmuState) {
            return s;
        }
        if state.is_null() {
            return null_args(inst, Call::FreeFmuState);
        }
        // SAFETY: non-null out-pointer.
        let p = unsafe { *state };
        if p.is_null() {
            return Status::Ok;
        }
        // SAFETY: see `state_box`.
        match unsafe { state_box(p) } {
            Some(b) => {
                b.magic = 0;
                // SAFETY: allocated by Box::into_raw here and freed once (magic now zero).
                drop(unsafe { Box::from_raw(p as *mut StateBox) });
                // SAFETY: as above.
                unsafe { *state = ptr::null_mut() };
                Status::Ok
            }
            None => bad_state(inst, Call::FreeFmuState),
        }
    })
}

/// fmi2SerializedFMUstateSize
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2Status {
    guarded(c, |inst| {
        if let Err(s) = inst.check(Call::SerializedFmuStateSize) {
            return s;
        }
        if size.is_null() {
            return null_args(inst, Call::SerializedFmuStateSize);
        }
        // SAFETY: see `state_box`.
        match unsafe { state_box(state) } {
            Some(b) => {
                // SAFETY: non-null out-pointer.
                unsafe { *size = b.bytes.len() };
                Status::Ok
            }
            None => bad_state(inst, Call::SerializedFmuStateSize),
        }
    })
}

/// fmi2SerializeFMUstate: copies the state into a buffer of at least the serialized size.
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2FmuState,
    bytes: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    guarded(c, |inst| {
        if let Err(s) = inst.check(Call::SerializeFmuState) {
            return s;
        }
        // SAFETY: see `state_box`.
        let Some(b) = (unsafe { state_box(state) }) else {
            return bad_state(inst, Call::SerializeFmuState);
        };
        let n = b.bytes.len();
        if size < n {
            return inst.error(format!(
                "fmi2SerializeFMUstate: buffer of {size} bytes, the state needs {n} (fmi2SerializedFMUstateSize)"
            ));
        }
        // SAFETY: FMI contract: `bytes` holds `size` >= n writable bytes.
        let Some(out) = (unsafe { slice_mut(bytes as *mut u8, n) }) else {
            return null_args(inst, Call::SerializeFmuState);
        };
        out.copy_from_slice(&b.bytes);
        Status::Ok
    })
}

/// fmi2DeSerializeFMUstate: checks the bytes (format, version, GUID, checksum) and makes a new
/// FMU state of them.
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    bytes: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: `bytes` holds `size` bytes.
        let Some(data) = (unsafe { slice(bytes as *const u8, size) }) else {
            return null_args(inst, Call::DeSerializeFmuState);
        };
        if state.is_null() {
            return null_args(inst, Call::DeSerializeFmuState);
        }
        if let Err(s) = inst.check_fmu_state(Call::DeSerializeFmuState, data) {
            return s;
        }
        let b = Box::new(StateBox {
            magic: STATE_MAGIC,
            bytes: data.to_vec(),
        });
        // SAFETY: non-null out-pointer.
        unsafe { *state = Box::into_raw(b) as Fmi2FmuState };
        Status::Ok
    })
}

/// fmi2GetDirectionalDerivative
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    unknown: *const Fmi2ValueReference,
    n_unknown: usize,
    known: *const Fmi2ValueReference,
    n_known: usize,
    dv_known: *const Fmi2Real,
    dv_unknown: *mut Fmi2Real,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: arrays of the given lengths.
        let (Some(u), Some(k), Some(dk), Some(du)) = (unsafe {
            (
                slice(unknown, n_unknown),
                slice(known, n_known),
                slice(dv_known, n_known),
                slice_mut(dv_unknown, n_unknown),
            )
        }) else {
            return null_args(inst, Call::GetDirectionalDerivative);
        };
        inst.get_directional_derivative(u, k, dk, du)
    })
}

/// fmi2SetRealInputDerivatives
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *const Fmi2Real,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: arrays of length `nvr`.
        let (Some(v), Some(o), Some(x)) =
            (unsafe { (slice(vr, nvr), slice(order, nvr), slice(value, nvr)) })
        else {
            return null_args(inst, Call::SetRealInputDerivatives);
        };
        inst.set_real_input_derivatives(v, o, x)
    })
}

/// fmi2GetRealOutputDerivatives
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    order: *const Fmi2Integer,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    guarded(c, |inst| {
        // SAFETY: FMI contract: arrays of length `nvr`.
        let (Some(v), Some(o), Some(x)) =
            (unsafe { (slice(vr, nvr), slice(order, nvr), slice_mut(value, nvr)) })
        else {
            return null_args(inst, Call::GetRealOutputDerivatives);
        };
        inst.get_real_output_derivatives(v, o, x)
    })
}

// ---------------------------------------------------------------------------------------------
// Co-Simulation: stepping and status
// ---------------------------------------------------------------------------------------------

/// fmi2DoStep
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: Fmi2Real,
    communication_step_size: Fmi2Real,
    _no_set_fmu_state_prior: Fmi2Boolean,
) -> Fmi2Status {
    guarded(c, |inst| {
        inst.do_step(current_communication_point, communication_step_size)
    })
}

/// fmi2CancelStep
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    guarded(c, |inst| inst.cancel_step())
}

fn get_status_value<T>(
    c: Fmi2Component,
    call: Call,
    kind: Fmi2StatusKind,
    value: *mut T,
    f: impl FnOnce(&mut Instance, StatusKind) -> Result<T, Status>,
) -> Fmi2Status {
    guarded(c, |inst| {
        if value.is_null() {
            return null_args(inst, call);
        }
        let Some(kind) = status_kind(kind) else {
            return inst.error(format!("{}: unknown fmi2StatusKind {kind}", call.name()));
        };
        match f(inst, kind) {
            Ok(v) => {
                // SAFETY: non-null pointer to a writable T (FMI contract).
                unsafe { value.write(v) };
                Status::Ok
            }
            Err(s) => s,
        }
    })
}

/// fmi2GetStatus
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    get_status_value(c, Call::GetStatus, kind, value, |i, k| {
        i.get_status(k).map(to_c)
    })
}

/// fmi2GetRealStatus
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Real,
) -> Fmi2Status {
    get_status_value(c, Call::GetRealStatus, kind, value, |i, k| {
        i.get_real_status(k)
    })
}

/// fmi2GetIntegerStatus
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Integer,
) -> Fmi2Status {
    get_status_value(c, Call::GetIntegerStatus, kind, value, |i, k| {
        i.get_integer_status(k)
    })
}

/// fmi2GetBooleanStatus
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    get_status_value(c, Call::GetBooleanStatus, kind, value, |i, k| {
        i.get_boolean_status(k)
            .map(|b| if b { FMI2_TRUE } else { FMI2_FALSE })
    })
}

/// fmi2GetStringStatus
#[must_use]
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2String,
) -> Fmi2Status {
    get_status_value(c, Call::GetStringStatus, kind, value, |i, k| {
        i.get_string_status(k).map(|s| s.as_ptr())
    })
}
