//! Packaging an FMU: `modelDescription.xml`, `resources/scene.toml` and the shared library as
//! `binaries/<platform>/<modelIdentifier>.<ext>`, zipped.

use crate::instance::SCENE_FILE;
use crate::model_description::model_description;
use crate::scene::Scene;
use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// The `binaries/` folder and library extension of a platform, given as Rust's
/// `std::env::consts::ARCH` and `OS` names.
///
/// FMI 2.0.4, section 2.3 ("FMU Distribution", directory `binaries`): the standardized names
/// are "win32", "win64", "linux32", "linux64", "darwin32", "darwin64", "where 32 stands for
/// 32-bit x86 and 64 for 64-bit x86"; "for any other platforms the platform tuples defined in
/// the FMI 3.0 Specification, 2.5.1.4.1 Platform Tuple Definition ... should be used", which
/// are `<arch>-<sys>` with arch `aarch32`, `aarch64`, `x86`, `x86_64` and sys `darwin`,
/// `linux`, `windows`. So an ARM machine (Apple silicon, ARM Linux, Windows on ARM) gets
/// `aarch64-darwin`, `aarch64-linux`, `aarch64-windows`, never `darwin64`. Other
/// architectures or systems have no standardized name and are rejected.
pub fn platform_folder(arch: &str, os: &str) -> Result<(&'static str, &'static str), String> {
    Ok(match (arch, os) {
        ("x86", "windows") => ("win32", "dll"),
        ("x86_64", "windows") => ("win64", "dll"),
        ("x86", "linux") => ("linux32", "so"),
        ("x86_64", "linux") => ("linux64", "so"),
        ("x86", "macos") => ("darwin32", "dylib"),
        ("x86_64", "macos") => ("darwin64", "dylib"),
        ("aarch64", "windows") => ("aarch64-windows", "dll"),
        ("aarch64", "linux") => ("aarch64-linux", "so"),
        ("aarch64", "macos") => ("aarch64-darwin", "dylib"),
        ("arm", "windows") => ("aarch32-windows", "dll"),
        ("arm", "linux") => ("aarch32-linux", "so"),
        _ => {
            return Err(format!(
                "no FMI 2.0 binary folder for architecture \"{arch}\" on \"{os}\": FMI 2.0.4 \
                 section 2.3 names x86 and x86_64 (win32/64, linux32/64, darwin32/64) and, \
                 through the FMI 3.0 platform tuples, aarch32 and aarch64 on darwin, linux \
                 and windows"
            ));
        }
    })
}

/// FMI 2.0 platform folder and library extension of the machine flexfmu was built for
/// ([`platform_folder`] of this target).
pub fn platform() -> Result<(&'static str, &'static str), String> {
    platform_folder(std::env::consts::ARCH, std::env::consts::OS)
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
    let (plat, ext) = platform()?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn x86_platforms_have_the_fmi2_names() {
        assert_eq!(platform_folder("x86", "windows"), Ok(("win32", "dll")));
        assert_eq!(platform_folder("x86_64", "windows"), Ok(("win64", "dll")));
        assert_eq!(platform_folder("x86", "linux"), Ok(("linux32", "so")));
        assert_eq!(platform_folder("x86_64", "linux"), Ok(("linux64", "so")));
        assert_eq!(platform_folder("x86", "macos"), Ok(("darwin32", "dylib")));
        assert_eq!(
            platform_folder("x86_64", "macos"),
            Ok(("darwin64", "dylib"))
        );
    }

    #[test]
    fn arm_platforms_have_platform_tuples() {
        assert_eq!(
            platform_folder("aarch64", "macos"),
            Ok(("aarch64-darwin", "dylib"))
        );
        assert_eq!(
            platform_folder("aarch64", "linux"),
            Ok(("aarch64-linux", "so"))
        );
        assert_eq!(
            platform_folder("aarch64", "windows"),
            Ok(("aarch64-windows", "dll"))
        );
        assert_eq!(platform_folder("arm", "linux"), Ok(("aarch32-linux", "so")));
        assert_eq!(
            platform_folder("arm", "windows"),
            Ok(("aarch32-windows", "dll"))
        );
    }

    #[test]
    fn unknown_platforms_are_rejected_by_name() {
        for (arch, os) in [
            ("riscv64", "linux"),
            ("powerpc64", "linux"),
            ("x86_64", "freebsd"),
            ("wasm32", "unknown"),
            ("aarch64", "android"),
        ] {
            let e = platform_folder(arch, os).unwrap_err();
            assert!(e.contains(arch) && e.contains(os), "{e}");
        }
    }

    #[test]
    fn this_machine_is_known() {
        let (folder, ext) = platform().unwrap();
        assert!(library_file_name().ends_with(ext), "{folder} {ext}");
    }
}
