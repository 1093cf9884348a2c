//! The importer's logger, called with the caller's `componentEnvironment` and a "%s" format so
//! that no message text is ever interpreted as a format string.

use super::types::{Fmi2CallbackLogger, Fmi2ComponentEnvironment, to_c};
use crate::instance::LogSink;
use crate::logging::Status;
use std::ffi::CString;

fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no interior NUL after replacement")
}

/// A log sink that forwards to a C logger. `None` logger: messages are dropped.
///
/// # Safety
/// `logger` and `env` must stay valid for as long as the sink is used (the importer guarantees
/// this for the lifetime of the instance, FMI 2.0 section 2.1.5).
pub unsafe fn c_sink(
    logger: Option<Fmi2CallbackLogger>,
    env: Fmi2ComponentEnvironment,
    instance_name: &str,
) -> LogSink {
    let name = c_string(instance_name);
    Box::new(move |status: Status, category: &str, msg: &str| {
        if let Some(log) = logger {
            let cat = c_string(category);
            let text = c_string(msg);
            // SAFETY: `logger` and `env` are valid (contract of `c_sink`); all strings are valid
            // NUL-terminated C strings that outlive the call; "%s" consumes exactly one
            // `char*` argument.
            unsafe {
                log(
                    env,
                    name.as_ptr(),
                    to_c(status),
                    cat.as_ptr(),
                    c"%s".as_ptr(),
                    text.as_ptr(),
                );
            }
        }
    })
}
