//! Parameter sweeps: `flexfmu sweep SWEEP.toml` (worker threads, each reusing one
//! [`crate::instance::Instance`] through fmi2Reset) and the plan that the Python front end
//! (`flexfmu.sweep` on dask) runs through the FMU.
//!
//! # The sweep file (TOML)
//! Relative paths are relative to the sweep file.
//! ```toml
//! scene = "../scenes/pendulum.toml"   # or: fmu = "pendulum.fmu" (built by `flexfmu build`)
//!
//! [run]
//! start_time = 0.0      # [s], default 0
//! stop_time = 0.05      # [s]
//! step = 1e-3           # communication step [s]; must divide the run into whole steps
//!
//! # The variables set per point, in order: parameters, or inputs held constant over the run.
//! # Each has exactly one of: value = x (a constant), values = [..] (a list), linspace =
//! # [first, last, count] (Real only), lhs = [low, high] (Real only: a Latin hypercube
//! # dimension). The grid (value, values, linspace) is the Cartesian product, the first entry
//! # varying slowest; with lhs entries every grid point is crossed with the same sample.
//! [[parameters]]
//! name = "material.E"
//! linspace = [1e7, 3e7, 5]
//! [[parameters]]
//! name = "mesh.n_elements"
//! values = [2, 4]
//! [[parameters]]
//! name = "geometry.height"
//! lhs = [0.08, 0.12]
//!
//! [sample]              # needed with lhs entries
//! points = 20
//! seed = 1              # default 0
//!
//! [inputs]              # optional: time signals for inputs, linear between the rows
//! csv = "signals.csv"   # header `time,<input>,...`
//!
//! [[outputs]]           # the reductions kept over the communication points t_0..t_N
//! name = "tip.y"
//! reduce = ["final", "min", "max", "mean", "rms", "max_abs"]
//!
//! [series]              # optional: whole time series of a few points
//! outputs = ["tip.x", "tip.y"]
//! points = [0, 9]
//! ```
//! Results: one CSV row per point, `point,<settings>,<output>:<reduction>...,status`
//! (`status` = `ok` or why the run stopped; its reductions are then NaN); the series in
//! `<stem>_series.csv` (`point,time,<outputs>`); for 1-D and 2-D sweeps a plot `<stem>.svg`.
//!
//! [`spec`]: the file and its checks; [`design`]: grids, Latin hypercube, chunks; [`run`]:
//! the worker threads; [`table`]: CSV, merge, the plan; [`plot`]: the SVG.

pub mod design;
pub mod plot;
pub mod run;
pub mod spec;
pub mod table;

pub use design::chunk_range;
pub use run::{PointResult, run_points};
pub use spec::{Reduction, Sweep, parse_sweep, read_sweep};

use std::path::{Path, PathBuf};

/// Parses `K/N` (`--chunk`): chunk K (1-based) of N.
pub fn parse_chunk(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("--chunk {s}: give K/N with 1 <= K <= N, e.g. 3/10");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let k: usize = k.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The points that chunk `chunk` (K, N) of `sweep` runs (all without a chunk).
pub fn points_of(sweep: &Sweep, chunk: Option<(usize, usize)>) -> std::ops::Range<usize> {
    match chunk {
        None => 0..sweep.points.len(),
        Some((k, n)) => chunk_range(sweep.points.len(), k, n),
    }
}

/// `<dir>/<stem><suffix>` next to `out`.
pub fn sibling(out: &Path, suffix: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "sweep".into());
    out.with_file_name(format!("{stem}{suffix}"))
}

/// Writes the results CSV to `out`, the series next to it and, when `plot` and the sweep is
/// 1-D or 2-D, the SVG plot; returns the files written.
pub fn write_results(
    sweep: &Sweep,
    results: &[PointResult],
    out: &Path,
    plot: bool,
) -> Result<Vec<PathBuf>, String> {
    let csv = table::results_csv(sweep, results);
    table::write(out, &csv)?;
    let mut written = vec![out.to_path_buf()];
    if let Some(series) = table::series_csv(sweep, results) {
        let p = sibling(out, "_series.csv");
        table::write(&p, &series)?;
        written.push(p);
    }
    if plot && let Some(svg) = plot::plot_svg(&table::Csv::parse(&csv, "results")?) {
        let p = out.with_extension("svg");
        table::write(&p, &svg)?;
        written.push(p);
    }
    Ok(written)
}

/// `flexfmu sweep --merge FILES -o OUT`: joins chunk results (and, for results, writes the
/// plot of a 1-D or 2-D sweep next to `out`); returns the files written.
pub fn merge_files(files: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>, String> {
    let merged = table::merge(&table::read_files(files)?)?;
    table::write(out, &merged.text())?;
    let mut written = vec![out.to_path_buf()];
    if !merged.header.iter().any(|h| h == "time")
        && let Some(svg) = plot::plot_svg(&merged)
    {
        let p = out.with_extension("svg");
        table::write(&p, &svg)?;
        written.push(p);
    }
    Ok(written)
}
