//! Input signals for `flexfmu advise --inputs signals.csv`: a CSV file whose first column is
//! the time [s] and whose other columns are scene inputs by name, linearly interpolated
//! between rows and held at the first and last values outside them.

use crate::scene::Scene;
use crate::variables::{Role, VariableTable};

/// Input time histories read from a CSV file.
#[derive(Clone, Debug, PartialEq)]
pub struct Signals {
    /// Sample times [s], strictly increasing.
    pub times: Vec<f64>,
    /// For each column: the scene's input index and its values at `times`.
    pub columns: Vec<(usize, String, Vec<f64>)>,
}

impl Signals {
    /// Parses CSV text (header `time,<input>,...`, then rows of numbers) against the inputs of
    /// `scene`. Errors name the line, the column and the problem; an unknown column lists the
    /// scene's inputs.
    pub fn parse(text: &str, scene: &Scene) -> Result<Self, String> {
        let vars = VariableTable::from_scene(scene);
        let inputs: Vec<&str> = vars
            .vars()
            .iter()
            .filter(|v| matches!(v.role, Role::Input(_)))
            .map(|v| v.name.as_str())
            .collect();
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (_, header) = lines
            .next()
            .ok_or("inputs CSV: empty file (expected a header `time,<input>,...`)")?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        if !matches!(names[0], "time" | "t") {
            return Err(format!(
                "inputs CSV, line 1: the first column must be `time`, not `{}`",
                names[0]
            ));
        }
        if names.len() < 2 {
            return Err("inputs CSV, line 1: no input columns after `time`".into());
        }
        let mut columns = Vec::new();
        for (c, name) in names.iter().enumerate().skip(1) {
            let k = match vars.by_name(name).map(|v| v.role) {
                Some(Role::Input(k)) => k,
                _ => {
                    return Err(format!(
                        "inputs CSV, line 1, column {}: `{name}` is not an input of scene `{}`; its inputs are: {}",
                        c + 1,
                        scene.model_name(),
                        if inputs.is_empty() {
                            "(none)".to_string()
                        } else {
                            inputs.join(", ")
                        }
                    ));
                }
            };
            if columns.iter().any(|(j, _, _)| *j == k) {
                return Err(format!("inputs CSV, line 1: column `{name}` appears twice"));
            }
            columns.push((k, name.to_string(), Vec::new()));
        }
        let mut times: Vec<f64> = Vec::new();
        for (i, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(format!(
                    "inputs CSV, line {}: {} values, the header has {} columns",
                    i + 1,
                    cells.len(),
                    names.len()
                ));
            }
            let mut row = Vec::with_capacity(cells.len());
            for (c, cell) in cells.iter().enumerate() {
                let x: f64 = cell.parse().map_err(|_| {
                    format!(
                        "inputs CSV, line {}, column `{}`: `{cell}` is not a number",
                        i + 1,
                        names[c]
                    )
                })?;
                if !x.is_finite() {
                    return Err(format!(
                        "inputs CSV, line {}, column `{}`: {cell} is not finite",
                        i + 1,
                        names[c]
                    ));
                }
                row.push(x);
            }
            if let Some(&last) = times.last()
                && row[0] <= last
            {
                return Err(format!(
                    "inputs CSV, line {}: time {} does not increase (previous row: {last})",
                    i + 1,
                    row[0]
                ));
            }
            times.push(row[0]);
            for (col, x) in columns.iter_mut().zip(&row[1..]) {
                col.2.push(*x);
            }
        }
        if times.is_empty() {
            return Err("inputs CSV: a header but no rows".into());
        }
        Ok(Self { times, columns })
    }

    /// The same signals against the inputs of another scene (an element family's scene,
    /// whose inputs may be numbered differently): columns matched by name. Errors name the
    /// column the scene lacks.
    pub fn for_scene(&self, scene: &Scene) -> Result<Self, String> {
        let vars = VariableTable::from_scene(scene);
        let mut columns = Vec::with_capacity(self.columns.len());
        for (_, name, values) in &self.columns {
            match vars.by_name(name).map(|v| v.role) {
                Some(Role::Input(k)) => columns.push((k, name.clone(), values.clone())),
                _ => {
                    return Err(format!(
                        "`{name}` is not an input of scene `{}`",
                        scene.model_name()
                    ));
                }
            }
        }
        Ok(Self {
            times: self.times.clone(),
            columns,
        })
    }

    /// Column `c` at time `t`: value and slope of the piecewise linear interpolation (held
    /// constant, slope 0, outside the sampled times).
    pub fn at(&self, c: usize, t: f64) -> (f64, f64) {
        let y = &self.columns[c].2;
        let ts = &self.times;
        if t <= ts[0] {
            return (y[0], 0.0);
        }
        if t >= ts[ts.len() - 1] {
            return (y[y.len() - 1], 0.0);
        }
        let j = ts.partition_point(|&x| x <= t) - 1;
        let slope = (y[j + 1] - y[j]) / (ts[j + 1] - ts[j]);
        (y[j] + slope * (t - ts[j]), slope)
    }
}
