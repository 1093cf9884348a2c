//! Checks of a scene file beyond its syntax: names, locations, consistency. Parameter values
//! are checked by [`super::params::ParamValues::validate`].

use super::file::{SceneFile, SupportKind};
use std::collections::BTreeSet;

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Reserved prefixes: a load or probe may not take a parameter group's name.
const RESERVED: &[&str] = &[
    "material", "geometry", "mesh", "element", "solver", "gravity", "energy",
];

/// All problems of the scene, each naming its key.
pub fn check(s: &SceneFile) -> Result<(), Vec<String>> {
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
    if !s.geometry.origin.iter().all(|v| v.is_finite()) || !s.geometry.angle_deg.is_finite() {
        errs.push("geometry.origin / geometry.angle_deg: must be finite numbers".into());
    }

    let mut names = BTreeSet::new();
    let mut name_ok = |key: String, name: &str, errs: &mut Vec<String>| {
        if !is_identifier(name) {
            errs.push(format!(
                "{key}.name = \"{name}\": must start with a letter and contain only letters, digits and '_'"
            ));
        } else if RESERVED.contains(&name) {
            errs.push(format!("{key}.name = \"{name}\": reserved for parameters"));
        } else if !names.insert(name.to_string()) {
            errs.push(format!("{key}.name = \"{name}\": used twice"));
        }
    };
    let at_ok = |key: String, at: f64, errs: &mut Vec<String>| {
        if !(0.0..=1.0).contains(&at) {
            errs.push(format!(
                "{key}.at = {at}: must lie in [0, 1] (a fraction of the length)"
            ));
        }
    };
    for (i, sup) in s.supports.iter().enumerate() {
        let key = format!("supports[{i}]");
        at_ok(key.clone(), sup.at, &mut errs);
        match (sup.kind, sup.fixed) {
            (SupportKind::Roller, None) => errs.push(format!(
                "{key}.fixed: a roller needs the fixed direction, \"x\" or \"y\""
            )),
            (SupportKind::Clamp | SupportKind::Pin, Some(_)) => errs.push(format!(
                "{key}.fixed: only a roller takes a fixed direction"
            )),
            _ => {}
        }
    }
    for (i, l) in s.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        name_ok(key.clone(), &l.name, &mut errs);
        at_ok(key.clone(), l.at, &mut errs);
        if !l.fx.is_finite() || !l.fy.is_finite() {
            errs.push(format!("{key}: fx and fy must be finite"));
        }
    }
    for (i, p) in s.probes.iter().enumerate() {
        let key = format!("probes[{i}]");
        name_ok(key.clone(), &p.name, &mut errs);
        at_ok(key.clone(), p.at, &mut errs);
        if p.outputs.is_empty() {
            errs.push(format!(
                "{key}.outputs: empty; list at least one of x, y, vx, vy"
            ));
        }
        let mut seen = BTreeSet::new();
        for q in &p.outputs {
            if !seen.insert(format!("{q:?}")) {
                errs.push(format!("{key}.outputs: {q:?} listed twice"));
            }
        }
    }
    if errs.is_empty() { Ok(()) } else { Err(errs) }
}
