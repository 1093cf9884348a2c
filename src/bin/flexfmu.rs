//! `flexfmu`: build FMUs from scene files.
#![deny(unsafe_code)]

use clap::{Parser, Subcommand};
use flexfmu::cli::check_path;
use flexfmu::model_description::model_description;
use flexfmu::packaging::{build_fmu, find_library};
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
        /// Shared library to package (default: libflexfmu next to this executable).
        #[arg(long)]
        library: Option<PathBuf>,
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
            let lib = find_library(library.as_deref())?;
            build_fmu(&sc, &lib, &out)?;
            println!("wrote {}", out.display());
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
