//! Scene mutation test (issue 9, item 2: strict scenes).
//!
//! Every shipped scene (`scenes/*.toml`) is parsed into a TOML table, mutated at random (delete,
//! duplicate, retype, misspell and move keys, extreme numbers, unknown tables), written back to
//! text and given to `flexfmu check` ([`flexfmu::cli::check_scene`], the very function the
//! command calls) under `catch_unwind` in a watchdog thread. Properties:
//! - it never panics and never hangs ([`HANG_LIMIT`]);
//! - it accepts the scene, or its message names the mutated key and the table that holds it
//!   (for a deleted key the missing key; for a moved key the key; for an extreme number the key,
//!   e.g. in the parameter name `material.E`);
//! - it rejects what no scene of any kind may contain (a misspelled key whose new name no
//!   shipped scene uses, an unknown table, a plain value or unknown table at the top level,
//!   `nan` or `inf`), naming also the kind of the scene for an unknown key or table.
//!
//! Each mutation class is its own test; within it every scene gets [`CASES`] cases from a seed
//! derived from the class and scene names (override: `FLEXFMU_SCENE_MUTATION_CASES`,
//! `FLEXFMU_SCENE_MUTATION_SEED`). A failing case is shrunk by proptest and printed with the
//! mutated scene text and the message, together with the failures of the other scenes of the
//! class. `FLEXFMU_SCENE_MUTATION_SURVEY=1` runs every case without stopping or shrinking and
//! prints the failures by category and kind with an example each (run with `--nocapture`).
//! `tables_of_other_scenes` adds every top-level table of every other shipped scene, and the
//! plain regression tests at the end are the silent cases issue 9 names.

use flexfmu::cli::{self, CheckSummary};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};
use toml::{Table, Value};

/// Cases per scene and mutation class (10 scenes x 7 classes x 256 cases: about 18,000 checks).
const CASES: u32 = 256;
/// A check that takes longer than this is a hang (the shipped scenes take milliseconds).
const HANG_LIMIT: Duration = Duration::from_secs(30);
/// An accepted scene with an Integer parameter (element or point count) above this is not built:
/// the scene checks accept up to 1,000,000 elements, whose model build would take the whole
/// time budget of the test. Such cases are counted and reported as "not built".
const BUILD_GUARD_COUNT: i32 = 5_000;

// ---------------------------------------------------------------------------------------------
// Shipped scenes

/// A shipped scene: file name, text and parsed table.
struct Shipped {
    name: String,
    text: String,
    doc: Value,
    /// The kind `flexfmu check` gives the unmutated scene.
    kind: String,
}

fn shipped() -> Vec<Shipped> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 10, "shipped scenes: {paths:?}");
    paths
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).unwrap();
            let doc = Value::Table(text.parse::<Table>().unwrap());
            let scene = cli::parse_scene(&text)
                .unwrap_or_else(|e| panic!("shipped scene {}: {e}", p.display()));
            Shipped {
                name: p.file_stem().unwrap().to_string_lossy().into_owned(),
                text,
                doc,
                kind: cli::kind_name(&scene),
            }
        })
        .collect()
}

/// Key names used anywhere in the shipped scenes, and those used at the top level.
struct KnownKeys {
    anywhere: BTreeSet<String>,
    top_level: BTreeSet<String>,
}

fn known_keys(scenes: &[Shipped]) -> KnownKeys {
    let mut anywhere = BTreeSet::new();
    let mut top_level = BTreeSet::new();
    for s in scenes {
        for p in key_paths(&s.doc) {
            let (key, _) = key_and_table(&p);
            anywhere.insert(key.clone());
            if p.len() == 1 {
                top_level.insert(key);
            }
        }
    }
    KnownKeys {
        anywhere,
        top_level,
    }
}

// ---------------------------------------------------------------------------------------------
// Paths in a TOML document

/// One step of a path: a key of a table or an entry of an array.
#[derive(Clone, Debug, PartialEq)]
enum Seg {
    Key(String),
    Entry(usize),
}

type Path = Vec<Seg>;

fn show(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Entry(i) => s.push_str(&format!("[{i}]")),
        }
    }
    if s.is_empty() {
        "(top level)".into()
    } else {
        s
    }
}

fn at<'a>(v: &'a Value, path: &[Seg]) -> Option<&'a Value> {
    let mut cur = v;
    for seg in path {
        cur = match (seg, cur) {
            (Seg::Key(k), Value::Table(t)) => t.get(k)?,
            (Seg::Entry(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn at_mut<'a>(v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    let mut cur = v;
    for seg in path {
        cur = match (seg, cur) {
            (Seg::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Seg::Entry(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

/// The table at `path` (the document itself for an empty path).
fn table_mut<'a>(doc: &'a mut Value, path: &[Seg]) -> &'a mut Table {
    match at_mut(doc, path) {
        Some(Value::Table(t)) => t,
        other => panic!("no table at {}: {other:?}", show(path)),
    }
}

/// Splits a key path into its table path and key.
fn split(path: &[Seg]) -> (&[Seg], &str) {
    match path.split_last() {
        Some((Seg::Key(k), parent)) => (parent, k),
        _ => panic!("not a key path: {}", show(path)),
    }
}

/// The key a path names (its last key) and the table that holds that key (the last key before
/// it; `None` at the top level). An array entry `pulley[1].center[0]` gives (`center`, `pulley`).
fn key_and_table(path: &[Seg]) -> (String, Option<String>) {
    let keys: Vec<&String> = path
        .iter()
        .filter_map(|s| match s {
            Seg::Key(k) => Some(k),
            Seg::Entry(_) => None,
        })
        .collect();
    let key = keys.last().map(|k| k.to_string()).unwrap_or_default();
    let table = (keys.len() >= 2).then(|| keys[keys.len() - 2].to_string());
    (key, table)
}

/// The name a table path is known by in messages: its last key (`loads` for `loads[0]`).
fn table_name(path: &[Seg]) -> Option<String> {
    path.iter().rev().find_map(|s| match s {
        Seg::Key(k) => Some(k.clone()),
        Seg::Entry(_) => None,
    })
}

/// Every key: tables and the tables inside arrays of tables, depth first.
fn key_paths(doc: &Value) -> Vec<Path> {
    fn walk(v: &Value, prefix: &mut Path, out: &mut Vec<Path>) {
        match v {
            Value::Table(t) => {
                for (k, child) in t {
                    prefix.push(Seg::Key(k.clone()));
                    out.push(prefix.clone());
                    walk(child, prefix, out);
                    prefix.pop();
                }
            }
            Value::Array(a) => {
                for (i, child) in a.iter().enumerate() {
                    if child.is_table() {
                        prefix.push(Seg::Entry(i));
                        walk(child, prefix, out);
                        prefix.pop();
                    }
                }
            }
            _ => {}
        }
    }
    let mut out = vec![];
    walk(doc, &mut vec![], &mut out);
    out
}

/// Every table, the document itself first.
fn table_paths(doc: &Value) -> Vec<Path> {
    let mut out = vec![vec![]];
    for p in key_paths(doc) {
        match at(doc, &p) {
            Some(Value::Table(_)) => out.push(p),
            Some(Value::Array(a)) => {
                for (i, e) in a.iter().enumerate() {
                    if e.is_table() {
                        let mut q = p.clone();
                        q.push(Seg::Entry(i));
                        out.push(q);
                    }
                }
            }
            _ => {}
        }
    }
    out
}

/// Every number: values of keys and entries of arrays of numbers.
fn number_paths(doc: &Value) -> Vec<Path> {
    let mut out = vec![];
    for p in key_paths(doc) {
        match at(doc, &p) {
            Some(Value::Integer(_) | Value::Float(_)) => out.push(p),
            Some(Value::Array(a)) => {
                for (i, e) in a.iter().enumerate() {
                    if matches!(e, Value::Integer(_) | Value::Float(_)) {
                        let mut q = p.clone();
                        q.push(Seg::Entry(i));
                        out.push(q);
                    }
                }
            }
            _ => {}
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Mutations

/// The mutation classes, one test each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Delete,
    Duplicate,
    Retype,
    Misspell,
    Move,
    Extreme,
    UnknownTable,
}

/// A character edit of a key name.
#[derive(Clone, Debug)]
enum Edit {
    Insert(Pick, char),
    Remove(Pick),
    Swap(Pick),
}

/// One mutation, with its choices as indexes into what the scene has (resolved when applied).
#[derive(Clone, Debug)]
enum Spec {
    /// Delete a key.
    Delete(Pick),
    /// Copy a key into another table.
    Duplicate(Pick, Pick),
    /// Give a key a value of another type.
    Retype(Pick, Pick),
    /// Edit one character of a key name.
    Misspell(Pick, Edit),
    /// Move a key into another table (the top level and entries of arrays of tables included).
    Move(Pick, Pick),
    /// Set a number (or an entry of an array of numbers) to an extreme value.
    Extreme(Pick, Pick),
    /// Add a table of an unknown name (at the top level or inside a table).
    UnknownTable(Pick, String),
}

/// What a mutation did and what a rejection must say.
#[derive(Debug)]
struct Applied {
    /// Human-readable description, e.g. `deleted material.E`.
    what: String,
    /// A rejection names one of these (key, table: `None` at the top level).
    names: Vec<(String, Option<String>)>,
    /// The mutated scene is wrong for every kind: it must be rejected.
    must_reject: bool,
    /// The mutation adds a key or table that the kind does not know: a rejection names the kind
    /// too.
    names_kind: bool,
    /// The key may also be named as the start of a derived parameter name (`pulley[1].center`
    /// as `pulleys.center_distance`).
    derived: bool,
    /// Another kind a rejection may name instead (a table of another kind can make the scene
    /// read as that kind).
    other_kind: Option<String>,
}

fn replacement_values() -> Vec<Value> {
    let mut t = Table::new();
    t.insert("x".into(), Value::Integer(1));
    vec![
        Value::String("text".into()),
        Value::String(String::new()),
        Value::Integer(7),
        Value::Float(2.5),
        Value::Boolean(true),
        Value::Array(vec![1, 2, 3].into_iter().map(Value::Integer).collect()),
        Value::Array(vec![Value::String("a".into()), Value::String("b".into())]),
        Value::Array(vec![]),
        Value::Table(t),
        Value::Table(Table::new()),
        Value::Datetime("1979-05-27T07:32:00Z".parse().unwrap()),
    ]
}

/// Extreme numbers: TOML has no NaN literal for integers, but `nan` and `inf` are valid floats.
fn extreme_values() -> Vec<Value> {
    let ints = [
        0,
        -1,
        100_000, // the largest mesh the scene checks accept
        1_000_000,
        i32::MAX as i64 + 1,
        i32::MIN as i64 - 1,
        i64::MAX,
        i64::MIN,
    ];
    let floats = [
        0.0,
        -0.0,
        -1.0,
        1e300,
        -1e300,
        1e-300,
        -1e-300,
        f64::MIN_POSITIVE / 4.0, // subnormal
        f64::MAX,
        f64::MIN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    ints.iter()
        .map(|&i| Value::Integer(i))
        .chain(floats.iter().map(|&x| Value::Float(x)))
        .collect()
}

/// A value as a description shows it (floats in the shortest form, long values cut).
fn brief(v: &Value) -> String {
    let s = match v {
        Value::Float(x) => format!("{x:?}"),
        other => other.to_string(),
    };
    if s.chars().count() > 60 {
        format!("{}...", s.chars().take(57).collect::<String>())
    } else {
        s
    }
}

fn same_type(a: &Value, b: &Value) -> bool {
    std::mem::discriminant(a) == std::mem::discriminant(b)
}

/// Whether `inner` lies at or below `outer`.
fn is_within(inner: &[Seg], outer: &[Seg]) -> bool {
    inner.len() >= outer.len() && inner[..outer.len()] == *outer
}

/// Applies `spec` to a copy of `scene`; `None` where it does not apply (nothing to choose).
fn apply(spec: &Spec, scene: &Shipped, known: &KnownKeys) -> Option<(Value, Applied)> {
    let mut doc = scene.doc.clone();
    let keys = key_paths(&doc);
    let tables = table_paths(&doc);
    let applied = match spec {
        Spec::Delete(k) => {
            let path = k.get(&keys).clone();
            let (parent, key) = split(&path);
            table_mut(&mut doc, parent).remove(key);
            let (key, table) = key_and_table(&path);
            Applied {
                what: format!("deleted {}", show(&path)),
                names: vec![(key, table)],
                must_reject: false,
                names_kind: false,
                other_kind: None,
                derived: false,
            }
        }
        Spec::Duplicate(k, to) | Spec::Move(k, to) => {
            let moving = matches!(spec, Spec::Move(..));
            let path = k.get(&keys).clone();
            let (parent, key) = split(&path);
            let key = key.to_string();
            let value = at(&doc, &path).unwrap().clone();
            // Another table that does not hold the key yet and is not inside the moved value.
            let targets: Vec<&Path> = tables
                .iter()
                .filter(|t| t.as_slice() != parent && !is_within(t, &path))
                .filter(|t| !at(&doc, t).unwrap().as_table().unwrap().contains_key(&key))
                .collect();
            if targets.is_empty() {
                return None;
            }
            let dest = (*to.get(&targets)).clone();
            if moving {
                table_mut(&mut doc, parent).remove(&key);
            }
            table_mut(&mut doc, &dest).insert(key.clone(), value.clone());
            let (_, from_table) = key_and_table(&path);
            let to_table = table_name(&dest);
            // A plain value at the top level, or a table there that no scene has, is wrong for
            // every kind (the `kind` key is a string that names a kind, never a support's kind).
            let must_reject = dest.is_empty() && !known.top_level.contains(&key);
            let mut names = vec![(key.clone(), to_table)];
            if moving && !must_reject {
                names.push((key.clone(), from_table));
            }
            Applied {
                what: format!(
                    "{} {} to {}",
                    if moving { "moved" } else { "copied" },
                    show(&path),
                    show(&dest)
                ),
                names,
                must_reject,
                names_kind: must_reject,
                other_kind: None,
                derived: false,
            }
        }
        Spec::Retype(k, shape) => {
            let path = k.get(&keys).clone();
            let old = at(&doc, &path).unwrap().clone();
            let choices: Vec<Value> = replacement_values()
                .into_iter()
                .filter(|v| !same_type(v, &old))
                .collect();
            let new = shape.get(&choices).clone();
            *at_mut(&mut doc, &path).unwrap() = new.clone();
            let (key, table) = key_and_table(&path);
            Applied {
                what: format!(
                    "retyped {} = {} to {}",
                    show(&path),
                    brief(&old),
                    brief(&new)
                ),
                names: vec![(key, table)],
                must_reject: false,
                names_kind: false,
                other_kind: None,
                derived: false,
            }
        }
        Spec::Misspell(k, edit) => {
            let path = k.get(&keys).clone();
            let (parent, key) = split(&path);
            let mut chars: Vec<char> = key.chars().collect();
            match edit {
                Edit::Insert(i, c) => chars.insert(i.index(chars.len() + 1), *c),
                Edit::Remove(i) => {
                    chars.remove(i.index(chars.len()));
                }
                Edit::Swap(i) => {
                    if chars.len() < 2 {
                        return None;
                    }
                    let i = i.index(chars.len() - 1);
                    chars.swap(i, i + 1);
                }
            }
            let new: String = chars.into_iter().collect();
            let table = table_mut(&mut doc, parent);
            if new == key || table.contains_key(&new) {
                return None;
            }
            let value = table.remove(key).unwrap();
            table.insert(new.clone(), value);
            let table = table_name(parent);
            // A name no shipped scene uses anywhere cannot be a key of any kind's tables.
            let must_reject = !known.anywhere.contains(&new);
            // The unknown new name, or the now missing old one (a kind may report either first).
            let names = vec![(new.clone(), table.clone()), (key.to_string(), table)];
            Applied {
                what: format!("renamed {} to {new:?}", show(&path)),
                names,
                must_reject,
                names_kind: must_reject,
                other_kind: None,
                derived: false,
            }
        }
        Spec::Extreme(n, v) => {
            let numbers = number_paths(&doc);
            if numbers.is_empty() {
                return None;
            }
            let path = n.get(&numbers).clone();
            let new = v.get(&extreme_values()).clone();
            let old = std::mem::replace(at_mut(&mut doc, &path).unwrap(), new.clone());
            let (key, table) = key_and_table(&path);
            let non_finite = matches!(new, Value::Float(x) if !x.is_finite());
            Applied {
                what: format!("set {} = {} to {}", show(&path), brief(&old), brief(&new)),
                names: vec![(key, table)],
                must_reject: non_finite,
                names_kind: false,
                other_kind: None,
                derived: true,
            }
        }
        Spec::UnknownTable(parent, name) => {
            if known.anywhere.contains(name) {
                return None;
            }
            let parent = parent.get(&tables).clone();
            let mut t = Table::new();
            t.insert("value".into(), Value::Float(1.0));
            let table = table_mut(&mut doc, &parent);
            if table.contains_key(name) {
                return None;
            }
            table.insert(name.clone(), Value::Table(t));
            let mut path = parent.clone();
            path.push(Seg::Key(name.clone()));
            Applied {
                what: format!("added the table [{}]", show(&path)),
                names: vec![(name.clone(), table_name(&parent))],
                must_reject: true,
                names_kind: true,
                other_kind: None,
                derived: false,
            }
        }
    };
    Some((doc, applied))
}

fn key_index() -> impl Strategy<Value = Pick> {
    pick()
}

/// A uniform choice among the candidates that a mutation finds in a scene (shrinks towards the
/// first candidate).
#[derive(Clone, Copy, Debug)]
struct Pick(u64);

impl Pick {
    /// The chosen position among `len` candidates (`len > 0`).
    fn index(&self, len: usize) -> usize {
        assert!(len > 0, "nothing to pick from");
        ((len as u128 * self.0 as u128) >> 64) as usize
    }

    /// The chosen candidate.
    fn get<'a, T>(&self, slice: &'a [T]) -> &'a T {
        &slice[self.index(slice.len())]
    }

    /// The choice of position `i` among `len`.
    fn of(i: usize, len: usize) -> Self {
        assert!(i < len);
        Self((((2 * i + 1) as u128) << 63).div_euclid(len as u128) as u64)
    }
}

fn pick() -> impl Strategy<Value = Pick> {
    any::<u64>().prop_map(Pick)
}

fn strategy(class: Class) -> BoxedStrategy<Spec> {
    let edit_char = prop_oneof![
        4 => proptest::char::range('a', 'z'),
        1 => proptest::char::range('A', 'Z'),
        1 => proptest::char::range('0', '9'),
        1 => proptest::sample::select(vec!['_', '-', '.', ' ', 'é']),
    ];
    match class {
        Class::Delete => key_index().prop_map(Spec::Delete).boxed(),
        Class::Duplicate => (key_index(), pick())
            .prop_map(|(k, t)| Spec::Duplicate(k, t))
            .boxed(),
        Class::Retype => (key_index(), pick())
            .prop_map(|(k, v)| Spec::Retype(k, v))
            .boxed(),
        Class::Misspell => (
            key_index(),
            prop_oneof![
                (pick(), edit_char).prop_map(|(i, c)| Edit::Insert(i, c)),
                pick().prop_map(Edit::Remove),
                pick().prop_map(Edit::Swap),
            ],
        )
            .prop_map(|(k, e)| Spec::Misspell(k, e))
            .boxed(),
        Class::Move => (key_index(), pick())
            .prop_map(|(k, t)| Spec::Move(k, t))
            .boxed(),
        Class::Extreme => (pick(), pick())
            .prop_map(|(n, v)| Spec::Extreme(n, v))
            .boxed(),
        Class::UnknownTable => (pick(), "[a-z][a-z_0-9]{1,11}")
            .prop_map(|(p, name)| Spec::UnknownTable(p, name))
            .boxed(),
    }
}

// ---------------------------------------------------------------------------------------------
// Running `flexfmu check`

/// What `flexfmu check` did with a scene.
#[derive(Debug)]
enum Outcome {
    /// Parsed, validated and built.
    Accepted(CheckSummary),
    /// Parsed and validated; not built because of [`BUILD_GUARD_COUNT`] (the parameter named).
    AcceptedUnbuilt(String),
    /// Rejected with this message.
    Rejected(String),
    /// Panicked with this payload.
    Panicked(String),
    /// Still running after [`HANG_LIMIT`].
    Hung,
}

/// The Integer parameter above [`BUILD_GUARD_COUNT`], if any.
fn too_big_to_build(scene: &flexfmu::scene::Scene) -> Option<String> {
    scene.params.iter().find_map(|p| match p.start {
        flexfmu::variables::Value::Integer(n) if n > BUILD_GUARD_COUNT => {
            Some(format!("{} = {n}", p.name))
        }
        _ => None,
    })
}

/// `flexfmu check` on `text` ([`cli::check_scene`]) under `catch_unwind` in a thread that may
/// take at most [`HANG_LIMIT`]. The parse before it only decides whether the model is built.
fn run_check(text: String) -> (Outcome, Duration) {
    let (tx, rx) = mpsc::channel();
    let start = Instant::now();
    std::thread::spawn(move || {
        let result = catch_unwind(AssertUnwindSafe(|| {
            if let Ok(scene) = cli::parse_scene(&text)
                && let Some(why) = too_big_to_build(&scene)
            {
                return Outcome::AcceptedUnbuilt(why);
            }
            match cli::check_scene(&text) {
                Ok(summary) => Outcome::Accepted(summary),
                Err(e) => Outcome::Rejected(e),
            }
        }));
        let outcome = result.unwrap_or_else(|payload| {
            let msg = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "(non-string panic payload)".into());
            Outcome::Panicked(msg)
        });
        let _ = tx.send(outcome);
    });
    let outcome = rx.recv_timeout(HANG_LIMIT).unwrap_or(Outcome::Hung);
    (outcome, start.elapsed())
}

// ---------------------------------------------------------------------------------------------
// What a message names

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Whether `msg` contains `word` as a whole word (not inside a longer identifier).
fn names_word(msg: &str, word: &str) -> bool {
    if word.is_empty() {
        return msg.contains("\"\"") || msg.contains("``") || msg.contains("empty");
    }
    msg.match_indices(word).any(|(i, _)| {
        let before = msg[..i].chars().next_back();
        let after = msg[i + word.len()..].chars().next();
        !before.is_some_and(is_ident) && !after.is_some_and(is_ident)
    })
}

/// Whether `msg` contains `word` at the start of a word, as a whole or followed by `_` and more
/// (`center` in `pulleys.center_distance`).
fn names_prefix(msg: &str, word: &str) -> bool {
    !word.is_empty()
        && msg.match_indices(word).any(|(i, _)| {
            let before = msg[..i].chars().next_back();
            let after = msg[i + word.len()..].chars().next();
            !before.is_some_and(is_ident) && !after.is_some_and(|c| c.is_alphanumeric())
        })
}

/// Whether `msg` names the table `table`: as a word, or followed by an `s`, a number or an index
/// (`pulley`, `pulleys.center_distance`, `pulley2.radius`, `loads[0]`).
fn names_table(msg: &str, table: &str) -> bool {
    msg.match_indices(table).any(|(i, _)| {
        if msg[..i].chars().next_back().is_some_and(is_ident) {
            return false;
        }
        let rest = &msg[i + table.len()..];
        let rest = rest.strip_prefix('s').unwrap_or(rest);
        let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit());
        !rest.chars().next().is_some_and(is_ident)
    })
}

/// Whether `msg` names the kind `kind` (case, spaces and underscores aside: `belt_drive`,
/// `belt drive`, `BeltDrive`).
fn names_kind(msg: &str, kind: &str) -> bool {
    let norm = |s: &str| -> String {
        s.chars()
            .filter(|c| c.is_alphanumeric())
            .flat_map(char::to_lowercase)
            .collect()
    };
    norm(msg).contains(&norm(kind))
}

/// What a rejection message lacks of what `applied` requires (`None`: nothing).
fn message_lacks(msg: &str, applied: &Applied, kind: &str) -> Option<&'static str> {
    // The added table made the scene read as another kind, whose message names the keys that
    // kind does not know (the scene's own).
    if applied
        .other_kind
        .as_deref()
        .is_some_and(|k| names_kind(msg, k))
        && !names_kind(msg, kind)
    {
        return None;
    }
    let named = |key: &str| names_word(msg, key) || (applied.derived && names_prefix(msg, key));
    let key = applied.names.iter().any(|(key, _)| named(key));
    let table = applied
        .names
        .iter()
        .any(|(key, table)| named(key) && table.as_deref().is_none_or(|t| names_table(msg, t)));
    if !key {
        Some("the key")
    } else if !table {
        Some("the table")
    } else if applied.names_kind
        && !names_kind(msg, kind)
        && !applied
            .other_kind
            .as_deref()
            .is_some_and(|k| names_kind(msg, k))
    {
        Some("the kind")
    } else {
        None
    }
}

/// Whether a rejection message says what `applied` requires.
fn message_ok(msg: &str, applied: &Applied, kind: &str) -> bool {
    message_lacks(msg, applied, kind).is_none()
}

/// What is wrong with `outcome` for `applied`: a category and the details.
fn judge(outcome: &Outcome, applied: &Applied, kind: &str) -> Option<(String, String)> {
    match outcome {
        Outcome::Accepted(_) | Outcome::AcceptedUnbuilt(_) => applied
            .must_reject
            .then(|| ("accepted although wrong".into(), "accepted".into())),
        Outcome::Rejected(msg) => message_lacks(msg, applied, kind).map(|lack| {
            (
                format!("rejected; message lacks {lack}"),
                format!("rejected with a message that lacks {lack}: {msg}"),
            )
        }),
        Outcome::Panicked(msg) => Some(("PANIC".into(), format!("PANICKED: {msg}"))),
        Outcome::Hung => Some((
            "HANG".into(),
            format!("HUNG (no answer after {HANG_LIMIT:?})"),
        )),
    }
}

fn expectation(applied: &Applied, kind: &str) -> String {
    let alts: Vec<String> = applied
        .names
        .iter()
        .map(|(k, t)| match t {
            Some(t) => format!("key {k:?} and table {t:?}"),
            None => format!("key {k:?}"),
        })
        .collect();
    let kind = if applied.names_kind {
        match &applied.other_kind {
            Some(other) => format!(" and the kind {kind:?} (or {other:?})"),
            None => format!(" and the kind {kind:?}"),
        }
    } else {
        String::new()
    };
    if applied.must_reject {
        format!("must be rejected naming {}{kind}", alts.join(" or "))
    } else {
        format!("accepted, or rejected naming {}{kind}", alts.join(" or "))
    }
}

// ---------------------------------------------------------------------------------------------
// The property runner

#[derive(Default, Debug)]
struct Stats {
    checks: usize,
    not_applicable: usize,
    accepted: usize,
    unbuilt: usize,
    rejected: usize,
    failed: usize,
    total: Duration,
    slowest: (Duration, String),
    not_built: BTreeSet<String>,
    /// Failures by (category, kind): count and first example.
    survey: std::collections::BTreeMap<(String, String), (usize, String)>,
}

/// The first line of a message, cut to 300 characters.
fn first_line(msg: &str) -> String {
    let line = msg.lines().next().unwrap_or_default();
    line.chars().take(300).collect()
}

fn env_number(name: &str) -> Option<u64> {
    std::env::var(name).ok().map(|v| {
        v.parse()
            .unwrap_or_else(|_| panic!("{name}={v}: not a number"))
    })
}

/// A ChaCha seed from the class, the scene and `FLEXFMU_SCENE_MUTATION_SEED` (FNV-1a).
fn seed(class: Class, scene: &str) -> [u8; 32] {
    let base = env_number("FLEXFMU_SCENE_MUTATION_SEED").unwrap_or(9);
    let mut h: u64 = 0xcbf2_9ce4_8422_2325 ^ base;
    let mut out = [0u8; 32];
    for (round, chunk) in out.chunks_mut(8).enumerate() {
        for b in format!("{class:?}/{scene}/{round}").bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        chunk.copy_from_slice(&h.to_le_bytes());
    }
    out
}

/// Runs `class` over every shipped scene; panics with a report of every failing scene.
fn run_class(class: Class) {
    let scenes = shipped();
    let known = known_keys(&scenes);
    let cases = env_number("FLEXFMU_SCENE_MUTATION_CASES").map_or(CASES, |n| n as u32);
    let stats = RefCell::new(Stats::default());
    let mut failures = vec![];
    let strategy = strategy(class);
    let survey = std::env::var_os("FLEXFMU_SCENE_MUTATION_SURVEY").is_some();
    for scene in &scenes {
        let config = Config {
            cases,
            max_shrink_iters: 256,
            failure_persistence: None,
            rng_algorithm: RngAlgorithm::ChaCha,
            ..Config::default()
        };
        let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed(class, &scene.name));
        let mut runner = TestRunner::new_with_rng(config, rng);
        // After a hang (its thread still runs) the remaining cases of the scene pass at once, so
        // that shrinking ends with the hanging case instead of waiting for more hangs.
        let hung = std::cell::Cell::new(false);
        let case = |spec: Spec| -> Result<(), TestCaseError> {
            if hung.get() {
                return Ok(());
            }
            let Some((doc, applied)) = apply(&spec, scene, &known) else {
                stats.borrow_mut().not_applicable += 1;
                return Ok(());
            };
            let text = match toml::to_string(&doc) {
                Ok(t) => t,
                Err(e) => {
                    return Err(TestCaseError::fail(format!(
                        "{}: the mutated table does not serialize: {e}",
                        applied.what
                    )));
                }
            };
            let (outcome, took) = run_check(text.clone());
            let mut st = stats.borrow_mut();
            st.checks += 1;
            st.total += took;
            if took > st.slowest.0 {
                st.slowest = (took, format!("{}: {}", scene.name, applied.what));
            }
            match &outcome {
                Outcome::Accepted(_) => st.accepted += 1,
                Outcome::AcceptedUnbuilt(why) => {
                    st.unbuilt += 1;
                    st.not_built.insert(why.clone());
                }
                Outcome::Rejected(_) => st.rejected += 1,
                _ => {}
            }
            hung.set(matches!(outcome, Outcome::Hung));
            let problem = judge(&outcome, &applied, &scene.kind);
            if let Some((category, detail)) = &problem {
                let entry = st
                    .survey
                    .entry((category.clone(), scene.kind.clone()))
                    .or_insert((0, String::new()));
                entry.0 += 1;
                if entry.1.is_empty() {
                    entry.1 = format!("{}: {}: {}", scene.name, applied.what, first_line(detail));
                }
            }
            let problem = problem.map(|(_, detail)| detail);
            match problem {
                None => Ok(()),
                Some(problem) => {
                    st.failed += 1;
                    Err(TestCaseError::fail(format!(
                        "{}\n    expected: {}\n    got: {problem}\n    mutated scene:\n{}",
                        applied.what,
                        expectation(&applied, &scene.kind),
                        indent(&text)
                    )))
                }
            }
        };
        if survey {
            // Every case, no shrinking: the failures by category (the lead's to-do list).
            for _ in 0..cases {
                let spec = strategy.new_tree(&mut runner).unwrap().current();
                let _ = case(spec);
            }
            continue;
        }
        let result = runner.run(&strategy, case);
        match result {
            Ok(()) => {}
            Err(TestError::Fail(reason, _)) => {
                failures.push(format!("scenes/{}.toml: {reason}", scene.name))
            }
            Err(TestError::Abort(reason)) => {
                failures.push(format!("scenes/{}.toml: aborted: {reason}", scene.name))
            }
        }
    }
    let st = stats.into_inner();
    eprintln!(
        "{class:?}: {} checks ({} accepted, {} accepted but not built, {} rejected, {} failing, \
         shrink runs included), {} mutations not applicable; check time {:.2} s in all, slowest \
         {:.3} s ({})",
        st.checks,
        st.accepted,
        st.unbuilt,
        st.rejected,
        st.failed,
        st.not_applicable,
        st.total.as_secs_f64(),
        st.slowest.0.as_secs_f64(),
        st.slowest.1
    );
    for why in &st.not_built {
        eprintln!("  not built: {why}");
    }
    for ((category, kind), (count, example)) in &st.survey {
        eprintln!("  {count:5} x {category} ({kind}), e.g. {example}");
    }
    assert!(
        !survey || st.survey.is_empty(),
        "{class:?}: the survey found failures (listed above)"
    );
    // The test must be able to fail: most cases have to produce a mutated scene.
    assert!(
        st.checks >= st.not_applicable,
        "{class:?}: {} of {} mutations did not apply",
        st.not_applicable,
        st.checks + st.not_applicable
    );
    assert!(
        failures.is_empty(),
        "{class:?}: {} of {} scenes fail (minimal case per scene after shrinking):\n\n{}",
        failures.len(),
        scenes.len(),
        failures.join("\n\n")
    );
}

fn indent(text: &str) -> String {
    text.lines()
        .map(|l| format!("      | {l}"))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn deleted_keys() {
    run_class(Class::Delete);
}

#[test]
fn duplicated_keys() {
    run_class(Class::Duplicate);
}

#[test]
fn retyped_values() {
    run_class(Class::Retype);
}

#[test]
fn misspelled_keys() {
    run_class(Class::Misspell);
}

#[test]
fn moved_keys() {
    run_class(Class::Move);
}

#[test]
fn extreme_numbers() {
    run_class(Class::Extreme);
}

#[test]
fn unknown_tables() {
    run_class(Class::UnknownTable);
}

// ---------------------------------------------------------------------------------------------
// Tables of other kinds (exhaustive: every top-level table of every other shipped scene)

/// Top-level tables every kind has.
const COMMON_TABLES: &[&str] = &["fmu", "experiment", "element", "solver", "gravity"];

/// Every shipped scene with every top-level table of another shipped scene that it lacks: no
/// panic; a table its kind does not use is rejected naming the table and the kind (or the
/// donor's kind: `[belt]` may make a beam scene read as a belt drive); any other is accepted or
/// rejected naming the table.
#[test]
fn tables_of_other_scenes() {
    let scenes = shipped();
    let mut failures = BTreeSet::new();
    let mut checks = 0;
    for scene in &scenes {
        let own = flexfmu::kinds::by_name(&scene.kind)
            .unwrap_or_else(|| panic!("no kind {:?} in the registry", scene.kind))
            .tables();
        let root = scene.doc.as_table().unwrap();
        for donor in scenes.iter().filter(|d| d.name != scene.name) {
            for (key, value) in donor.doc.as_table().unwrap() {
                if root.contains_key(key) {
                    continue;
                }
                let mut doc = scene.doc.clone();
                table_mut(&mut doc, &[]).insert(key.clone(), value.clone());
                let foreign =
                    !own.contains(&key.as_str()) && !COMMON_TABLES.contains(&key.as_str());
                let applied = Applied {
                    what: format!("added [{key}] of scenes/{}.toml", donor.name),
                    names: vec![(key.clone(), None)],
                    must_reject: foreign,
                    names_kind: foreign,
                    other_kind: Some(donor.kind.clone()),
                    derived: false,
                };
                let (outcome, _) = run_check(toml::to_string(&doc).unwrap());
                checks += 1;
                let problem = judge(&outcome, &applied, &scene.kind).map(|(_, d)| d);
                if let Some(problem) = problem {
                    failures.insert(format!(
                        "scenes/{}.toml ({}): {}: expected {}; got {problem}",
                        scene.name,
                        scene.kind,
                        applied.what,
                        expectation(&applied, &scene.kind)
                    ));
                }
            }
        }
    }
    assert!(checks > 50, "only {checks} combinations");
    assert!(
        failures.is_empty(),
        "{} of {checks} scenes with a table of another scene fail:\n{}",
        failures.len(),
        failures.into_iter().collect::<Vec<_>>().join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// The machinery itself

/// The round trip through `toml::Table` keeps every shipped scene valid and equal: mutations
/// start from what `flexfmu check` accepts.
#[test]
fn shipped_scenes_pass_check_after_round_trip() {
    for s in shipped() {
        let original =
            cli::check_scene(&s.text).unwrap_or_else(|e| panic!("scenes/{}.toml: {e}", s.name));
        let text = toml::to_string(&s.doc).unwrap();
        let (outcome, _) = run_check(text);
        match outcome {
            Outcome::Accepted(summary) => assert_eq!(summary, original, "{}", s.name),
            other => panic!("scenes/{}.toml after the round trip: {other:?}", s.name),
        }
    }
}

/// The watchdog reports panics as panics and rejections as rejections.
#[test]
fn run_check_tells_rejections_from_acceptance() {
    let text = shipped().remove(0).text;
    assert!(matches!(run_check(text.clone()).0, Outcome::Accepted(_)));
    let bad = text.replacen("model_name = \"", "model_name = 3 # \"", 1);
    assert_ne!(bad, text);
    let (outcome, _) = run_check(bad);
    assert!(
        matches!(outcome, Outcome::Rejected(ref m) if m.contains("model_name")),
        "{outcome:?}"
    );
}

#[test]
fn message_matching() {
    assert!(names_word("material.E = 1e300: must lie", "E"));
    assert!(!names_word("Element type", "E"));
    assert!(!names_word("unknown key `nmae`", "name"));
    assert!(names_word("unknown field `nmae`, expected", "nmae"));
    assert!(names_prefix("pulleys.center_distance = inf", "center"));
    assert!(!names_prefix("pulleys.centers", "center"));
    assert!(!names_word("pulleys.center_distance = inf", "center"));
    assert!(names_table("pulley2.radius = -1", "pulley"));
    assert!(names_table("pulleys.center_distance", "pulley"));
    assert!(names_table("loads[0].at", "loads"));
    assert!(!names_table("payloads", "loads"));
    assert!(!names_table("pulley_x", "pulley"));
    assert!(names_kind("not used by a belt drive", "belt_drive"));
    assert!(names_kind("kind \"beam_3d\", key `x`", "beam_3d"));
    assert!(!names_kind("kind \"beam_2d\"", "beam_3d"));
    let applied = Applied {
        what: String::new(),
        names: vec![("belt_points".into(), Some("outputs".into()))],
        must_reject: true,
        names_kind: true,
        other_kind: None,
        derived: false,
    };
    assert!(message_ok(
        "kind \"beam_3d\", key `belt_points` in table [outputs]: unknown field",
        &applied,
        "beam_3d"
    ));
    assert!(!message_ok("belt_points: not used", &applied, "beam_3d"));
}

/// Each mutation class produces the intended change on a known scene.
#[test]
fn mutations_do_what_they_say() {
    let scenes = shipped();
    let known = known_keys(&scenes);
    let cantilever = scenes.iter().find(|s| s.name == "cantilever").unwrap();
    let keys = key_paths(&cantilever.doc);
    let e_path = vec![Seg::Key("material".into()), Seg::Key("E".into())];
    let idx = Pick::of;
    let n = keys.len();
    let e = keys.iter().position(|k| *k == e_path).unwrap();
    for i in 0..n {
        assert_eq!(Pick::of(i, n).index(n), i);
    }

    let (doc, applied) = apply(&Spec::Delete(idx(e, n)), cantilever, &known).unwrap();
    assert!(at(&doc, &e_path).is_none());
    assert_eq!(applied.names, vec![("E".into(), Some("material".into()))]);

    let swap = Spec::Misspell(idx(e, n), Edit::Insert(idx(1, 2), 'q'));
    let (doc, applied) = apply(&swap, cantilever, &known).unwrap();
    assert!(at(&doc, &[Seg::Key("material".into()), Seg::Key("Eq".into())]).is_some());
    assert!(applied.must_reject);

    let extreme = extreme_values();
    let nan = extreme
        .iter()
        .position(|v| matches!(v, Value::Float(x) if x.is_nan()))
        .unwrap();
    let numbers = number_paths(&cantilever.doc);
    let en = numbers.iter().position(|p| *p == e_path).unwrap();
    let spec = Spec::Extreme(idx(en, numbers.len()), idx(nan, extreme.len()));
    let (doc, applied) = apply(&spec, cantilever, &known).unwrap();
    assert!(matches!(at(&doc, &e_path), Some(Value::Float(x)) if x.is_nan()));
    assert!(applied.must_reject);
    assert!(toml::to_string(&doc).unwrap().contains("E = nan"));

    let tables = table_paths(&cantilever.doc);
    let spec = Spec::Move(idx(e, n), idx(0, tables.len() - 1));
    let (doc, applied) = apply(&spec, cantilever, &known).unwrap();
    assert!(at(&doc, &e_path).is_none());
    assert!(
        at(&doc, &[Seg::Key("E".into())]).is_some(),
        "moved to the top level"
    );
    assert!(applied.must_reject);
}

// ---------------------------------------------------------------------------------------------
// Regression tests: the silent cases issue 9 names

/// `scenes/<name>.toml` with `value` added at `path` (tables created as needed); `flexfmu check`
/// must reject it with a message that names `key`, `table` (if any) and the scene's kind.
fn assert_rejected_naming(name: &str, path: &[&str], value: Value, table: Option<&str>) {
    let scene = shipped().into_iter().find(|s| s.name == name).unwrap();
    let mut doc = scene.doc.clone();
    let (last, parents) = path.split_last().unwrap();
    let mut t = doc.as_table_mut().unwrap();
    for p in parents {
        t = t
            .entry(p.to_string())
            .or_insert_with(|| Value::Table(Table::new()))
            .as_table_mut()
            .unwrap();
    }
    assert!(t.get(*last).is_none(), "{name} already has {path:?}");
    t.insert(last.to_string(), value);
    let text = toml::to_string(&doc).unwrap();
    let what = format!("scenes/{name}.toml with {}", path.join("."));
    match cli::check_scene(&text) {
        Ok(summary) => panic!("{what}: accepted without a word ({summary})"),
        Err(msg) => {
            let ok = names_word(&msg, last)
                && table.is_none_or(|t| names_table(&msg, t))
                && names_kind(&msg, &scene.kind);
            assert!(
                ok,
                "{what}: the message must name {last:?}{} and the kind {:?}: {msg}",
                table.map(|t| format!(", table {t:?}")).unwrap_or_default(),
                scene.kind
            );
        }
    }
}

fn motions_table() -> Value {
    let mut m = Table::new();
    m.insert("name".into(), Value::String("port".into()));
    m.insert("at".into(), Value::Float(1.0));
    Value::Array(vec![Value::Table(m)])
}

fn initial_table() -> Value {
    let mut t = Table::new();
    t.insert("angular_velocity".into(), Value::Float(0.0));
    Value::Table(t)
}

#[test]
fn beam_3d_scene_rejects_motions() {
    assert_rejected_naming("cantilever3d", &["motions"], motions_table(), None);
}

#[test]
fn beam_3d_scene_rejects_initial() {
    assert_rejected_naming("cantilever3d", &["initial"], initial_table(), None);
}

#[test]
fn beam_3d_scene_rejects_belt_points() {
    assert_rejected_naming(
        "cantilever3d",
        &["outputs", "belt_points"],
        Value::Integer(20),
        Some("outputs"),
    );
}

#[test]
fn beam_2d_scene_rejects_belt_points() {
    assert_rejected_naming(
        "cantilever",
        &["outputs", "belt_points"],
        Value::Integer(20),
        Some("outputs"),
    );
}

#[test]
fn belt_scene_rejects_motions() {
    assert_rejected_naming("belt_drive", &["motions"], motions_table(), None);
}

#[test]
fn belt_scene_rejects_initial() {
    assert_rejected_naming("belt_drive", &["initial"], initial_table(), None);
}

/// Serde reads a struct from an array by position: `contact = [0.4]` was silently read as
/// `[contact] mu = 0.4`. A table given as an array is an error that names it.
#[test]
fn belt_scene_rejects_table_given_as_array() {
    let scene = shipped()
        .into_iter()
        .find(|s| s.name == "belt_drive")
        .unwrap();
    let mut doc = scene.doc.clone();
    table_mut(&mut doc, &[]).insert("contact".into(), Value::Array(vec![Value::Float(0.4)]));
    match cli::check_scene(&toml::to_string(&doc).unwrap()) {
        Ok(summary) => panic!("contact = [0.4] accepted ({summary})"),
        Err(msg) => assert!(
            names_word(&msg, "contact") && names_kind(&msg, &scene.kind),
            "the message must name contact and the kind: {msg}"
        ),
    }
}

/// An arc of radius 1.8e308 (finite, so valid TOML and not caught as non-finite) made the
/// element distribution of the 3D-beam mesher overflow (`n_elements * length / total` = inf,
/// cast to usize::MAX) and count down to the mesh size one by one: `flexfmu check` hung.
#[test]
fn beam_3d_scene_with_huge_arc_radius_answers() {
    let scene = shipped().into_iter().find(|s| s.name == "bend45").unwrap();
    let mut doc = scene.doc.clone();
    let path = [
        Seg::Key("centreline".into()),
        Seg::Key("segments".into()),
        Seg::Entry(0),
        Seg::Key("radius".into()),
    ];
    *at_mut(&mut doc, &path).unwrap() = Value::Float(f64::MAX);
    let applied = Applied {
        what: "set centreline.segments[0].radius to 1.8e308".into(),
        names: vec![("radius".into(), Some("segments".into()))],
        must_reject: false,
        names_kind: false,
        other_kind: None,
        derived: true,
    };
    let (outcome, took) = run_check(toml::to_string(&doc).unwrap());
    if let Some((_, problem)) = judge(&outcome, &applied, &scene.kind) {
        panic!("{}: {problem} (after {took:?})", applied.what);
    }
}
