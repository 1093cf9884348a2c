//! Results as CSV (one row per point; series as `point,time,<outputs>`), merging the CSV
//! files of chunks, and the plan that the Python front end runs (JSON).

use super::run::PointResult;
use super::spec::{Source, Sweep};
use crate::variables::{Causality, Value};
use std::fmt::Write;
use std::path::Path;

/// Text of a value in the CSV: reals in their shortest round-trip form.
pub fn fmt_value(v: Value) -> String {
    match v {
        Value::Real(x) => format!("{x:?}"),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => b.to_string(),
    }
}

/// The results CSV: the header of [`Sweep::header`], then one row per result.
pub fn results_csv(sweep: &Sweep, results: &[PointResult]) -> String {
    let mut s = sweep.header().join(",");
    s.push('\n');
    for r in results {
        let mut row = vec![r.point.to_string()];
        row.extend(sweep.points[r.point].iter().map(|&v| fmt_value(v)));
        row.extend(r.values.iter().map(|x| format!("{x:?}")));
        row.push(r.status.replace([',', '\n', '\r'], ";"));
        s.push_str(&row.join(","));
        s.push('\n');
    }
    s
}

/// The series CSV (`point,time,<outputs>`), or `None` when the sweep keeps no series.
pub fn series_csv(sweep: &Sweep, results: &[PointResult]) -> Option<String> {
    let outs = &sweep.series.as_ref()?.outputs;
    let mut s = String::from("point,time");
    for (n, _) in outs {
        s.push(',');
        s.push_str(n);
    }
    s.push('\n');
    for r in results {
        for row in &r.series {
            let _ = write!(s, "{}", r.point);
            for x in row {
                let _ = write!(s, ",{x:?}");
            }
            s.push('\n');
        }
    }
    Some(s)
}

/// A CSV file as a header and rows of fields (no quoting: sweep CSVs have none).
#[derive(Clone, Debug, PartialEq)]
pub struct Csv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows, each as long as the header.
    pub rows: Vec<Vec<String>>,
}

impl Csv {
    /// Parses CSV text; `name` is used in messages.
    pub fn parse(text: &str, name: &str) -> Result<Self, String> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header: Vec<String> = lines
            .next()
            .ok_or_else(|| format!("{name}: empty file"))?
            .split(',')
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            let row: Vec<String> = l.split(',').map(str::to_string).collect();
            if row.len() != header.len() {
                return Err(format!(
                    "{name}: row {} has {} fields, the header {}",
                    i + 1,
                    row.len(),
                    header.len()
                ));
            }
            rows.push(row);
        }
        Ok(Self { header, rows })
    }

    /// The CSV text.
    pub fn text(&self) -> String {
        let mut s = self.header.join(",");
        s.push('\n');
        for r in &self.rows {
            s.push_str(&r.join(","));
            s.push('\n');
        }
        s
    }
}

/// Joins the CSV files of the chunks of one sweep (`flexfmu sweep --merge`): the headers must
/// agree; rows are ordered by `point` (stable, so a series keeps its time order). For results
/// (no `time` column) every point must appear once and the points must run from 0 without
/// gaps.
pub fn merge(files: &[(String, String)]) -> Result<Csv, String> {
    let mut out: Option<Csv> = None;
    for (name, text) in files {
        let c = Csv::parse(text, name)?;
        if c.header.first().map(String::as_str) != Some("point") {
            return Err(format!(
                "{name}: not a sweep result (first column is not `point`)"
            ));
        }
        match &mut out {
            None => out = Some(c),
            Some(o) => {
                if o.header != c.header {
                    return Err(format!(
                        "{name}: its columns differ from {}'s: not chunks of the same sweep",
                        files[0].0
                    ));
                }
                o.rows.extend(c.rows);
            }
        }
    }
    let mut out = out.ok_or("--merge: no files")?;
    let point = |r: &Vec<String>| {
        r[0].parse::<usize>()
            .map_err(|_| format!("bad point {}", r[0]))
    };
    for r in &out.rows {
        point(r)?;
    }
    out.rows
        .sort_by_key(|r| r[0].parse::<usize>().expect("checked above"));
    if !out.header.iter().any(|h| h == "time") {
        let points: Vec<usize> = out.rows.iter().map(point).collect::<Result<_, _>>()?;
        if let Some(w) = points.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!("point {} appears in more than one file", w[0]));
        }
        for (i, &p) in points.iter().enumerate() {
            if p != i {
                return Err(format!("points {i} to {} are missing", p - 1));
            }
        }
    }
    Ok(out)
}

/// Writes a merged or computed result next to `path` read from files.
pub fn read_files(paths: &[std::path::PathBuf]) -> Result<Vec<(String, String)>, String> {
    paths
        .iter()
        .map(|p| {
            std::fs::read_to_string(p)
                .map(|t| (p.display().to_string(), t))
                .map_err(|e| format!("cannot read {}: {e}", p.display()))
        })
        .collect()
}

fn json_str(s: &str) -> String {
    let mut o = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\u{:04x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

fn json_value(v: Value) -> String {
    match v {
        Value::Real(x) => format!("{x:?}"),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => b.to_string(),
    }
}

fn json_reals(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|x| format!("{x:?}")).collect();
    format!("[{}]", items.join(","))
}

/// The expanded sweep as JSON for the Python front end (`flexfmu sweep SWEEP --plan FILE`):
/// the model (`scene` or `fmu`, absolute), the run, the settings with value references and
/// types, every point, the input table, the outputs with their reductions, the series and the
/// column headers. Reals are written in their shortest round-trip form, so Python reads the
/// same doubles.
pub fn plan_json(sweep: &Sweep, chunk: std::ops::Range<usize>) -> String {
    let mut s = String::from("{\n");
    let (key, path) = match &sweep.source {
        Source::Scene(p) => ("scene", p),
        Source::Fmu(p) => ("fmu", p),
    };
    let _ = writeln!(
        s,
        "  {}: {},",
        json_str(key),
        json_str(&path.display().to_string())
    );
    let _ = writeln!(
        s,
        "  \"start_time\": {:?},\n  \"stop_time\": {:?},\n  \"step\": {:?},\n  \"steps\": {},",
        sweep.start_time, sweep.stop_time, sweep.step, sweep.steps
    );
    let settings: Vec<String> = sweep
        .settings
        .iter()
        .map(|st| {
            format!(
                "{{\"name\": {}, \"vr\": {}, \"type\": \"{:?}\", \"causality\": \"{}\", \"varies\": {}}}",
                json_str(&st.name),
                st.vr,
                st.ty,
                match st.causality {
                    Causality::Parameter => "parameter",
                    Causality::Input => "input",
                    Causality::Output => "output",
                },
                st.varies
            )
        })
        .collect();
    let _ = writeln!(s, "  \"settings\": [{}],", settings.join(", "));
    let points: Vec<String> = chunk
        .clone()
        .map(|p| {
            let vals: Vec<String> = sweep.points[p].iter().map(|&v| json_value(v)).collect();
            format!("[{p}, [{}]]", vals.join(", "))
        })
        .collect();
    let _ = writeln!(s, "  \"points\": [\n    {}\n  ],", points.join(",\n    "));
    match &sweep.inputs {
        None => s.push_str("  \"inputs\": null,\n"),
        Some(t) => {
            let cols: Vec<String> = t
                .columns
                .iter()
                .map(|(n, vr, ys)| {
                    format!(
                        "{{\"name\": {}, \"vr\": {vr}, \"values\": {}}}",
                        json_str(n),
                        json_reals(ys)
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "  \"inputs\": {{\"time\": {}, \"columns\": [{}]}},",
                json_reals(&t.time),
                cols.join(", ")
            );
        }
    }
    let outs: Vec<String> = sweep
        .outputs
        .iter()
        .map(|o| {
            let r: Vec<String> = o.reductions.iter().map(|r| json_str(r.name())).collect();
            format!(
                "{{\"name\": {}, \"vr\": {}, \"reduce\": [{}]}}",
                json_str(&o.name),
                o.vr,
                r.join(", ")
            )
        })
        .collect();
    let _ = writeln!(s, "  \"outputs\": [{}],", outs.join(", "));
    match &sweep.series {
        None => s.push_str("  \"series\": null,\n"),
        Some(series) => {
            let (outs, pts) = (&series.outputs, &series.points);
            let o: Vec<String> = outs
                .iter()
                .map(|(n, vr)| format!("{{\"name\": {}, \"vr\": {vr}}}", json_str(n)))
                .collect();
            let p: Vec<String> = pts.iter().map(usize::to_string).collect();
            let _ = writeln!(
                s,
                "  \"series\": {{\"outputs\": [{}], \"points\": [{}]}},",
                o.join(", "),
                p.join(", ")
            );
        }
    }
    let h: Vec<String> = sweep.header().iter().map(|x| json_str(x)).collect();
    let _ = writeln!(s, "  \"header\": [{}]", h.join(", "));
    s.push_str("}\n");
    s
}

/// Writes `text` to `path`, naming the path in the error.
pub fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
