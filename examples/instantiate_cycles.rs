//! Repeated instantiate / initialize / step / FMU-state / free cycles through the C ABI, for a
//! leak check under valgrind (`pytests/test_importers.py::test_no_leaks`):
//! `cargo run --release --example instantiate_cycles -- <resources dir> <guid> [cycles]`.

use flexfmu::fmi2::exports::*;
use flexfmu::fmi2::types::*;
use std::ffi::{CString, c_char};
use std::ptr;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: instantiate_cycles <resources dir> <guid> [cycles]");
        std::process::exit(2);
    }
    let uri = CString::new(format!("file://{}", args[1])).unwrap();
    let guid = CString::new(args[2].clone()).unwrap();
    let cycles: usize = args.get(3).map_or(20, |s| s.parse().unwrap());
    let cb = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: ptr::null_mut(),
    };
    let name = c"cycle";
    let mut bad = 0;
    for _ in 0..cycles {
        // SAFETY: valid arguments per the FMI signatures.
        unsafe {
            let c = fmi2Instantiate(
                name.as_ptr(),
                FMI2_COSIMULATION,
                guid.as_ptr(),
                uri.as_ptr(),
                &cb,
                0,
                0,
            );
            assert!(!c.is_null(), "instantiation failed");
            bad += (fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0) != FMI2_OK) as i32;
            bad += (fmi2EnterInitializationMode(c) != FMI2_OK) as i32;
            bad += (fmi2ExitInitializationMode(c) != FMI2_OK) as i32;
            let mut state: Fmi2FmuState = ptr::null_mut();
            for k in 0..5 {
                bad += (fmi2DoStep(c, k as f64 * 1e-3, 1e-3, 1) != FMI2_OK) as i32;
                bad += (fmi2GetFMUstate(c, &mut state) != FMI2_OK) as i32;
            }
            let mut size = 0;
            bad += (fmi2SerializedFMUstateSize(c, state, &mut size) != FMI2_OK) as i32;
            let mut buf = vec![0u8; size];
            bad += (fmi2SerializeFMUstate(c, state, buf.as_mut_ptr() as *mut c_char, size)
                != FMI2_OK) as i32;
            let mut copy: Fmi2FmuState = ptr::null_mut();
            bad += (fmi2DeSerializeFMUstate(c, buf.as_ptr() as *const c_char, size, &mut copy)
                != FMI2_OK) as i32;
            bad += (fmi2SetFMUstate(c, copy) != FMI2_OK) as i32;
            bad += (fmi2FreeFMUstate(c, &mut copy) != FMI2_OK) as i32;
            bad += (fmi2FreeFMUstate(c, &mut state) != FMI2_OK) as i32;
            // an error path too: unknown value reference, then reset
            let vr = [9999u32];
            let mut x = [0.0];
            bad += (fmi2GetReal(c, vr.as_ptr(), 1, x.as_mut_ptr()) != FMI2_ERROR) as i32;
            bad += (fmi2Reset(c) != FMI2_OK) as i32;
            fmi2FreeInstance(c);
        }
    }
    println!("{cycles} cycles, {bad} unexpected statuses");
    std::process::exit(if bad == 0 { 0 } else { 1 });
}
