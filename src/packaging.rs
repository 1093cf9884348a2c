//! Packaging an FMU: `modelDescription.xml`, `resources/scene.toml` and the shared library as
//! `binaries/<platform>/<modelIdentifier>.<ext>`, zipped.

use crate::instance::SCENE_FILE;
use crate::model_description::model_description;
use crate::scene::Scene;
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// FMI 2.0 platform folder and library extension of the machine flexfmu was built for.
pub fn platform() -> (&'static str, &'static str) {
    if cfg!(all(target_os = "linux", target_pointer_width = "64")) {
        ("linux64", "so")
    } else if cfg!(all(target_os = "linux", target_pointer_width = "32")) {
        ("linux32", "so")
    } else if cfg!(target_os = "macos") {
        ("darwin64", "dylib")
    } else if cfg!(all(target_os = "windows", target_pointer_width = "64")) {
        ("win64", "dll")
    } else {
        ("win32", "dll")
    }
}

/// File name of the flexfmu shared library cargo builds on this platform.
pub fn library_file_name() -> &'static str {
    if cfg!(target_os = "windows") {
        "flexfmu.dll"
    } else if cfg!(target_os = "macos") {
        "libflexfmu.dylib"
    } else {
        "libflexfmu.so"
    }
}

/// The shared library: `explicit`, else `$FLEXFMU_LIBRARY`, else next to the running executable.
pub fn find_library(explicit: Option<&Path>) -> Result<PathBuf, String> {
    if let Some(p) = explicit {
        return if p.is_file() {
            Ok(p.to_path_buf())
        } else {
            Err(format!("library {} does not exist", p.display()))
        };
    }
    if let Some(p) = std::env::var_os("FLEXFMU_LIBRARY") {
        let p = PathBuf::from(p);
        return if p.is_file() {
            Ok(p)
        } else {
            Err(format!("FLEXFMU_LIBRARY = {} does not exist", p.display()))
        };
    }
    let exe = std::env::current_exe()
        .map_err(|e| format!("cannot locate the flexfmu executable: {e}"))?;
    let dir = exe.parent().ok_or("the executable has no directory")?;
    let candidate = dir.join(library_file_name());
    if candidate.is_file() {
        Ok(candidate)
    } else {
        Err(format!(
            "cannot find {} next to {}; build it with `cargo build --release` or pass --library",
            library_file_name(),
            exe.display()
        ))
    }
}

/// Writes the FMU of `scene` with the shared library `library` to `out`.
pub fn build_fmu(scene: &Scene, library: &Path, out: &Path) -> Result<(), String> {
    let lib =
        std::fs::read(library).map_err(|e| format!("cannot read {}: {e}", library.display()))?;
    let xml = model_description(scene);
    let (plat, ext) = platform();
    let file =
        std::fs::File::create(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let entries: [(String, &[u8], u32); 3] = [
        ("modelDescription.xml".into(), xml.as_bytes(), 0o644),
        (
            format!("resources/{SCENE_FILE}"),
            scene.text.as_bytes(),
            0o644,
        ),
        (
            format!("binaries/{plat}/{}.{ext}", scene.model_name()),
            &lib,
            0o755,
        ),
    ];
    let err = |e: &dyn std::fmt::Display| format!("writing {}: {e}", out.display());
    for (name, data, mode) in entries {
        zip.start_file(name, opts.unix_permissions(mode))
            .map_err(|e| err(&e))?;
        zip.write_all(data).map_err(|e| err(&e))?;
    }
    zip.finish().map_err(|e| err(&e))?;
    Ok(())
}
