//! The sweep file: parsed with every key checked (unknown keys rejected, errors name the key),
//! then resolved against the scene's variable table into a [`Sweep`].

use super::design::{grid, latin_hypercube, linspace};
use crate::scene::Scene;
use crate::variables::{Causality, Value, VarType, VariableTable};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The sweep file as written (see the module documentation for the keys).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    scene: Option<String>,
    fmu: Option<String>,
    run: RunTable,
    #[serde(default)]
    parameters: Vec<ParamEntry>,
    sample: Option<SampleTable>,
    inputs: Option<InputsTable>,
    outputs: Vec<OutputEntry>,
    series: Option<SeriesTable>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct RunTable {
    #[serde(default)]
    start_time: f64,
    stop_time: f64,
    step: f64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ParamEntry {
    name: String,
    value: Option<toml::Value>,
    values: Option<Vec<toml::Value>>,
    linspace: Option<(f64, f64, usize)>,
    lhs: Option<[f64; 2]>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SampleTable {
    points: usize,
    #[serde(default)]
    seed: u64,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct InputsTable {
    csv: String,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct OutputEntry {
    name: String,
    reduce: Vec<Reduction>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SeriesTable {
    outputs: Vec<String>,
    points: Vec<usize>,
}

/// A reduction of an output over the communication points `t_0 … t_N` of a run (including the
/// initial one, after initialization).
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Reduction {
    /// `y(t_N)`.
    Final,
    /// `max_k y_k`.
    Max,
    /// `min_k y_k`.
    Min,
    /// `(Σ_k y_k) / (N + 1)`, summed in order of time.
    Mean,
    /// `sqrt((Σ_k y_k²) / (N + 1))`, summed in order of time.
    Rms,
    /// `max_k |y_k|`.
    MaxAbs,
}

impl Reduction {
    /// The name in sweep files and column headers.
    pub fn name(self) -> &'static str {
        match self {
            Reduction::Final => "final",
            Reduction::Max => "max",
            Reduction::Min => "min",
            Reduction::Mean => "mean",
            Reduction::Rms => "rms",
            Reduction::MaxAbs => "max_abs",
        }
    }
}

/// Where the model comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// A scene file (absolute path).
    Scene(PathBuf),
    /// An FMU built by `flexfmu build` (absolute path); its `resources/scene.toml` is run.
    Fmu(PathBuf),
}

/// A variable the sweep sets per point (a parameter, or an input held constant over the run).
#[derive(Clone, Debug)]
pub struct Setting {
    /// Variable name.
    pub name: String,
    /// Value reference.
    pub vr: u32,
    /// FMI type.
    pub ty: VarType,
    /// Parameter or input.
    pub causality: Causality,
    /// Whether the sweep varies it (more than one value); constants are set but not plotted.
    pub varies: bool,
}

/// Input signals from a CSV file: linear interpolation between the rows, held constant before
/// the first and after the last time.
#[derive(Clone, Debug)]
pub struct InputTable {
    /// Times [s], strictly increasing.
    pub time: Vec<f64>,
    /// Per input: name, value reference and the values at `time`.
    pub columns: Vec<(String, u32, Vec<f64>)>,
}

impl InputTable {
    /// Value of column `c` at time `t`: on the segment `i` with `time[i] <= t` the largest such
    /// `i` below the last row, `y_i + (y_{i+1} - y_i) ((t - t_i) / (t_{i+1} - t_i))`; the first
    /// value before the table and the last after it. (The Python front end evaluates the same
    /// expression in the same order.)
    pub fn value(&self, c: usize, t: f64) -> f64 {
        let y = &self.columns[c].2;
        let n = self.time.len();
        if n == 1 || t <= self.time[0] {
            return y[0];
        }
        if t >= self.time[n - 1] {
            return y[n - 1];
        }
        let i = self.time.partition_point(|&x| x <= t) - 1;
        let (t0, t1) = (self.time[i], self.time[i + 1]);
        y[i] + (y[i + 1] - y[i]) * ((t - t0) / (t1 - t0))
    }
}

/// An output the sweep keeps, with its reductions.
#[derive(Clone, Debug)]
pub struct OutputSpec {
    /// Variable name.
    pub name: String,
    /// Value reference.
    pub vr: u32,
    /// Reductions, in file order.
    pub reductions: Vec<Reduction>,
}

/// The time series a sweep keeps.
#[derive(Clone, Debug)]
pub struct SeriesSpec {
    /// Outputs: name and value reference.
    pub outputs: Vec<(String, u32)>,
    /// The points whose series are kept.
    pub points: Vec<usize>,
}

/// A resolved sweep: the model, the points, the run and what to keep.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The model's source.
    pub source: Source,
    /// The scene text that is run (the scene file, or the FMU's `resources/scene.toml`).
    pub scene_text: String,
    /// Start time [s].
    pub start_time: f64,
    /// Stop time [s].
    pub stop_time: f64,
    /// Communication step [s].
    pub step: f64,
    /// Number of steps `N = (stop - start) / step`.
    pub steps: usize,
    /// The variables set per point, in file order.
    pub settings: Vec<Setting>,
    /// Per point, one value per setting.
    pub points: Vec<Vec<Value>>,
    /// Time-varying inputs, if any.
    pub inputs: Option<InputTable>,
    /// Outputs and reductions kept.
    pub outputs: Vec<OutputSpec>,
    /// Time series kept, if any.
    pub series: Option<SeriesSpec>,
}

impl Sweep {
    /// Communication point `k`: `start + k step`.
    pub fn time(&self, k: usize) -> f64 {
        self.start_time + k as f64 * self.step
    }

    /// Column headers of the results: `point`, the settings, `output:reduction` per output
    /// and reduction, `status`.
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["point".to_string()];
        h.extend(self.settings.iter().map(|s| s.name.clone()));
        for o in &self.outputs {
            h.extend(
                o.reductions
                    .iter()
                    .map(|r| format!("{}:{}", o.name, r.name())),
            );
        }
        h.push("status".into());
        h
    }
}

/// Reads and resolves a sweep file; relative paths in it are relative to its directory.
pub fn read_sweep(path: &Path) -> Result<Sweep, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    parse_sweep(&text, &dir).map_err(|e| format!("{}: {e}", path.display()))
}

fn absolute(dir: &Path, p: &str) -> PathBuf {
    let p = Path::new(p);
    let joined = if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    };
    std::path::absolute(&joined).unwrap_or(joined)
}

/// The `resources/scene.toml` of an FMU.
pub fn scene_of_fmu(fmu: &Path) -> Result<String, String> {
    use std::io::Read;
    let file =
        std::fs::File::open(fmu).map_err(|e| format!("cannot open {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| format!("{} is not an FMU (zip): {e}", fmu.display()))?;
    let mut entry = zip
        .by_name(&format!("resources/{}", crate::instance::SCENE_FILE))
        .map_err(|_| {
            format!(
                "{} has no resources/{}: not an FMU built by flexfmu",
                fmu.display(),
                crate::instance::SCENE_FILE
            )
        })?;
    let mut s = String::new();
    entry
        .read_to_string(&mut s)
        .map_err(|e| format!("{}: {e}", fmu.display()))?;
    Ok(s)
}

/// Parses sweep text; `dir` resolves relative paths. Errors name the key.
pub fn parse_sweep(text: &str, dir: &Path) -> Result<Sweep, String> {
    let de = toml::Deserializer::parse(text).map_err(|e| format!("sweep file: {e}"))?;
    let f: SweepFile = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let msg = inner.message().trim().to_string();
        if path == "." {
            format!("sweep file: {msg}")
        } else {
            format!("sweep file, key `{path}`: {msg}")
        }
    })?;
    let (source, scene_text) = match (&f.scene, &f.fmu) {
        (Some(s), None) => {
            let p = absolute(dir, s);
            let t = std::fs::read_to_string(&p)
                .map_err(|e| format!("key `scene`: cannot read {}: {e}", p.display()))?;
            (Source::Scene(p), t)
        }
        (None, Some(s)) => {
            let p = absolute(dir, s);
            let t = scene_of_fmu(&p).map_err(|e| format!("key `fmu`: {e}"))?;
            (Source::Fmu(p), t)
        }
        _ => return Err("give exactly one of the keys `scene` and `fmu`".into()),
    };
    let scene = Scene::from_toml(&scene_text).map_err(|e| format!("the model's {}", e.0))?;
    let vars = VariableTable::from_scene(&scene);

    let RunTable {
        start_time,
        stop_time,
        step,
    } = f.run;
    if !(start_time.is_finite() && stop_time.is_finite() && stop_time > start_time) {
        return Err(format!(
            "key `run.stop_time`: must be a finite time after run.start_time ({start_time} s), got {stop_time}"
        ));
    }
    if !(step.is_finite() && step > 0.0) {
        return Err(format!("key `run.step`: must be a time > 0, got {step}"));
    }
    let n = ((stop_time - start_time) / step).round();
    if n < 1.0 || ((start_time + n * step) - stop_time).abs() > 1e-9 * (stop_time - start_time) {
        return Err(format!(
            "key `run.step`: {step} s does not divide the run from {start_time} to {stop_time} s into whole steps"
        ));
    }
    let steps = n as usize;

    // settings: grid axes and Latin hypercube dimensions
    let mut settings = Vec::new();
    let mut axes: Vec<Vec<Value>> = Vec::new();
    let mut lhs_ranges = Vec::new();
    let mut lhs_columns = Vec::new();
    for (i, p) in f.parameters.iter().enumerate() {
        let key = |k: &str| format!("key `parameters[{i}].{k}`");
        let v = vars.by_name(&p.name).ok_or_else(|| {
            format!(
                "{}: no parameter or input \"{}\" in model \"{}\"",
                key("name"),
                p.name,
                scene.model_name()
            )
        })?;
        if v.causality == Causality::Output {
            return Err(format!(
                "{}: \"{}\" is an output; sweep parameters and inputs",
                key("name"),
                p.name
            ));
        }
        if settings.iter().any(|s: &Setting| s.name == p.name) {
            return Err(format!("{}: \"{}\" appears twice", key("name"), p.name));
        }
        let given = [
            p.value.is_some(),
            p.values.is_some(),
            p.linspace.is_some(),
            p.lhs.is_some(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(format!(
                "key `parameters[{i}]` (\"{}\"): give exactly one of value, values, linspace, lhs",
                p.name
            ));
        }
        let convert = |k: &str, x: &toml::Value| -> Result<Value, String> {
            let bad = || {
                format!(
                    "{}: {x} is not a {:?} value for \"{}\"",
                    key(k),
                    v.ty,
                    p.name
                )
            };
            let val = match (v.ty, x) {
                (VarType::Real, toml::Value::Float(f)) => Value::Real(*f),
                (VarType::Real, toml::Value::Integer(n)) => Value::Real(*n as f64),
                (VarType::Integer, toml::Value::Integer(n)) => {
                    Value::Integer(i32::try_from(*n).map_err(|_| bad())?)
                }
                (VarType::Boolean, toml::Value::Boolean(b)) => Value::Boolean(*b),
                _ => return Err(bad()),
            };
            if let Value::Real(r) = val
                && !r.is_finite()
            {
                return Err(bad());
            }
            Ok(val)
        };
        let real_only = |k: &str| -> Result<(), String> {
            match v.ty {
                VarType::Real => Ok(()),
                t => Err(format!(
                    "{}: \"{}\" is {t:?}; {k} needs a Real variable (use `values`)",
                    key(k),
                    p.name
                )),
            }
        };
        let axis: Option<Vec<Value>> = if let Some(x) = &p.value {
            Some(vec![convert("value", x)?])
        } else if let Some(xs) = &p.values {
            if xs.is_empty() {
                return Err(format!("{}: empty list", key("values")));
            }
            Some(
                xs.iter()
                    .map(|x| convert("values", x))
                    .collect::<Result<_, _>>()?,
            )
        } else if let Some((lo, hi, n)) = p.linspace {
            real_only("linspace")?;
            if !(lo.is_finite() && hi.is_finite()) || n == 0 {
                return Err(format!(
                    "{}: give [first, last, count] with finite values and count >= 1",
                    key("linspace")
                ));
            }
            Some(linspace(lo, hi, n).into_iter().map(Value::Real).collect())
        } else {
            let [lo, hi] = p.lhs.expect("one key is given");
            real_only("lhs")?;
            if !(lo.is_finite() && hi.is_finite() && hi > lo) {
                return Err(format!(
                    "{}: give [low, high] with finite low < high",
                    key("lhs")
                ));
            }
            lhs_ranges.push([lo, hi]);
            lhs_columns.push(settings.len());
            None
        };
        let varies = axis.as_ref().is_none_or(|a| a.len() > 1);
        if let Some(a) = axis {
            axes.push(a);
        }
        settings.push(Setting {
            name: p.name.clone(),
            vr: v.vr,
            ty: v.ty,
            causality: v.causality,
            varies,
        });
    }
    let lhs = match (&f.sample, lhs_ranges.is_empty()) {
        (None, true) => None,
        (Some(s), false) => {
            if s.points == 0 {
                return Err("key `sample.points`: at least 1".into());
            }
            Some(latin_hypercube(&lhs_ranges, s.points, s.seed))
        }
        (None, false) => {
            return Err(
                "key `sample`: the `lhs` parameters need a [sample] table with `points` (and `seed`)"
                    .into(),
            );
        }
        (Some(_), true) => {
            return Err("key `sample`: no parameter has an `lhs` range to sample".into());
        }
    };
    let grid_points = grid(&axes);
    let mut points = Vec::new();
    for g in &grid_points {
        let samples: Vec<&[f64]> = match &lhs {
            Some(s) => s.iter().map(|r| r.as_slice()).collect(),
            None => vec![&[]],
        };
        for s in samples {
            let (mut gi, mut si) = (0, 0);
            let row = (0..settings.len())
                .map(|c| {
                    if lhs_columns.contains(&c) {
                        si += 1;
                        Value::Real(s[si - 1])
                    } else {
                        gi += 1;
                        g[gi - 1]
                    }
                })
                .collect();
            points.push(row);
        }
    }

    let inputs = match &f.inputs {
        None => None,
        Some(t) => {
            let p = absolute(dir, &t.csv);
            let table = read_input_csv(&p, &vars, &settings)
                .map_err(|e| format!("key `inputs.csv` ({}): {e}", p.display()))?;
            Some(table)
        }
    };

    let output = |key: String, name: &str| -> Result<u32, String> {
        match vars.by_name(name) {
            Some(v) if v.causality == Causality::Output && v.ty == VarType::Real => Ok(v.vr),
            Some(_) => Err(format!("{key}: \"{name}\" is not a Real output")),
            None => Err(format!(
                "{key}: no output \"{name}\" in model \"{}\"",
                scene.model_name()
            )),
        }
    };
    if f.outputs.is_empty() && f.series.is_none() {
        return Err("key `outputs`: name at least one output to keep".into());
    }
    let mut outputs = Vec::new();
    for (i, o) in f.outputs.iter().enumerate() {
        let vr = output(format!("key `outputs[{i}].name`"), &o.name)?;
        if o.reduce.is_empty() {
            return Err(format!(
                "key `outputs[{i}].reduce`: give at least one of final, max, min, mean, rms, max_abs"
            ));
        }
        outputs.push(OutputSpec {
            name: o.name.clone(),
            vr,
            reductions: o.reduce.clone(),
        });
    }
    let series = match &f.series {
        None => None,
        Some(s) => {
            let outs = s
                .outputs
                .iter()
                .enumerate()
                .map(|(i, n)| Ok((n.clone(), output(format!("key `series.outputs[{i}]`"), n)?)))
                .collect::<Result<Vec<_>, String>>()?;
            for (i, &p) in s.points.iter().enumerate() {
                if p >= points.len() {
                    return Err(format!(
                        "key `series.points[{i}]`: point {p} does not exist (the sweep has {} points, 0 to {})",
                        points.len(),
                        points.len() - 1
                    ));
                }
            }
            Some(SeriesSpec {
                outputs: outs,
                points: s.points.clone(),
            })
        }
    };
    Ok(Sweep {
        source,
        scene_text,
        start_time,
        stop_time,
        step,
        steps,
        settings,
        points,
        inputs,
        outputs,
        series,
    })
}

/// Reads an input CSV: a header `time,<input>,...` then rows of numbers.
fn read_input_csv(
    path: &Path,
    vars: &VariableTable,
    settings: &[Setting],
) -> Result<InputTable, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read: {e}"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    let (_, header) = lines.next().ok_or("empty file")?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names.first() != Some(&"time") || names.len() < 2 {
        return Err("the header must be `time,<input name>,...`".into());
    }
    let mut columns = Vec::new();
    for name in &names[1..] {
        match vars.by_name(name) {
            Some(v) if v.causality == Causality::Input && v.ty == VarType::Real => {
                if settings.iter().any(|s| s.name == *name) {
                    return Err(format!(
                        "input \"{name}\" is both a swept constant and a CSV column"
                    ));
                }
                columns.push((name.to_string(), v.vr, Vec::new()));
            }
            _ => {
                return Err(format!(
                    "column \"{name}\" is not a Real input of the model"
                ));
            }
        }
    }
    let mut time = Vec::new();
    for (ln, line) in lines {
        let vals = line
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("line {}: {e}", ln + 1))?;
        if vals.len() != names.len() || vals.iter().any(|v| !v.is_finite()) {
            return Err(format!(
                "line {}: {} finite numbers expected",
                ln + 1,
                names.len()
            ));
        }
        if time.last().is_some_and(|&t| vals[0] <= t) {
            return Err(format!("line {}: times must increase", ln + 1));
        }
        time.push(vals[0]);
        for (c, v) in columns.iter_mut().zip(&vals[1..]) {
            c.2.push(*v);
        }
    }
    if time.is_empty() {
        return Err("no rows".into());
    }
    Ok(InputTable { time, columns })
}
