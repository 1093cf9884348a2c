//! Packaging an FMU: `modelDescription.xml`, `resources/scene.toml`, the documentation,
//! licences, icon and terminals ([`crate::docs`]), the FMI-LS-REF reference files
//! ([`crate::ls_ref`]) and one shared library per platform as
//! `binaries/<platform>/<modelIdentifier>.<ext>`, zipped; adding platforms to an existing FMU.

use crate::docs::documentation_files;
use crate::docs::osp::{osp_file_name, osp_model_description};
use crate::docs::terminals::terminals;
use crate::instance::SCENE_FILE;
use crate::ls_ref::ls_ref_files;
use crate::model_description::model_description;
use crate::scene::Scene;
use crate::variables::VariableTable;
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

/// Every FMI 2.0 binary folder flexfmu knows ([`platform_folder`] over the architectures
/// and systems it names).
pub fn known_platforms() -> Vec<&'static str> {
    let mut out = Vec::new();
    for arch in ["x86", "x86_64", "arm", "aarch64"] {
        for os in ["windows", "linux", "macos"] {
            if let Ok((p, _)) = platform_folder(arch, os) {
                out.push(p);
            }
        }
    }
    out
}

/// The library extension of an FMI 2.0 binary folder (`win64` → `dll`, `aarch64-darwin` →
/// `dylib`), or an error naming the known folders.
pub fn platform_extension(folder: &str) -> Result<&'static str, String> {
    for arch in ["x86", "x86_64", "arm", "aarch64"] {
        for os in ["windows", "linux", "macos"] {
            if let Ok((p, ext)) = platform_folder(arch, os)
                && p == folder
            {
                return Ok(ext);
            }
        }
    }
    Err(format!(
        "\"{folder}\" is no FMI 2.0 binary folder; known: {}",
        known_platforms().join(", ")
    ))
}

/// A shared library to package and the binary folder it goes to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlatformLibrary {
    /// FMI 2.0 binary folder, e.g. `linux64`, `aarch64-darwin`.
    pub platform: String,
    /// The library file (any name: it is renamed to `<modelIdentifier>.<ext>`).
    pub path: PathBuf,
}

/// Reads a `--library` argument: `PLATFORM=PATH` (an FMI 2.0 binary folder name) or a bare
/// `PATH` for this machine's platform.
pub fn parse_library_arg(arg: &str) -> Result<PlatformLibrary, String> {
    if let Some((p, path)) = arg.split_once('=')
        && !p.contains(['/', '\\'])
    {
        platform_extension(p).map_err(|e| format!("--library {arg}: {e}"))?;
        if path.is_empty() {
            return Err(format!("--library {arg}: give PLATFORM=PATH"));
        }
        return Ok(PlatformLibrary {
            platform: p.to_string(),
            path: PathBuf::from(path),
        });
    }
    Ok(PlatformLibrary {
        platform: platform()?.0.to_string(),
        path: PathBuf::from(arg),
    })
}

/// The binary entries `binaries/<platform>/<model_identifier>.<ext>` of `libraries`; two
/// libraries for one platform or an unreadable file are errors.
fn binary_entries(
    libraries: &[PlatformLibrary],
    model_identifier: &str,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut out: Vec<(String, Vec<u8>)> = Vec::new();
    for l in libraries {
        let ext = platform_extension(&l.platform)?;
        let name = format!("binaries/{}/{model_identifier}.{ext}", l.platform);
        if out.iter().any(|(n, _)| *n == name) {
            return Err(format!("two libraries for platform {}", l.platform));
        }
        let data =
            std::fs::read(&l.path).map_err(|e| format!("cannot read {}: {e}", l.path.display()))?;
        out.push((name, data));
    }
    Ok(out)
}

fn write_zip(out: &Path, entries: &[(String, Vec<u8>)]) -> Result<(), String> {
    let file =
        std::fs::File::create(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let err = |e: &dyn std::fmt::Display| format!("writing {}: {e}", out.display());
    for (name, data) in entries {
        let mode = if name.starts_with("binaries/") {
            0o755
        } else {
            0o644
        };
        zip.start_file(name.as_str(), opts.unix_permissions(mode))
            .map_err(|e| err(&e))?;
        zip.write_all(data).map_err(|e| err(&e))?;
    }
    zip.finish().map_err(|e| err(&e))?;
    Ok(())
}

/// Writes the FMU of `scene` to `out` with one shared library per platform: the model
/// description, the scene (`resources/`), the documentation, licences, icon and terminals
/// ([`crate::docs::documentation_files`]), the FMI-LS-REF files
/// ([`crate::ls_ref::ls_ref_files`]: runs the smoke test) and `binaries/<platform>/`; and,
/// next to it, the
/// OSP side file `<stem>_OspModelDescription.xml`. Returns the paths written.
pub fn build_fmu(
    scene: &Scene,
    libraries: &[PlatformLibrary],
    out: &Path,
) -> Result<Vec<PathBuf>, String> {
    if libraries.is_empty() {
        return Err("no shared library to package".into());
    }
    let mut entries: Vec<(String, Vec<u8>)> = vec![(
        "modelDescription.xml".into(),
        model_description(scene).into_bytes(),
    )];
    for f in documentation_files(scene)?
        .into_iter()
        .chain(ls_ref_files(scene)?)
    {
        entries.push((f.path, f.data));
    }
    entries.push((
        format!("resources/{SCENE_FILE}"),
        scene.text.clone().into_bytes(),
    ));
    entries.extend(binary_entries(libraries, scene.model_name())?);
    write_zip(out, &entries)?;
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| scene.model_name().to_string());
    let side = out.with_file_name(osp_file_name(&stem));
    let ports = terminals(&VariableTable::from_scene(scene));
    std::fs::write(&side, osp_model_description(&ports))
        .map_err(|e| format!("cannot write {}: {e}", side.display()))?;
    Ok(vec![out.to_path_buf(), side])
}

/// The `modelIdentifier` of the CoSimulation element of a model description.
pub fn model_identifier(model_description_xml: &str) -> Result<String, String> {
    let mut r = quick_xml::Reader::from_str(model_description_xml);
    loop {
        match r.read_event() {
            Ok(quick_xml::events::Event::Start(e) | quick_xml::events::Event::Empty(e))
                if e.name().as_ref() == "CoSimulation" =>
            {
                for a in e.attributes().flatten() {
                    if a.key.as_ref() == "modelIdentifier" {
                        return Ok(a.value.to_string());
                    }
                }
                return Err("CoSimulation without modelIdentifier".into());
            }
            Ok(quick_xml::events::Event::Eof) => {
                return Err("modelDescription.xml has no CoSimulation element".into());
            }
            Err(e) => return Err(format!("modelDescription.xml: {e}")),
            _ => {}
        }
    }
}

/// Copies the FMU `fmu` to `out` with the libraries `libraries` added (or replacing the
/// library of the same platform): one flexfmu library serves every scene, so an FMU built on
/// one machine takes the libraries built on others. Returns the binary folders of `out`.
pub fn add_platforms(
    fmu: &Path,
    libraries: &[PlatformLibrary],
    out: &Path,
) -> Result<Vec<String>, String> {
    let file =
        std::fs::File::open(fmu).map_err(|e| format!("cannot open {}: {e}", fmu.display()))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| format!("{}: not a zip archive: {e}", fmu.display()))?;
    let mut entries: Vec<(String, Vec<u8>)> = Vec::new();
    for k in 0..zip.len() {
        let mut f = zip
            .by_index(k)
            .map_err(|e| format!("{}: {e}", fmu.display()))?;
        if f.is_dir() {
            continue;
        }
        let name = f
            .name()
            .map_err(|e| format!("{}: {e}", fmu.display()))?
            .to_string();
        let mut data = Vec::new();
        std::io::Read::read_to_end(&mut f, &mut data)
            .map_err(|e| format!("{}: {name}: {e}", fmu.display()))?;
        entries.push((name, data));
    }
    let md = entries
        .iter()
        .find(|(n, _)| n == "modelDescription.xml")
        .ok_or_else(|| format!("{}: no modelDescription.xml", fmu.display()))?;
    let id = model_identifier(&String::from_utf8_lossy(&md.1))?;
    let new = binary_entries(libraries, &id)?;
    entries.retain(|(n, _)| {
        !libraries
            .iter()
            .any(|l| n.starts_with(&format!("binaries/{}/", l.platform)))
    });
    entries.extend(new);
    write_zip(out, &entries)?;
    let mut platforms: Vec<String> = entries
        .iter()
        .filter_map(|(n, _)| {
            n.strip_prefix("binaries/")?
                .split('/')
                .next()
                .map(String::from)
        })
        .collect();
    platforms.sort();
    platforms.dedup();
    Ok(platforms)
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
    fn library_arguments_name_fmi2_folders() {
        let l = parse_library_arg("win64=/tmp/flexfmu.dll").unwrap();
        assert_eq!(l.platform, "win64");
        assert_eq!(l.path, PathBuf::from("/tmp/flexfmu.dll"));
        let here = parse_library_arg("target/release/libflexfmu.so").unwrap();
        assert_eq!(here.platform, platform().unwrap().0);
        // a folder FMI 2.0.4 does not name is refused, by name
        let e = parse_library_arg("x86_64-linux=/tmp/a.so").unwrap_err();
        assert!(e.contains("x86_64-linux") && e.contains("linux64"), "{e}");
        assert!(parse_library_arg("linux64=").is_err());
        assert_eq!(platform_extension("aarch64-darwin"), Ok("dylib"));
        assert_eq!(platform_extension("win32"), Ok("dll"));
        assert_eq!(known_platforms().len(), 11);
    }

    #[test]
    fn this_machine_is_known() {
        let (folder, ext) = platform().unwrap();
        assert!(library_file_name().ends_with(ext), "{folder} {ext}");
    }
}
