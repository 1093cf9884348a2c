//! The axially moving (ALE) belt of the belt-drive kind (`belt.formulation`, issue 12 item 2):
//! in progress. What is tested so far: the parameter (default Lagrangian, the scenes' other
//! parameters unchanged) and the refusals of the scenes outside the ALE model's scope, each
//! naming its key. The model itself refuses to build until it exists (see
//! `src/kinds/belt_drive/ale.rs`); its validation (steady running tensions and the driven
//! pulley's speed against the Lagrangian drive within 0.5 %) is the next step.

use flexfmu::kinds::belt_drive::BeltDriveScene;
use flexfmu::kinds::belt_drive::model::BeltDrive;
use flexfmu::scene::{ParamValues, Scene};
use flexfmu::variables::Value;

fn scene_text(name: &str) -> String {
    std::fs::read_to_string(format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

/// The scene `name` with `key = value` added at the end of its `[belt]` table.
fn with_belt_key(name: &str, line: &str) -> String {
    let text = scene_text(name);
    let at = text.find("[belt]").unwrap() + "[belt]".len();
    format!("{}\n{line}{}", &text[..at], &text[at..])
}

fn build(text: &str) -> Result<BeltDrive, String> {
    let scene = Scene::from_toml(text).map_err(|e| e.0)?;
    let tables: &BeltDriveScene = scene.tables().unwrap();
    let p = ParamValues::defaults(&scene.params);
    BeltDrive::build(tables, &p)
}

fn formulation(text: &str) -> Option<Value> {
    let scene = Scene::from_toml(text).unwrap();
    ParamValues::defaults(&scene.params).get("belt.formulation")
}

#[test]
fn the_formulation_defaults_to_lagrangian_and_takes_names_and_codes() {
    let plain = scene_text("belt_drive.toml");
    assert_eq!(formulation(&plain), Some(Value::Integer(1)));
    let named = with_belt_key("belt_drive.toml", "formulation = \"lagrangian\"");
    assert_eq!(formulation(&named), Some(Value::Integer(1)));
    let coded = with_belt_key("belt_drive.toml", "formulation = 2");
    assert_eq!(formulation(&coded), Some(Value::Integer(2)));
    let wrong = with_belt_key("belt_drive.toml", "formulation = \"eulerian\"");
    let err = Scene::from_toml(&wrong).err().unwrap().0;
    assert!(err.contains("belt.formulation"), "{err}");
    assert!(err.contains("\"ale\" (2)"), "{err}");
}

#[test]
fn an_explicit_lagrangian_formulation_builds_the_same_drive() {
    use flexfmu::model::Model;
    use flexfmu::snapshot::StateWriter;
    let save = |m: &BeltDrive| {
        let mut w = StateWriter::new();
        m.save(&mut w).unwrap();
        w.bytes().to_vec()
    };
    let a = build(&scene_text("belt_drive.toml")).unwrap();
    let b = build(&with_belt_key(
        "belt_drive.toml",
        "formulation = \"lagrangian\"",
    ))
    .unwrap();
    assert_eq!(save(&a), save(&b));
}

#[test]
fn the_ale_belt_in_its_scope_is_refused_as_not_available_yet() {
    let err = build(&with_belt_key("belt_drive.toml", "formulation = \"ale\""))
        .err()
        .unwrap();
    assert!(err.contains("belt.formulation"), "{err}");
    assert!(err.contains("not available yet"), "{err}");
}

#[test]
fn the_ale_belt_refuses_tensioner_back_side_idlers_and_gravity() {
    let err = build(&with_belt_key("serpentine.toml", "formulation = \"ale\""))
        .err()
        .unwrap();
    assert!(err.contains("[tensioner]"), "{err}");
    assert!(err.contains("side = \"back\""), "{err}");
    assert!(!err.contains("not available yet"), "{err}");
    let mut text = with_belt_key("belt_drive.toml", "formulation = \"ale\"");
    text.push_str("\n[gravity]\nx = 0.0\ny = -9.81\n");
    let err = build(&text).err().unwrap();
    assert!(err.contains("gravity.y"), "{err}");
    assert!(!err.contains("gravity.x"), "{err}");
}

#[test]
fn the_ale_belt_refuses_the_shear_element_and_bending_damping() {
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"")
        .replace("damping_bending = 0.0", "damping_bending = 0.001");
    let err = build(&text).err().unwrap();
    assert!(err.contains("belt.damping_bending"), "{err}");
    let text = with_belt_key("belt_drive.toml", "formulation = \"ale\"")
        .replace("type = \"ancf_cable_2d\"", "type = \"ancf_shear_2d\"")
        .replace("damping_axial = 20.0", "damping_axial = 0.0");
    let err = build(&text).err().unwrap();
    assert!(err.contains("belt.element"), "{err}");
}
