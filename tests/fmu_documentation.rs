//! What every shipped FMU carries besides its model (issue 14): `documentation/index.html`
//! (well-formed XHTML naming every variable), `documentation/licenses/`, `model.png`,
//! `terminalsAndIcons/terminalsAndIcons.xml` (checked against the structure of the FMI 3.0
//! schema `fmi3TerminalsAndIcons.xsd` / `fmi3Terminal.xsd`, which FMI 2.0.4 section 2.3
//! refers to), the OSP side file, and multi-platform packaging. Every scene in `scenes/` is
//! checked, so a new scene or kind is covered by itself.

use flexfmu::docs::licenses::crates;
use flexfmu::docs::osp::osp_model_description;
use flexfmu::docs::terminals::terminals;
use flexfmu::docs::{FmuFile, documentation_files};
use flexfmu::model::build_model;
use flexfmu::model_description::model_description;
use flexfmu::packaging::{PlatformLibrary, add_platforms, build_fmu, platform};
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::{Causality, VariableTable};
use quick_xml::Reader;
use quick_xml::events::{BytesStart, Event};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn shipped_scenes() -> Vec<(String, Scene)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 5, "expected the shipped scenes");
    paths
        .iter()
        .map(|p| {
            let s = Scene::from_path(p).unwrap_or_else(|e| panic!("{}: {}", p.display(), e.0));
            (p.file_stem().unwrap().to_string_lossy().into_owned(), s)
        })
        .collect()
}

/// An element: name, attributes, children (text ignored).
#[derive(Debug)]
struct Element {
    name: String,
    attrs: BTreeMap<String, String>,
    children: Vec<Element>,
}

#[allow(deprecated)] // unescape_value: the five predefined entities are all we write
fn element(e: &BytesStart) -> Element {
    Element {
        name: String::from_utf8_lossy(e.name().as_ref().as_bytes()).into_owned(),
        attrs: e
            .attributes()
            .map(|a| {
                let a = a.expect("well-formed attribute");
                (
                    String::from_utf8_lossy(a.key.as_ref().as_bytes()).into_owned(),
                    a.unescape_value().expect("valid escapes").into_owned(),
                )
            })
            .collect(),
        children: vec![],
    }
}

/// Parses a whole document (quick-xml checks that end tags match their start tags); panics
/// with the position on any well-formedness error, and on a second root element.
fn parse_xml(text: &str, what: &str) -> Element {
    let mut r = Reader::from_str(text);
    r.config_mut().check_end_names = true;
    let mut stack: Vec<Element> = vec![];
    let mut root = None;
    loop {
        match r.read_event() {
            Ok(Event::Start(e)) => stack.push(element(&e)),
            Ok(Event::Empty(e)) => {
                let el = element(&e);
                match stack.last_mut() {
                    Some(p) => p.children.push(el),
                    None => {
                        assert!(root.is_none(), "{what}: two root elements");
                        root = Some(el)
                    }
                }
            }
            Ok(Event::End(_)) => {
                let el = stack.pop().expect("end tag without start");
                match stack.last_mut() {
                    Some(p) => p.children.push(el),
                    None => {
                        assert!(root.is_none(), "{what}: two root elements");
                        root = Some(el)
                    }
                }
            }
            Ok(Event::Eof) => break,
            Ok(Event::GeneralRef(r)) => {
                // XML knows only its five predefined entities (an HTML &nbsp; is an error)
                let name = r.xml10_content().into_owned();
                assert!(
                    r.is_char_ref() || ["amp", "lt", "gt", "quot", "apos"].contains(&name.as_str()),
                    "{what}: undefined entity &{name};"
                );
            }
            Ok(_) => {}
            Err(e) => panic!("{what}: not well-formed at {}: {e}", r.error_position()),
        }
    }
    assert!(stack.is_empty(), "{what}: unclosed elements");
    root.unwrap_or_else(|| panic!("{what}: no root element"))
}

fn file<'a>(files: &'a [FmuFile], path: &str) -> &'a [u8] {
    &files
        .iter()
        .find(|f| f.path == path)
        .unwrap_or_else(|| panic!("no {path}"))
        .data
}

fn descendants<'a>(e: &'a Element, out: &mut Vec<&'a Element>) {
    for c in &e.children {
        out.push(c);
        descendants(c, out);
    }
}

/// The names of the ScalarVariables of a model description.
fn model_description_names(xml: &str) -> Vec<String> {
    let md = parse_xml(xml, "modelDescription.xml");
    let mut all = vec![];
    descendants(&md, &mut all);
    all.iter()
        .filter(|e| e.name == "ScalarVariable")
        .map(|e| e.attrs["name"].clone())
        .collect()
}

#[test]
fn every_fmu_documents_every_variable_in_well_formed_xhtml() {
    for (name, scene) in shipped_scenes() {
        let files = documentation_files(&scene).unwrap_or_else(|e| panic!("{name}: {e}"));
        let html = std::str::from_utf8(file(&files, "documentation/index.html")).unwrap();
        let root = parse_xml(html, &format!("{name}: index.html"));
        assert_eq!(root.name, "html", "{name}");
        assert_eq!(
            root.attrs["xmlns"], "http://www.w3.org/1999/xhtml",
            "{name}"
        );
        let mut all = vec![];
        descendants(&root, &mut all);
        let svg = all
            .iter()
            .find(|e| e.name == "svg")
            .expect("inline picture");
        let lines = svg.children.iter().filter(|e| e.name == "polyline").count();
        assert!(lines >= 1, "{name}: the picture draws nothing");
        for v in VariableTable::from_scene(&scene).vars() {
            let cell = format!("<code>{}</code>", v.name);
            assert!(html.contains(&cell), "{name}: {} is not documented", v.name);
        }
        let kind = scene.kind();
        assert!(
            html.contains(&format!("{} — ", kind.name())),
            "{name}: kind"
        );
        // the kind's validation text, paragraph by paragraph
        let first = kind.validation().split("\n\n").next().unwrap();
        let words: String = first
            .split_whitespace()
            .take(6)
            .collect::<Vec<_>>()
            .join(" ");
        assert!(
            html.contains(&words),
            "{name}: validation text missing: {words}"
        );
    }
}

#[test]
fn every_shipped_model_draws_itself() {
    for (name, scene) in shipped_scenes() {
        let model = build_model(&scene, &ParamValues::defaults(&scene.params)).unwrap();
        let sketch = model.sketch();
        assert!(!sketch.is_empty(), "{name}: Model::sketch draws nothing");
        assert!(!sketch.mesh.is_empty(), "{name}: no mesh description");
        let (lo, hi) = sketch.bounds();
        let size = (hi - lo).norm();
        assert!(
            size.is_finite() && size > 1e-6,
            "{name}: drawing of size {size}"
        );
    }
}

#[test]
fn terminals_follow_the_fmi3_schema_and_name_existing_variables() {
    let mut seen_terminals = 0;
    for (name, scene) in shipped_scenes() {
        let files = documentation_files(&scene).unwrap();
        let xml =
            std::str::from_utf8(file(&files, "terminalsAndIcons/terminalsAndIcons.xml")).unwrap();
        let root = parse_xml(xml, &format!("{name}: terminalsAndIcons.xml"));
        // fmi3TerminalsAndIcons.xsd: root element, required fmiVersion matching
        // 3[.](0|[1-9][0-9]*)([.](0|[1-9][0-9]*))?(-.+)?, children in the sequence
        // GraphicalRepresentation?, Terminals?, Annotations?
        assert_eq!(root.name, "fmiTerminalsAndIcons");
        let v = &root.attrs["fmiVersion"];
        assert!(v.starts_with("3.") && v[2..].split('.').all(|p| p.parse::<u32>().is_ok()));
        let order: Vec<&str> = root.children.iter().map(|c| c.name.as_str()).collect();
        let rank = |n: &str| {
            ["GraphicalRepresentation", "Terminals", "Annotations"]
                .iter()
                .position(|x| *x == n)
                .unwrap_or_else(|| panic!("{name}: unexpected element {n}"))
        };
        assert!(
            order.windows(2).all(|w| rank(w[0]) < rank(w[1])),
            "{order:?}"
        );
        for g in root
            .children
            .iter()
            .filter(|c| c.name == "GraphicalRepresentation")
        {
            for c in &g.children {
                let required: &[&str] = match c.name.as_str() {
                    "CoordinateSystem" => &["x1", "y1", "x2", "y2", "suggestedScalingFactorTo_mm"],
                    "Icon" => &["x1", "y1", "x2", "y2"],
                    other => panic!("{name}: unexpected {other}"),
                };
                for a in required {
                    assert!(c.attrs[*a].parse::<f64>().is_ok(), "{name}: {a}");
                }
            }
        }
        let md_names = model_description_names(&model_description(&scene));
        let table = VariableTable::from_scene(&scene);
        let mut covered = vec![];
        let mut names = vec![];
        for t in root.children.iter().filter(|c| c.name == "Terminals") {
            for term in &t.children {
                // fmi3Terminal: name and matchingRule required, terminalKind and description
                // optional; members TerminalMemberVariable (variableKind, variableName
                // required, memberName optional)
                assert_eq!(term.name, "Terminal");
                for a in term.attrs.keys() {
                    assert!(
                        ["name", "matchingRule", "terminalKind", "description"]
                            .contains(&a.as_str()),
                        "{name}: attribute {a}"
                    );
                }
                assert!(!term.attrs["matchingRule"].is_empty());
                names.push(term.attrs["name"].clone());
                assert!(!term.children.is_empty(), "{name}: empty terminal");
                for m in &term.children {
                    assert_eq!(m.name, "TerminalMemberVariable", "{name}");
                    for a in m.attrs.keys() {
                        assert!(
                            ["variableKind", "memberName", "variableName"].contains(&a.as_str()),
                            "{name}: attribute {a}"
                        );
                    }
                    assert!(!m.attrs["variableKind"].is_empty());
                    let var = &m.attrs["variableName"];
                    assert!(
                        md_names.contains(var),
                        "{name}: {var} not in modelDescription.xml"
                    );
                    assert!(var.ends_with(&format!(".{}", m.attrs["memberName"])));
                    covered.push(var.clone());
                }
                seen_terminals += 1;
            }
        }
        let mut unique = names.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(
            unique.len(),
            names.len(),
            "{name}: duplicate terminal names"
        );
        // every input belongs to a port: the master can reach all of them through terminals
        for v in table
            .vars()
            .iter()
            .filter(|v| v.causality == Causality::Input)
        {
            assert!(
                covered.contains(&v.name),
                "{name}: input {} in no terminal",
                v.name
            );
        }
    }
    assert!(
        seen_terminals >= 10,
        "only {seen_terminals} terminals over the shipped scenes"
    );
}

#[test]
fn the_ports_are_the_physical_ones() {
    let scenes: BTreeMap<String, Scene> = shipped_scenes().into_iter().collect();
    let ports = |n: &str| -> Vec<(String, String)> {
        terminals(&VariableTable::from_scene(&scenes[n]))
            .iter()
            .map(|t| (t.name.clone(), t.description()))
            .collect()
    };
    // the examples: pulley1 (angle and omega in, torque and forces out), the load,
    // a motion port, the air spring's top plate; sensors (probes, energies) are no ports
    assert_eq!(
        ports("belt_drive")[0],
        (
            "pulley1".into(),
            "in: angle, omega; out: torque, force_x, force_y".into()
        )
    );
    assert_eq!(ports("cantilever"), [("load".into(), "in: fx, fy".into())]);
    assert_eq!(
        ports("cantilever_motion"),
        [("tip".into(), "in: x, y, vx, vy; out: fx, fy".into())]
    );
    assert_eq!(
        ports("air_spring_axisym"),
        [("top".into(), "in: z, vz; out: fz".into())]
    );
    assert_eq!(ports("pendulum"), []);
}

#[test]
fn the_icon_is_a_png_of_the_stated_size() {
    for (name, scene) in shipped_scenes() {
        let files = documentation_files(&scene).unwrap();
        let png = file(&files, "model.png");
        assert_eq!(file(&files, "terminalsAndIcons/icon.png"), png);
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{name}");
        assert_eq!(&png[12..16], b"IHDR");
        let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
        assert_eq!((w, h), (256, 256), "{name}");
    }
}

#[test]
fn licences_cover_flexfmu_and_every_linked_crate() {
    let crates = crates().expect("collected at build time");
    assert_eq!(crates[0].name, "flexfmu");
    assert_eq!(crates[0].license, env!("CARGO_PKG_LICENSE"));
    // the direct dependencies of Cargo.toml are there, with a licence expression
    for dep in [
        "nalgebra",
        "faer",
        "serde",
        "toml",
        "quick-xml",
        "zip",
        "thiserror",
    ] {
        let c = crates
            .iter()
            .find(|c| c.name == dep)
            .unwrap_or_else(|| panic!("{dep} missing"));
        assert!(!c.license.is_empty(), "{dep}: no licence expression");
        assert!(!c.files.is_empty(), "{dep}: no licence file");
    }
    // dev-dependencies are not linked
    assert!(crates.iter().all(|c| c.name != "proptest"));
    let files = documentation_files(&shipped_scenes()[0].1).unwrap();
    let txt = std::str::from_utf8(file(&files, "documentation/licenses/license.txt")).unwrap();
    for c in &crates[1..] {
        assert!(
            txt.contains(&format!("{}-{} ", c.name, c.version)),
            "{} not listed",
            c.name
        );
        for (n, data) in c.files {
            let path = format!("documentation/licenses/{}-{}/{n}", c.name, c.version);
            assert_eq!(file(&files, &path), *data);
        }
    }
}

#[test]
fn the_osp_side_file_groups_the_ports() {
    for (name, scene) in shipped_scenes() {
        let table = VariableTable::from_scene(&scene);
        let ports = terminals(&table);
        let root = parse_xml(&osp_model_description(&ports), &format!("{name}: OSP"));
        assert_eq!(root.name, "OspModelDescription");
        assert_eq!(
            root.attrs["xmlns"],
            "https://open-simulation-platform.com/OspModelDescription/1.0.0"
        );
        let groups = &root.children[0];
        assert_eq!(groups.name, "VariableGroups");
        assert_eq!(groups.children.len(), ports.len(), "{name}");
        for g in &groups.children {
            for v in &g.children {
                assert!(
                    table.by_name(&v.attrs["ref"]).is_some(),
                    "{name}: {:?}",
                    v.attrs
                );
            }
        }
    }
}

#[test]
fn an_fmu_takes_libraries_for_several_platforms() {
    let dir = std::env::temp_dir().join(format!("flexfmu_docs_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let lib = dir.join("lib_here");
    std::fs::write(&lib, b"stand-in library for this platform").unwrap();
    let other = dir.join("lib_other");
    std::fs::write(&other, b"stand-in library built elsewhere").unwrap();
    let scene = shipped_scenes().remove(0).1;
    let here = platform().unwrap();
    let out = dir.join("two.fmu");
    let written = build_fmu(
        &scene,
        &[
            PlatformLibrary {
                platform: here.0.into(),
                path: lib.clone(),
            },
            PlatformLibrary {
                platform: "win64".into(),
                path: other.clone(),
            },
        ],
        &out,
    )
    .unwrap();
    let side = dir.join("two_OspModelDescription.xml");
    assert_eq!(written, [out.clone(), side.clone()]);
    assert!(side.is_file());
    let names = |p: &Path| -> Vec<String> {
        let mut z = zip::ZipArchive::new(std::fs::File::open(p).unwrap()).unwrap();
        (0..z.len())
            .map(|k| z.by_index(k).unwrap().name().unwrap().to_string())
            .collect()
    };
    let id = scene.model_name();
    let n = names(&out);
    assert!(
        n.contains(&format!("binaries/{}/{id}.{}", here.0, here.1)),
        "{n:?}"
    );
    assert!(n.contains(&format!("binaries/win64/{id}.dll")), "{n:?}");
    for f in [
        "modelDescription.xml",
        "model.png",
        "documentation/index.html",
    ] {
        assert!(n.contains(&f.to_string()), "{f}");
    }
    // re-packaging adds a third platform and replaces one, keeping everything else
    let newer = dir.join("lib_newer");
    std::fs::write(&newer, b"newer win64 build").unwrap();
    let out2 = dir.join("three.fmu");
    let platforms = add_platforms(
        &out,
        &[
            PlatformLibrary {
                platform: "aarch64-darwin".into(),
                path: lib.clone(),
            },
            PlatformLibrary {
                platform: "win64".into(),
                path: newer,
            },
        ],
        &out2,
    )
    .unwrap();
    let mut expect = vec![here.0.to_string(), "aarch64-darwin".into(), "win64".into()];
    expect.sort();
    assert_eq!(platforms, expect);
    let n2 = names(&out2);
    assert_eq!(n2.len(), n.len() + 1);
    let mut z = zip::ZipArchive::new(std::fs::File::open(&out2).unwrap()).unwrap();
    let mut data = Vec::new();
    std::io::Read::read_to_end(
        &mut z.by_name(&format!("binaries/win64/{id}.dll")).unwrap(),
        &mut data,
    )
    .unwrap();
    assert_eq!(data, b"newer win64 build");
    // two libraries for one platform are refused
    let e = build_fmu(
        &scene,
        &[
            PlatformLibrary {
                platform: "win64".into(),
                path: lib.clone(),
            },
            PlatformLibrary {
                platform: "win64".into(),
                path: other,
            },
        ],
        &out,
    )
    .unwrap_err();
    assert!(e.contains("two libraries for platform win64"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_scene_whose_default_model_fails_is_documented_with_the_reason() {
    // the plate with every edge free and static equilibrium requested: the build refuses the
    // rigid motions, yet the FMU (whose user may set supports first) is still documented
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("scenes/plate.toml"))
        .unwrap()
        .replace("\"simply_supported\"", "\"free\"");
    let scene = Scene::from_toml(&text).unwrap();
    let err = build_model(&scene, &ParamValues::defaults(&scene.params))
        .err()
        .expect("the free plate does not build");
    let files = documentation_files(&scene).unwrap();
    let html = std::str::from_utf8(file(&files, "documentation/index.html")).unwrap();
    parse_xml(html, "free plate");
    assert!(html.contains("does not build with the default parameters"));
    assert!(
        html.contains(&flexfmu::docs::xml_text::escape(&err)),
        "{err}"
    );
    assert!(html.contains("no drawing"));
}
