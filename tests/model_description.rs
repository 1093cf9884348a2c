//! The committed `modelDescription/*.xml` of every shipped scene must equal what the generator
//! writes today. Regenerate with:
//! `cargo run --release -- xml scenes/*.toml --out-dir modelDescription`

use flexfmu::model_description::model_description;
use flexfmu::scene::Scene;
use std::path::Path;

#[test]
fn committed_model_descriptions_match_the_generator() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for entry in std::fs::read_dir(root.join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::from_path(&path).unwrap();
        let committed = root
            .join("modelDescription")
            .join(format!("{}.xml", scene.model_name()));
        let expected = std::fs::read_to_string(&committed).unwrap_or_else(|_| {
            panic!(
                "{} is missing: regenerate the model descriptions",
                committed.display()
            )
        });
        let generated = model_description(&scene);
        if generated != expected {
            let line = generated
                .lines()
                .zip(expected.lines())
                .position(|(a, b)| a != b)
                .map_or(0, |i| i + 1);
            panic!(
                "{} differs from the generator (first difference at line {line}); regenerate with \
                 `cargo run --release -- xml scenes/*.toml --out-dir modelDescription`",
                committed.display()
            );
        }
        n += 1;
    }
    assert!(n >= 3, "expected the shipped scenes, found {n}");
}

/// Every shipped scene has an XML file and no stale XML is left behind.
#[test]
fn no_stale_model_descriptions() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "toml")
                .then(|| Scene::from_path(&p).unwrap().model_name().to_string())
        })
        .collect();
    names.sort();
    let mut xmls: Vec<String> = std::fs::read_dir(root.join("modelDescription"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "xml").then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    xmls.sort();
    assert_eq!(names, xmls);
}
