//! The licence tool behind `documentation/licenses/`: reads `cargo metadata --format-version 1
//! --filter-platform <target>` (Cargo book, "cargo metadata": `packages[]` with `license`,
//! `license_file`, `manifest_path` and `targets[].kind`; `resolve.nodes[].deps[].dep_kinds[]`
//! with `kind` null for normal dependencies), walks the normal dependencies of the root
//! package (the crates linked into the library) and finds each crate's own licence files in
//! its source folder. The build script (`build.rs`) runs it and embeds the result; this file
//! uses nothing outside `std`, so that the build script can include it by path.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A JSON value (RFC 8259), as much as `cargo metadata` needs.
#[derive(Clone, Debug, PartialEq)]
pub enum Json {
    /// `null`
    Null,
    /// `true` / `false`
    Bool(bool),
    /// A number, kept as its text.
    Number(String),
    /// A string.
    Str(String),
    /// An array.
    Array(Vec<Json>),
    /// An object (keys sorted).
    Object(BTreeMap<String, Json>),
}

impl Json {
    /// Member `key` of an object.
    pub fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Object(m) => m.get(key),
            _ => None,
        }
    }

    /// The string, if this is one.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Json::Str(s) => Some(s),
            _ => None,
        }
    }

    /// The elements, if this is an array (else none).
    pub fn items(&self) -> &[Json] {
        match self {
            Json::Array(v) => v,
            _ => &[],
        }
    }
}

/// Parses a JSON text; the error gives the byte offset.
pub fn parse_json(text: &str) -> Result<Json, String> {
    let mut p = Parser {
        s: text.as_bytes(),
        i: 0,
    };
    let v = p.value()?;
    p.ws();
    if p.i != p.s.len() {
        return Err(format!("JSON: trailing text at byte {}", p.i));
    }
    Ok(v)
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\n' | b'\r') {
            self.i += 1;
        }
    }

    fn err<T>(&self, what: &str) -> Result<T, String> {
        Err(format!("JSON: {what} at byte {}", self.i))
    }

    fn eat(&mut self, lit: &str) -> Result<(), String> {
        if self.s[self.i..].starts_with(lit.as_bytes()) {
            self.i += lit.len();
            Ok(())
        } else {
            self.err(&format!("expected {lit}"))
        }
    }

    fn value(&mut self) -> Result<Json, String> {
        self.ws();
        match self.s.get(self.i) {
            None => self.err("unexpected end"),
            Some(b'n') => self.eat("null").map(|_| Json::Null),
            Some(b't') => self.eat("true").map(|_| Json::Bool(true)),
            Some(b'f') => self.eat("false").map(|_| Json::Bool(false)),
            Some(b'"') => self.string().map(Json::Str),
            Some(b'[') => {
                self.i += 1;
                let mut v = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b']') {
                    self.i += 1;
                    return Ok(Json::Array(v));
                }
                loop {
                    v.push(self.value()?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Array(v));
                        }
                        _ => return self.err("expected , or ]"),
                    }
                }
            }
            Some(b'{') => {
                self.i += 1;
                let mut m = BTreeMap::new();
                self.ws();
                if self.s.get(self.i) == Some(&b'}') {
                    self.i += 1;
                    return Ok(Json::Object(m));
                }
                loop {
                    self.ws();
                    if self.s.get(self.i) != Some(&b'"') {
                        return self.err("expected a key");
                    }
                    let k = self.string()?;
                    self.ws();
                    self.eat(":")?;
                    let v = self.value()?;
                    m.insert(k, v);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Object(m));
                        }
                        _ => return self.err("expected , or }"),
                    }
                }
            }
            Some(c) if *c == b'-' || c.is_ascii_digit() => {
                let start = self.i;
                while self.i < self.s.len()
                    && matches!(
                        self.s[self.i],
                        b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9'
                    )
                {
                    self.i += 1;
                }
                Ok(Json::Number(
                    String::from_utf8_lossy(&self.s[start..self.i]).into_owned(),
                ))
            }
            Some(_) => self.err("unexpected character"),
        }
    }

    fn hex4(&mut self) -> Result<u32, String> {
        let h = self
            .s
            .get(self.i..self.i + 4)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u32::from_str_radix(h, 16).ok());
        match h {
            Some(v) => {
                self.i += 4;
                Ok(v)
            }
            None => self.err("bad \\u escape"),
        }
    }

    fn string(&mut self) -> Result<String, String> {
        self.i += 1; // opening quote
        let mut out: Vec<u8> = Vec::new();
        loop {
            let Some(&c) = self.s.get(self.i) else {
                return self.err("unterminated string");
            };
            self.i += 1;
            match c {
                b'"' => break,
                b'\\' => {
                    let Some(&e) = self.s.get(self.i) else {
                        return self.err("unterminated escape");
                    };
                    self.i += 1;
                    let ch = match e {
                        b'"' => '"',
                        b'\\' => '\\',
                        b'/' => '/',
                        b'b' => '\u{8}',
                        b'f' => '\u{c}',
                        b'n' => '\n',
                        b'r' => '\r',
                        b't' => '\t',
                        b'u' => {
                            let hi = self.hex4()?;
                            let code = if (0xd800..0xdc00).contains(&hi) {
                                self.eat("\\u")?;
                                let lo = self.hex4()?;
                                0x10000 + ((hi - 0xd800) << 10) + (lo.wrapping_sub(0xdc00) & 0x3ff)
                            } else {
                                hi
                            };
                            char::from_u32(code).unwrap_or('\u{fffd}')
                        }
                        _ => return self.err("bad escape"),
                    };
                    let mut buf = [0u8; 4];
                    out.extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
                }
                c => out.push(c),
            }
        }
        String::from_utf8(out).or_else(|_| self.err("invalid UTF-8 in a string"))
    }
}

/// One crate in the library's dependency graph and its licence.
#[derive(Clone, Debug, PartialEq)]
pub struct CrateLicense {
    /// Crate name.
    pub name: String,
    /// Version.
    pub version: String,
    /// SPDX licence expression from its manifest (empty if it gives none).
    pub license: String,
    /// Only a procedural macro (runs in the compiler, not linked into the library).
    pub proc_macro: bool,
    /// Its licence files: (file name, path on this machine).
    pub files: Vec<(String, PathBuf)>,
}

/// Whether a file name is a licence or notice text (`LICENSE`, `LICENSE-MIT`,
/// `LICENCE.md`, `COPYING`, `NOTICE`, `UNLICENSE`, any case).
pub fn is_license_file(name: &str) -> bool {
    let u = name.to_ascii_uppercase();
    [
        "LICENSE",
        "LICENCE",
        "COPYING",
        "NOTICE",
        "UNLICENSE",
        "COPYRIGHT",
    ]
    .iter()
    .any(|p| u.starts_with(p))
}

/// The root package and every package reached from it through normal dependencies, in name
/// order (root first), with their licence files.
pub fn collect(metadata: &Json) -> Result<Vec<CrateLicense>, String> {
    let resolve = metadata.get("resolve").ok_or("metadata without resolve")?;
    let root = resolve
        .get("root")
        .and_then(Json::as_str)
        .ok_or("metadata without a root package")?;
    let nodes: BTreeMap<&str, &Json> = resolve
        .get("nodes")
        .map(Json::items)
        .unwrap_or_default()
        .iter()
        .filter_map(|n| Some((n.get("id")?.as_str()?, n)))
        .collect();
    let mut seen: Vec<&str> = vec![root];
    let mut stack = vec![root];
    while let Some(id) = stack.pop() {
        let node = nodes
            .get(id)
            .ok_or_else(|| format!("no resolve node {id}"))?;
        for d in node.get("deps").map(Json::items).unwrap_or_default() {
            let normal = d
                .get("dep_kinds")
                .map(Json::items)
                .unwrap_or_default()
                .iter()
                .any(|k| k.get("kind") == Some(&Json::Null));
            let Some(pkg) = d.get("pkg").and_then(Json::as_str) else {
                continue;
            };
            if normal && !seen.contains(&pkg) {
                seen.push(pkg);
                stack.push(pkg);
            }
        }
    }
    let packages = metadata
        .get("packages")
        .map(Json::items)
        .unwrap_or_default();
    let mut out = Vec::new();
    for id in &seen {
        let p = packages
            .iter()
            .find(|p| p.get("id").and_then(Json::as_str) == Some(id))
            .ok_or_else(|| format!("no package {id}"))?;
        let s = |k: &str| p.get(k).and_then(Json::as_str).unwrap_or("").to_string();
        let dir = PathBuf::from(s("manifest_path"))
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let mut files: Vec<(String, PathBuf)> = std::fs::read_dir(&dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok())
            .filter(|e| e.path().is_file())
            .filter_map(|e| {
                let n = e.file_name().into_string().ok()?;
                is_license_file(&n).then(|| (n, e.path()))
            })
            .collect();
        if let Some(extra) = p.get("license_file").and_then(Json::as_str) {
            let path = dir.join(extra);
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if path.is_file() && !files.iter().any(|(n, _)| *n == name) {
                files.push((name, path));
            }
        }
        files.sort();
        let kinds: Vec<&str> = p
            .get("targets")
            .map(Json::items)
            .unwrap_or_default()
            .iter()
            .flat_map(|t| t.get("kind").map(Json::items).unwrap_or_default())
            .filter_map(Json::as_str)
            .collect();
        out.push(CrateLicense {
            name: s("name"),
            version: s("version"),
            license: s("license"),
            proc_macro: !kinds.is_empty() && kinds.iter().all(|k| *k == "proc-macro"),
            files,
        });
    }
    out[1..].sort_by(|a, b| (&a.name, &a.version).cmp(&(&b.name, &b.version)));
    Ok(out)
}

/// Rust source declaring `pub static CRATES: &[Crate]` (the type `Crate` of
/// `crate::docs::licenses`) with each licence file embedded by `include_bytes!`.
pub fn rust_source(crates: &[CrateLicense]) -> String {
    let mut s = String::from(
        "/// The library's crates (the root package first) with their licence files.\npub static CRATES: &[Crate] = &[\n",
    );
    for c in crates {
        s.push_str(&format!(
            "    Crate {{ name: {:?}, version: {:?}, license: {:?}, proc_macro: {}, files: &[",
            c.name, c.version, c.license, c.proc_macro
        ));
        for (n, p) in &c.files {
            s.push_str(&format!(
                "({n:?}, include_bytes!({:?})), ",
                p.display().to_string()
            ));
        }
        s.push_str("] },\n");
    }
    s.push_str("];\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_escapes_and_errors() {
        let v = parse_json(r#" {"a": [1, -2.5e3, true, null], "b": "x\"\u00e9\ud83d\ude00\n"} "#)
            .unwrap();
        assert_eq!(
            v.get("a").unwrap().items()[1],
            Json::Number("-2.5e3".into())
        );
        assert_eq!(v.get("a").unwrap().items()[3], Json::Null);
        assert_eq!(v.get("b").unwrap().as_str(), Some("x\"é😀\n"));
        assert!(parse_json("[1, 2").unwrap_err().contains("byte"));
        assert!(parse_json("{} x").is_err());
    }

    #[test]
    fn only_normal_dependencies_are_walked() {
        let dir = std::env::temp_dir().join(format!("flexfmu_lic_{}", std::process::id()));
        for p in ["root", "dep", "devdep", "macro"] {
            std::fs::create_dir_all(dir.join(p)).unwrap();
        }
        std::fs::write(dir.join("dep/LICENSE-MIT"), "mit text").unwrap();
        std::fs::write(dir.join("dep/lib.rs"), "").unwrap();
        let m = |p: &str| format!("{}", dir.join(p).join("Cargo.toml").display());
        let pkg = |id: &str, lic: &str, kind: &str| {
            format!(
                r#"{{"id": "{id}", "name": "{id}", "version": "1.0.0", "license": "{lic}",
                "license_file": null, "manifest_path": {:?}, "targets": [{{"kind": ["{kind}"]}}]}}"#,
                m(id)
            )
        };
        let meta = format!(
            r#"{{"packages": [{}, {}, {}, {}],
              "resolve": {{"root": "root", "nodes": [
                {{"id": "root", "deps": [
                  {{"pkg": "dep", "dep_kinds": [{{"kind": null, "target": null}}]}},
                  {{"pkg": "devdep", "dep_kinds": [{{"kind": "dev", "target": null}}]}},
                  {{"pkg": "macro", "dep_kinds": [{{"kind": null, "target": null}}]}}]}},
                {{"id": "dep", "deps": []}}, {{"id": "devdep", "deps": []}},
                {{"id": "macro", "deps": []}}]}}}}"#,
            pkg("root", "MIT", "lib"),
            pkg("dep", "MIT OR Apache-2.0", "lib"),
            pkg("devdep", "MIT", "lib"),
            pkg("macro", "MIT", "proc-macro"),
        );
        let c = collect(&parse_json(&meta).unwrap()).unwrap();
        let names: Vec<&str> = c.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["root", "dep", "macro"]);
        assert_eq!(c[1].license, "MIT OR Apache-2.0");
        assert_eq!(c[1].files.len(), 1);
        assert_eq!(c[1].files[0].0, "LICENSE-MIT");
        assert!(c[2].proc_macro && !c[1].proc_macro);
        let src = rust_source(&c);
        assert!(src.contains("include_bytes!") && src.contains("name: \"dep\""));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
