//! Checks of a scene file common to all kinds: names, experiment, uniqueness of variable names.
//! Kind-specific checks live with the kind (e.g. [`crate::kinds::beam_2d::scene::check`]).

use super::params::ParamDef;
use super::tables::CommonTables;
use crate::variables::IoVariable;
use std::collections::BTreeSet;

/// Whether `s` is a valid identifier (letter, then letters, digits, '_').
pub fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Records the outputs a probe `key` lists twice.
pub fn reject_repeated<T: std::fmt::Debug>(key: &str, outputs: &[T], errs: &mut Vec<String>) {
    let mut seen = BTreeSet::new();
    for q in outputs {
        if !seen.insert(format!("{q:?}")) {
            errs.push(format!("{key}.outputs: {q:?} listed twice"));
        }
    }
}

/// Records a problem when the position `at` of the entry `key` is not a fraction in [0, 1] of
/// `what` (e.g. "the length").
pub fn check_fraction(key: &str, at: f64, what: &str, errs: &mut Vec<String>) {
    if !(0.0..=1.0).contains(&at) {
        errs.push(format!(
            "{key}.at = {at}: must lie in [0, 1] (a fraction of {what})"
        ));
    }
}

/// Records a problem when the name of the entry `key` is not an identifier.
pub fn check_identifier(key: &str, name: &str, errs: &mut Vec<String>) {
    if !is_identifier(name) {
        errs.push(format!(
            "{key}.name = \"{name}\": must start with a letter and contain only letters, digits and '_'"
        ));
    }
}

/// Problems of the `[fmu]` and `[experiment]` tables.
pub fn check_common(s: &CommonTables) -> Result<(), Vec<String>> {
    let mut errs = Vec::new();
    if !is_identifier(&s.fmu.model_name) {
        errs.push(format!(
            "fmu.model_name = \"{}\": must start with a letter and contain only letters, digits and '_' (it names the shared library)",
            s.fmu.model_name
        ));
    }
    let e = &s.experiment;
    for (k, v) in [
        ("experiment.start_time", e.start_time),
        ("experiment.stop_time", e.stop_time),
        ("experiment.step_size", e.step_size),
    ] {
        if !v.is_finite() {
            errs.push(format!("{k} = {v}: not a finite number"));
        }
    }
    if e.stop_time <= e.start_time {
        errs.push(format!(
            "experiment.stop_time = {} must be greater than experiment.start_time = {}",
            e.stop_time, e.start_time
        ));
    }
    if e.step_size <= 0.0 {
        errs.push(format!(
            "experiment.step_size = {} must be positive",
            e.step_size
        ));
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}

/// Every variable name is unique (a load or probe named like a parameter group would clash).
pub fn check_names(params: &[ParamDef], io: &[IoVariable]) -> Result<(), Vec<String>> {
    let mut seen = BTreeSet::new();
    let mut errs = Vec::new();
    for name in params
        .iter()
        .map(|p| p.name.to_string())
        .chain(io.iter().map(|v| v.name.clone()))
    {
        if !seen.insert(name.clone()) {
            errs.push(format!(
                "variable {name} is declared twice: rename one of the [[loads]], [[probes]] or [[motions]] entries named \"{}\"",
                name.split('.').next().unwrap_or(&name)
            ));
        }
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}
