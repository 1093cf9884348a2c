//! Body kinds: the registry, the explicit `kind` key and the files written before it.

use flexfmu::kinds::{self, REGISTRY};
use flexfmu::model_description::model_description;
use flexfmu::scene::Scene;
use flexfmu::variables::VariableTable;

mod common;

const SHIPPED: [&str; 11] = [
    "cantilever",
    "simply_supported",
    "pendulum",
    "cantilever_motion",
    "cantilever3d",
    "bend45",
    "right_angle_cantilever",
    "belt_drive",
    "belt_drive_cosim",
    "belt_drive_inertia",
    "serpentine",
];

/// Kind names are unique and each names its module; every kind is reachable by name.
#[test]
fn registry_names_are_unique() {
    let mut names: Vec<&str> = REGISTRY.iter().map(|k| k.name()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), REGISTRY.len());
    for k in REGISTRY {
        assert_eq!(kinds::by_name(k.name()).map(|f| f.name()), Some(k.name()));
        assert!(!k.summary().is_empty());
        for common in ["kind", "fmu", "experiment", "solver"] {
            assert!(
                k.tables().contains(&common),
                "{}: {:?}",
                k.name(),
                k.tables()
            );
        }
    }
}

/// The table lists come from the scene structs: spot checks.
#[test]
fn kinds_list_their_tables() {
    let tables = |name: &str| kinds::by_name(name).unwrap().tables();
    assert!(tables("beam_2d").contains(&"motions") && !tables("beam_2d").contains(&"section"));
    assert!(tables("beam_3d").contains(&"centreline") && !tables("beam_3d").contains(&"motions"));
    assert!(tables("belt_drive").contains(&"pulley") && !tables("belt_drive").contains(&"mesh"));
    assert!(tables("shell").contains(&"meridian") && tables("shell").contains(&"plate"));
    assert!(!tables("shell").contains(&"section") && !tables("shell").contains(&"centreline"));
}

/// Every shipped file (written without the key) reads the same with `kind = "<its kind>"`
/// added: same kind, same variables, same model description but for the GUID.
#[test]
fn explicit_kind_reads_like_the_legacy_file() {
    for name in SHIPPED {
        let legacy = common::scene(name);
        let kind = legacy.kind().name();
        let text = format!("kind = \"{kind}\"\n{}", legacy.text);
        let explicit = Scene::from_toml(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(explicit.kind().name(), kind, "{name}");
        assert_eq!(
            VariableTable::from_scene(&explicit),
            VariableTable::from_scene(&legacy),
            "{name}"
        );
        let strip = |xml: String| {
            xml.lines()
                .filter(|l| !l.contains("guid="))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(
            strip(model_description(&explicit)),
            strip(model_description(&legacy)),
            "{name}"
        );
    }
}

/// A file read as another kind fails on a table (or key) that kind does not have, and says so.
#[test]
fn a_wrong_kind_names_the_table_and_the_kind() {
    for (name, wrong, tables) in [
        (
            "cantilever",
            "beam_3d",
            &["[element]", "[geometry]", "[material]"][..],
        ),
        (
            "bend45",
            "beam_2d",
            &["[centreline]", "[section]", "[element]"],
        ),
        (
            "belt_drive",
            "beam_2d",
            &["[belt]", "[contact]", "[element]"],
        ),
        (
            "pendulum",
            "belt_drive",
            &["[element]", "[geometry]", "[material]", "[mesh]"],
        ),
    ] {
        let text = format!("kind = \"{wrong}\"\n{}", common::scene(name).text);
        let err = Scene::from_toml(&text).unwrap_err().0;
        assert!(
            err.contains(&format!("kind \"{wrong}\"")) && tables.iter().any(|t| err.contains(t)),
            "{name} as {wrong}: {err}"
        );
    }
    let err = Scene::from_toml(&format!("kind = 3\n{}", common::scene("bend45").text))
        .unwrap_err()
        .0;
    assert!(err.contains("kind") && err.contains("\"beam_3d\""), "{err}");
}
