//! `flexfmu`: build FMUs from scene files.
#![deny(unsafe_code)]

use clap::{Parser, Subcommand};
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
        Cmd::Check { scenes } => {
            for path in scenes {
                let summary = check_path(&path)?;
                println!("{}: ok, {summary}", path.display());
            }
        }
    }
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
