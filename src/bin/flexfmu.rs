//! `flexfmu`: build FMUs from scene files.
#![deny(unsafe_code)]

use clap::{Parser, Subcommand};
use flexfmu::advise::{AdviseOptions, Signals, advise, report};
use flexfmu::cli::check_path;
use flexfmu::model_description::model_description;
use flexfmu::packaging::{
    PlatformLibrary, add_platforms, build_fmu, find_library, parse_library_arg, platform,
};
use flexfmu::scene::Scene;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "flexfmu",
    version,
    about = "Flexible bodies as FMI 2.0 Co-Simulation units"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build an FMU from a scene file.
    Build {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output .fmu file (default: <model_name>.fmu).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Shared library to package: PLATFORM=PATH with an FMI 2.0 binary folder (linux64,
        /// win64, darwin64, aarch64-darwin, aarch64-linux, ...), or a bare PATH for this
        /// machine; repeat for more platforms (default: libflexfmu next to this executable).
        #[arg(long)]
        library: Vec<String>,
    },
    /// Copy an FMU with more platforms: libraries built elsewhere are added as
    /// binaries/<PLATFORM>/ (one flexfmu library serves every scene).
    AddPlatforms {
        /// Existing FMU.
        fmu: PathBuf,
        /// PLATFORM=PATH, repeatable.
        #[arg(long, required = true)]
        library: Vec<String>,
        /// Output .fmu file (default: overwrite the input).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Print (or write) the modelDescription.xml of scene files.
    Xml {
        /// Scene files.
        scenes: Vec<PathBuf>,
        /// Write <model_name>.xml into this directory instead of printing.
        #[arg(long)]
        out_dir: Option<PathBuf>,
    },
    /// Check scene files: parse, validate, and build the model with the default parameters.
    Check {
        /// Scene files.
        scenes: Vec<PathBuf>,
    },
    /// Generate a level-3 air-spring scene (effective-area table with the gas law) from a
    /// membrane-level air-spring scene: constant-pressure equilibria over the heights.
    AirSpringTable {
        /// Membrane-level air-spring scene (TOML).
        scene: PathBuf,
        /// Output scene file.
        #[arg(short, long)]
        output: PathBuf,
        /// Heights MIN:MAX:COUNT [m] of the top plate above the piston base.
        #[arg(long, default_value = "0.18:0.32:29")]
        heights: String,
        /// Reference gauge pressure [Pa] (default: gas.pressure_design).
        #[arg(long)]
        pressure: Option<f64>,
        /// Model name of the new scene (default: the old one with `_table`).
        #[arg(long)]
        name: Option<String>,
        /// Elements along the sleeve for the membrane solves (default: the scene's mesh).
        #[arg(long)]
        elements: Option<usize>,
    },
    /// Run a parameter sweep (sweep file: see `flexfmu::sweep`): worker threads, each reusing
    /// one instance; results as CSV (one row per point), a plot for 1-D and 2-D sweeps.
    Sweep {
        /// Sweep file (TOML); not with --merge.
        sweep: Option<PathBuf>,
        /// Output CSV (default: <sweep file stem>.csv; with --chunk K/N: ..._K_of_N.csv).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Worker threads (default: the available cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Run only slice K of N (1-based), e.g. from a batch array job; join with --merge.
        #[arg(long)]
        chunk: Option<String>,
        /// Join the result CSVs of chunks into -o (no sweep file).
        #[arg(long, num_args = 1.., conflicts_with_all = ["sweep", "chunk", "plan"])]
        merge: Vec<PathBuf>,
        /// Write the expanded sweep (points, value references, run) as JSON for the Python
        /// front end instead of running it.
        #[arg(long)]
        plan: Option<PathBuf>,
        /// No progress on stderr.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Advise the cheapest configuration of a scene (element family, element count,
    /// integrator, internal step, adaptive tolerance, contact points) whose error on one output
    /// stays within TOL over the run, from a convergence study with Richardson extrapolation;
    /// writes the advised scene, the table (CSV) and a Pareto plot (SVG).
    Advise {
        /// Scene file (TOML).
        scene: PathBuf,
        /// The output whose error counts (e.g. tip.y).
        #[arg(long)]
        output: String,
        /// Admissible error on that output, max over the run, in its unit.
        #[arg(long)]
        tol: f64,
        /// End of the run [s] (default: the scene's stop time).
        #[arg(long)]
        stop_time: Option<f64>,
        /// Input signals: CSV with a `time` column and one column per scene input.
        #[arg(long)]
        inputs: Option<PathBuf>,
        /// Allow another element family even when the families' converged answers differ by
        /// more than TOL.
        #[arg(long)]
        allow_element_change: bool,
        /// Refinement levels per ladder (at least 3).
        #[arg(long, default_value_t = 4)]
        levels: usize,
        /// How many levels are finer than the scene's own values.
        #[arg(long, default_value_t = 1)]
        finer: usize,
        /// Knob to keep at the scene's value instead of studying it (a parameter name such as
        /// solver.integrator); repeatable.
        #[arg(long)]
        keep: Vec<String>,
        /// Worker threads (default: the cores, at most 2).
        #[arg(long)]
        jobs: Option<usize>,
        /// Advised scene file (default: <scene>_advised.toml); the table and plot are
        /// written next to it as <name>_table.csv and <name>_pareto.svg.
        #[arg(short = 'o', long = "out")]
        out: Option<PathBuf>,
    },
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Build {
            scene,
            output,
            library,
        } => {
            let sc = Scene::from_path(&scene).map_err(|e| e.0)?;
            let out = output.unwrap_or_else(|| PathBuf::from(format!("{}.fmu", sc.model_name())));
            let libs = if library.is_empty() {
                vec![PlatformLibrary {
                    platform: platform()?.0.to_string(),
                    path: find_library(None)?,
                }]
            } else {
                library
                    .iter()
                    .map(|a| parse_library_arg(a))
                    .collect::<Result<Vec<_>, _>>()?
            };
            for path in build_fmu(&sc, &libs, &out)? {
                println!("wrote {}", path.display());
            }
        }
        Cmd::AddPlatforms {
            fmu,
            library,
            output,
        } => {
            let libs = library
                .iter()
                .map(|a| parse_library_arg(a))
                .collect::<Result<Vec<_>, _>>()?;
            let out = output.unwrap_or_else(|| fmu.clone());
            // read fully before writing: the output may be the input
            let tmp = out.with_extension("fmu.tmp");
            let platforms = add_platforms(&fmu, &libs, &tmp)?;
            std::fs::rename(&tmp, &out).map_err(|e| format!("{}: {e}", out.display()))?;
            println!(
                "wrote {} (binaries: {})",
                out.display(),
                platforms.join(", ")
            );
        }
        Cmd::Xml { scenes, out_dir } => {
            for path in scenes {
                let sc = Scene::from_path(&path).map_err(|e| e.0)?;
                let xml = model_description(&sc);
                match &out_dir {
                    Some(dir) => {
                        let out = dir.join(format!("{}.xml", sc.model_name()));
                        std::fs::write(&out, xml).map_err(|e| format!("{}: {e}", out.display()))?;
                        println!("wrote {}", out.display());
                    }
                    None => print!("{xml}"),
                }
            }
        }
        Cmd::AirSpringTable {
            scene,
            output,
            heights,
            pressure,
            name,
            elements,
        } => {
            let parts: Vec<&str> = heights.split(':').collect();
            let bad = || format!("--heights {heights}: give MIN:MAX:COUNT, e.g. 0.18:0.32:29");
            if parts.len() != 3 {
                return Err(bad());
            }
            let lo: f64 = parts[0].parse().map_err(|_| bad())?;
            let hi: f64 = parts[1].parse().map_err(|_| bad())?;
            let n: usize = parts[2].parse().map_err(|_| bad())?;
            if n < 4 || hi <= lo || !hi.is_finite() || !lo.is_finite() || lo <= 0.0 {
                return Err(bad());
            }
            if pressure.is_some_and(|p| !(p.is_finite() && p > 0.0)) {
                return Err("--pressure: a positive gauge pressure [Pa]".into());
            }
            let hs: Vec<f64> = (0..n)
                .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
                .collect();
            let text = std::fs::read_to_string(&scene)
                .map_err(|e| format!("cannot read {}: {e}", scene.display()))?;
            let sc = Scene::from_toml(&text).map_err(|e| e.0)?;
            let name = name.unwrap_or_else(|| format!("{}_table", sc.model_name()));
            let out = flexfmu::kinds::air_spring::table::generate(
                &text,
                &hs,
                pressure,
                elements,
                &name,
                &mut |done, total| eprint!("\rheight {done}/{total}"),
            )?;
            eprintln!();
            std::fs::write(&output, out).map_err(|e| format!("{}: {e}", output.display()))?;
            println!("wrote {}", output.display());
        }
        Cmd::Sweep {
            sweep,
            output,
            threads,
            chunk,
            merge,
            plan,
            quiet,
        } => sweep_command(sweep, output, threads, chunk, merge, plan, quiet)?,
        Cmd::Advise {
            scene,
            output,
            tol,
            stop_time,
            inputs,
            allow_element_change,
            levels,
            finer,
            keep,
            jobs,
            out,
        } => {
            let sc = Scene::from_path(&scene).map_err(|e| e.0)?;
            let mut opts = AdviseOptions::new(&output, tol);
            opts.stop_time = stop_time;
            opts.allow_element_change = allow_element_change;
            opts.levels = levels;
            opts.finer = finer;
            opts.keep = keep;
            if let Some(j) = jobs {
                opts.jobs = j;
            }
            if let Some(path) = inputs {
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| format!("cannot read inputs {}: {e}", path.display()))?;
                opts.inputs = Some(
                    Signals::parse(&text, &sc).map_err(|e| format!("{}: {e}", path.display()))?,
                );
            }
            let advice = advise(&sc, &opts)?;
            let out = out.unwrap_or_else(|| {
                let stem = scene
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or("scene");
                PathBuf::from(format!("{stem}_advised.toml"))
            });
            let write = |p: &std::path::Path, text: &str| {
                std::fs::write(p, text).map_err(|e| format!("cannot write {}: {e}", p.display()))
            };
            if out == scene {
                return Err(format!(
                    "-o {}: the advised scene would overwrite the original",
                    out.display()
                ));
            }
            let stem = out
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("advised");
            let csv = out.with_file_name(format!("{stem}_table.csv"));
            let svg = out.with_file_name(format!("{stem}_pareto.svg"));
            write(&csv, &report::csv(&advice))?;
            write(&svg, &report::pareto_svg(&advice))?;
            println!("{}", report::markdown(&advice));
            print!("{}", report::summary(&advice));
            println!("wrote {} and {}", csv.display(), svg.display());
            let text = report::advised_scene(&sc, &advice)?;
            write(&out, &text)?;
            println!("wrote {}", out.display());
        }
        Cmd::Check { scenes } => {
            for path in scenes {
                let summary = check_path(&path)?;
                println!("{}: ok, {summary}", path.display());
            }
        }
    }
    Ok(())
}

/// `flexfmu sweep`.
fn sweep_command(
    sweep: Option<PathBuf>,
    output: Option<PathBuf>,
    threads: Option<usize>,
    chunk: Option<String>,
    merge: Vec<PathBuf>,
    plan: Option<PathBuf>,
    quiet: bool,
) -> Result<(), String> {
    use flexfmu::sweep;
    if !merge.is_empty() {
        let out = output.ok_or("--merge needs -o OUT.csv")?;
        for p in sweep::merge_files(&merge, &out)? {
            println!("wrote {}", p.display());
        }
        return Ok(());
    }
    let path = sweep.ok_or("give a sweep file (or --merge FILES -o OUT)")?;
    let sw = sweep::read_sweep(&path)?;
    let chunk = chunk.as_deref().map(sweep::parse_chunk).transpose()?;
    let range = sweep::points_of(&sw, chunk);
    if let Some(plan) = plan {
        std::fs::write(&plan, sweep::table::plan_json(&sw, range))
            .map_err(|e| format!("cannot write {}: {e}", plan.display()))?;
        println!("wrote {}", plan.display());
        return Ok(());
    }
    let out = output.unwrap_or_else(|| match chunk {
        None => path.with_extension("csv"),
        Some((k, n)) => sweep::sibling(&path, &format!("_{k}_of_{n}.csv")),
    });
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let start = std::time::Instant::now();
    let total_all = sw.points.len();
    let progress = |done: usize, total: usize| {
        if quiet {
            return;
        }
        let el = start.elapsed().as_secs_f64();
        let eta = el / done as f64 * (total - done) as f64;
        eprint!(
            "\rsweep: {done}/{total} points ({total_all} in the sweep), {el:.1} s, {eta:.0} s left   "
        );
    };
    let results = sweep::run_points(&sw, range, threads, &progress)?;
    if !quiet {
        eprintln!();
    }
    let failed = results.iter().filter(|r| r.status != "ok").count();
    for p in sweep::write_results(&sw, &results, &out, chunk.is_none())? {
        println!("wrote {}", p.display());
    }
    println!(
        "{} points in {:.2} s on {threads} threads, {failed} failed",
        results.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("flexfmu: error: {e}");
            ExitCode::FAILURE
        }
    }
}
