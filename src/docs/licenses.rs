//! `documentation/licenses/`: flexfmu's licence and those of the crates linked into the
//! library, collected at build time by the build script with
//! [`super::license_collector`] from `cargo metadata` and the crates' own licence files.
//! FMI 2.0.4, section 2.3: "license.{txt,html} ... can serve as an entry point".

/// A crate of the library's dependency graph, with its licence files embedded.
#[derive(Clone, Copy, Debug)]
pub struct Crate {
    /// Crate name.
    pub name: &'static str,
    /// Version.
    pub version: &'static str,
    /// SPDX licence expression of its manifest (empty: none given).
    pub license: &'static str,
    /// Only a procedural macro: runs in the compiler, nothing of it is linked.
    pub proc_macro: bool,
    /// Its licence files: (file name, contents).
    pub files: &'static [(&'static str, &'static [u8])],
}

// `CRATES` (root package first) and `COLLECTION_ERROR`, written by build.rs.
include!(concat!(env!("OUT_DIR"), "/licenses.rs"));

/// The crates (flexfmu first), or why the build could not collect them.
pub fn crates() -> Result<&'static [Crate], &'static str> {
    match COLLECTION_ERROR {
        Some(e) => Err(e),
        None => Ok(CRATES),
    }
}

/// The files of `documentation/licenses/` (paths relative to it): `license.txt`, the entry
/// point listing every crate with its licence expression, and `<crate>-<version>/<file>` for
/// each crate's own licence files.
pub fn license_files() -> Result<Vec<(String, Vec<u8>)>, String> {
    let crates =
        crates().map_err(|e| format!("the licences were not collected at build time: {e}"))?;
    let (root, deps) = crates.split_first().ok_or("no crates collected")?;
    let mut txt = format!(
        "Licences of {name} {version}\n\n\
         {name} {version} is licensed under {license} (the `license` field of its Cargo.toml).\n\n\
         The FMU's shared library links the crates below (the normal dependency graph of the\n\
         {name} package for this target, from `cargo metadata`) and the Rust standard\n\
         library (`rust-std`, with the notice file of the toolchain). Each crate's licence\n\
         expression is the `license` field of its manifest; its licence files, copied from\n\
         its published source, are in the folder <crate>-<version>/ next to this file.\n\
         Procedural-macro crates run inside the compiler and are not linked; they are listed\n\
         for completeness.\n\n",
        name = root.name,
        version = root.version,
        license = if root.license.is_empty() {
            "(no licence declared)"
        } else {
            root.license
        },
    );
    let mut files = Vec::new();
    for f in root.files {
        files.push((f.0.to_string(), f.1.to_vec()));
    }
    let width = deps
        .iter()
        .map(|c| c.name.len() + c.version.len() + 1)
        .max()
        .unwrap_or(0);
    for c in deps {
        let id = format!("{}-{}", c.name, c.version);
        let names: Vec<&str> = c.files.iter().map(|f| f.0).collect();
        txt.push_str(&format!(
            "{id:<width$}  {}{}  [{}]\n",
            if c.license.is_empty() {
                "(none declared)"
            } else {
                c.license
            },
            if c.proc_macro {
                " (procedural macro, not linked)"
            } else {
                ""
            },
            if names.is_empty() {
                "no licence file in the published crate".to_string()
            } else {
                names.join(", ")
            },
        ));
        for (n, data) in c.files {
            files.push((format!("{id}/{n}"), data.to_vec()));
        }
    }
    files.insert(0, ("license.txt".to_string(), txt.into_bytes()));
    Ok(files)
}
