//! Build script: collects the licences of the crates linked into the library
//! (`src/docs/license_collector.rs` over `cargo metadata`) into `$OUT_DIR/licenses.rs`, which
//! `src/docs/licenses.rs` embeds; `flexfmu build` writes them into every FMU's
//! `documentation/licenses/`.

#[path = "src/docs/license_collector.rs"]
#[allow(dead_code)]
mod license_collector;

use std::process::Command;

fn collect() -> Result<Vec<license_collector::CrateLicense>, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let manifest =
        std::path::Path::new(&std::env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?)
            .join("Cargo.toml");
    let target = std::env::var("TARGET").map_err(|e| e.to_string())?;
    let run = |offline: bool| {
        let mut c = Command::new(&cargo);
        c.args([
            "metadata",
            "--format-version",
            "1",
            "--filter-platform",
            &target,
        ])
        .arg("--manifest-path")
        .arg(&manifest);
        if offline {
            c.arg("--offline");
        }
        c.output()
    };
    // offline first: the build has every package it links already; online only as a fallback
    let mut out = run(true).map_err(|e| format!("cannot run cargo metadata: {e}"))?;
    if !out.status.success() {
        out = run(false).map_err(|e| format!("cannot run cargo metadata: {e}"))?;
    }
    if !out.status.success() {
        return Err(format!(
            "cargo metadata failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let text = String::from_utf8(out.stdout).map_err(|e| e.to_string())?;
    let mut crates = license_collector::collect(&license_collector::parse_json(&text)?)?;
    crates.insert(1, rust_std());
    Ok(crates)
}

/// The Rust standard library, linked statically into every Rust library: its licence
/// expression and the notice file the toolchain ships for binaries that contain it
/// (`<sysroot>/share/doc/rust/COPYRIGHT-library.html`, when the toolchain has it).
fn rust_std() -> license_collector::CrateLicense {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let run = |arg: &str| {
        Command::new(&rustc)
            .arg(arg)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let version = run("--version")
        .and_then(|v| v.split_whitespace().nth(1).map(String::from))
        .unwrap_or_default();
    let files = run("--print=sysroot")
        .map(|s| std::path::Path::new(&s).join("share/doc/rust/COPYRIGHT-library.html"))
        .filter(|p| p.is_file())
        .map(|p| vec![("COPYRIGHT-library.html".to_string(), p)])
        .unwrap_or_default();
    license_collector::CrateLicense {
        name: "rust-std".into(),
        version,
        license: "MIT OR Apache-2.0".into(),
        proc_macro: false,
        files,
    }
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/docs/license_collector.rs");
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=Cargo.lock");
    let source = match collect() {
        Ok(crates) => format!(
            "{}/// Why the licences could not be collected (none: they were).\npub static COLLECTION_ERROR: Option<&str> = None;\n",
            license_collector::rust_source(&crates)
        ),
        Err(e) => {
            println!("cargo:warning=licence collection failed: {e}");
            format!(
                "/// Nothing collected.\npub static CRATES: &[Crate] = &[];\n/// Why the licences could not be collected.\npub static COLLECTION_ERROR: Option<&str> = Some({e:?});\n"
            )
        }
    };
    let out = std::path::Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("licenses.rs");
    std::fs::write(&out, source).expect("writing OUT_DIR/licenses.rs");
}
