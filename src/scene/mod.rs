//! Scenes: what an FMU models. A TOML file names its body kind (`kind = "..."`, see
//! [`crate::kinds`]); the kind reads its tables strictly and declares the parameters
//! ([`params`]) and the inputs and outputs, from which the variable table and the model are
//! built. Tables several kinds share are in [`tables`].
//!
//! Scene files without a `kind` key (written before it existed) keep working: the kind is
//! then the one whose old rule matches (`[belt]` or `[[pulley]]`: `belt_drive`; element type
//! `"ancf_shear_2d"` or `"ancf_cable_2d"`: `beam_2d`; `"corotational_3d"`: `beam_3d`; a `[[pulley]]`
//! centre with three components: `belt_3d`; the tables outrank the element type; each kind
//! states its own rule in [`kinds::BodyKind::claims_legacy`]).

pub mod params;
pub mod tables;
pub(crate) mod validate;

pub use params::{ParamDef, ParamValues};
pub use tables::CommonTables;

use crate::kinds::{self, BodyKind, KindScene};
use crate::variables::IoVariable;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::sync::Arc;

/// A parsed and checked scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The kind's tables (they build the model).
    pub body: Arc<dyn KindScene>,
    /// The tables every kind has.
    pub common: CommonTables,
    /// The exact text it was parsed from (packaged into the FMU's `resources/`).
    pub text: String,
    /// Parameters the scene exposes, with its values as defaults.
    pub params: Vec<ParamDef>,
    /// Inputs and outputs the scene exposes.
    pub io: Vec<IoVariable>,
}

/// A scene that cannot be used; the message names the key and the problem.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{0}")]
pub struct SceneError(pub String);

/// The kind a scene file asks for: its `kind` key or, without one, the kind whose old rule
/// matches the tables.
fn select_kind(tables: &toml::Table) -> Result<&'static dyn BodyKind, String> {
    match tables.get("kind") {
        Some(toml::Value::String(name)) => kinds::by_name(name).ok_or_else(|| {
            format!(
                "kind = \"{name}\": unknown body kind; known kinds: {}",
                kinds::names()
            )
        }),
        Some(other) => Err(format!(
            "kind: must be a string naming the body kind ({}), not {}",
            kinds::names(),
            other.type_str()
        )),
        None => {
            let strength = |k: &&dyn BodyKind| k.claims_legacy(tables);
            let best = kinds::REGISTRY.iter().filter_map(strength).max();
            let claims: Vec<_> = kinds::REGISTRY
                .iter()
                .copied()
                .filter(|k| best.is_some() && strength(k) == best)
                .collect();
            match claims.as_slice() {
                [one] => Ok(*one),
                _ => Err(match kinds::legacy_element_type(tables) {
                    Some("ancf_cable_2d") => "element type \"ancf_cable_2d\" is the belt element: add [belt], [contact] and [[pulley]] tables (or kind = \"belt_drive\")".to_string(),
                    _ => format!(
                        "kind: missing, and the tables do not say which kind (files without the key give [element] type = \"ancf_shear_2d\" or \"ancf_cable_2d\" for beam_2d or \"corotational_3d\" for beam_3d, or [belt] and [[pulley]] tables for belt_drive); name the body kind with a top-level key kind = one of {}",
                        kinds::names()
                    ),
                }),
            }
        }
    }
}

/// Deserializes the tables of a scene of kind `kind` strictly: an unknown, misplaced,
/// missing or mistyped key is an error that names the key, its table, the kind and the line.
/// A table written as an array (`contact = [0.4]`, which serde would read by position) is
/// rejected too.
pub fn parse_strict<T: DeserializeOwned + Serialize>(
    text: &str,
    kind: &str,
) -> Result<T, Vec<String>> {
    let de = toml::de::Deserializer::parse(text).map_err(|e| vec![e.to_string()])?;
    let tables: T = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.inner();
        let line = inner
            .span()
            .map(|s| {
                format!(
                    " (line {})",
                    text[..s.start.min(text.len())].lines().count().max(1)
                )
            })
            .unwrap_or_default();
        let top: Option<toml::Table> = toml::from_str(text).ok();
        let place = match path.rsplit_once('.') {
            _ if path == "." || path.is_empty() => "at the top level".to_string(),
            Some((table, key)) => format!("key `{key}` in table [{table}]"),
            None => match top.as_ref().and_then(|t| t.get(&path)) {
                Some(toml::Value::Table(_)) => format!("table [{path}]"),
                Some(toml::Value::Array(a)) if a.iter().all(|v| v.is_table()) && !a.is_empty() => {
                    format!("table [[{path}]]")
                }
                _ => format!("key `{path}` at the top level"),
            },
        };
        vec![format!(
            "kind \"{kind}\", {place}: {}{line}",
            inner.message().trim_end()
        )]
    })?;
    // Compare the shape of the file with what was read: a table must be written as a table.
    let mut errs = Vec::new();
    if let (Ok(raw), Ok(read)) = (
        toml::from_str::<toml::Value>(text),
        toml::Value::try_from(&tables),
    ) {
        same_shape(&raw, &read, "", kind, &mut errs);
    }
    if errs.is_empty() {
        Ok(tables)
    } else {
        Err(errs)
    }
}

/// Records every place where `raw` (the file) has an array and `read` (the tables as the
/// kind read them) a table.
fn same_shape(
    raw: &toml::Value,
    read: &toml::Value,
    path: &str,
    kind: &str,
    errs: &mut Vec<String>,
) {
    use toml::Value::{Array, Table};
    match (raw, read) {
        (Array(_), Table(_)) => errs.push(format!(
            "kind \"{kind}\", table [{path}]: written as an array; write it as a table ([{path}] with key = value lines)"
        )),
        (Table(r), Table(t)) => {
            for (k, rv) in r {
                if let Some(tv) = t.get(k) {
                    let sub = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
                    same_shape(rv, tv, &sub, kind, errs);
                }
            }
        }
        (Array(r), Array(t)) if r.len() == t.len() => {
            for (i, (rv, tv)) in r.iter().zip(t).enumerate() {
                same_shape(rv, tv, &format!("{path}[{i}]"), kind, errs);
            }
        }
        _ => {}
    }
}

/// The top-level keys (tables) of a kind's scene struct `T`, read from its serde derive.
pub fn table_names<T: DeserializeOwned>() -> &'static [&'static str] {
    use serde::de::{self, Visitor};
    struct Names(Option<&'static [&'static str]>);
    impl<'de> de::Deserializer<'de> for &mut Names {
        type Error = de::value::Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            self.0 = Some(fields);
            Err(de::Error::custom("names read"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map enum
            identifier ignored_any
        }
    }
    let mut names = Names(None);
    let _ = T::deserialize(&mut names);
    names.0.unwrap_or(&[])
}

impl Scene {
    /// Parses and checks a scene from TOML text.
    pub fn from_toml(text: &str) -> Result<Self, SceneError> {
        let fail = |errs: Vec<String>| SceneError(format!("scene file: {}", errs.join("; ")));
        let tables: toml::Table = toml::from_str(text).map_err(|e| fail(vec![e.to_string()]))?;
        let kind = select_kind(&tables).map_err(|e| fail(vec![e]))?;
        let body = kind.parse(text).map_err(|errs| {
            let named = |e: String| match e.starts_with("kind ") {
                true => e,
                false => format!("kind \"{}\", {e}", kind.name()),
            };
            fail(errs.into_iter().map(named).collect())
        })?;
        let common: CommonTables = toml::from_str(text).map_err(|e| fail(vec![e.to_string()]))?;
        validate::check_common(&common).map_err(fail)?;
        let mut params = body.params().map_err(|e| fail(vec![e]))?;
        params.extend(params::solver_params(&common.solver).map_err(|e| fail(vec![e]))?);
        let io = body.io();
        validate::check_names(&params, &io).map_err(fail)?;
        ParamValues::defaults(&params)
            .validate(&params)
            .map_err(fail)?;
        Ok(Self {
            body,
            common,
            text: text.to_string(),
            params,
            io,
        })
    }

    /// Reads and parses a scene file.
    pub fn from_path(path: &std::path::Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SceneError(format!("cannot read scene {}: {e}", path.display())))?;
        Self::from_toml(&text).map_err(|e| SceneError(format!("{}: {}", path.display(), e.0)))
    }

    /// The body kind.
    pub fn kind(&self) -> &'static dyn BodyKind {
        self.body.kind()
    }

    /// The kind's own tables, if they are of type `T` (tests and tools).
    pub fn tables<T: 'static>(&self) -> Option<&T> {
        self.body.as_any().downcast_ref::<T>()
    }

    /// Model name (also the model identifier).
    pub fn model_name(&self) -> &str {
        &self.common.fmu.model_name
    }

    /// Checks parameter values (from the importer) against their definitions.
    pub fn validate_params(&self, values: &ParamValues) -> Result<(), String> {
        values.validate(&self.params).map_err(|e| e.join("; "))
    }
}
