//! The shell level's automatic circumferential count (`mesh.n_circumferential = 0`, the
//! shipped `scenes/air_spring.toml`): the coarsest of 16, 24, 32 elements around whose design
//! force, at the design pressure and at half of it, is within 0.5 % of the membrane level's.
//! Issue 11 item 8 asks levels 1 and 2 to agree on the vertical force within 1 %; with 16
//! elements around the shell misses that off the reference spring's design (session-28 sweep,
//! README "Level 1 off its design"): the sleeve rolled onto the narrower piston is in hoop
//! compression there, and at a low pressure a 16-gon misplaces the lobe (axisymmetric, not
//! wrinkled: measured 8088 N against 8690 N at 2 bar, 16 × 40).

mod common;

use common::{Log, get, init, instance, output, set, simulation};
use flexfmu::logging::Status;
use flexfmu::variables::Value;

/// `top.fz` of the design state of the shipped level-`level` scene with `overrides` [N].
fn design_force(scene_name: &str, overrides: &[(&str, Value)]) -> f64 {
    let scene = common::scene(scene_name);
    let sim = simulation(&scene, overrides).unwrap();
    output(&scene, &sim, "top.fz")
}

/// At 2 bar the automatic count agrees with the membrane level (60 elements) within 0.5 %,
/// where 16 elements around miss it by more than 3 % (measured −7.0 %; the automatic count
/// takes 32: −0.13 %).
#[test]
fn automatic_count_agrees_with_the_membrane_level_at_2_bar() {
    let p = [("gas.pressure_design", Value::Real(2e5))];
    let membrane = design_force("air_spring_axisym", &p);
    let auto = design_force("air_spring", &p);
    let sixteen = design_force(
        "air_spring",
        &[p[0], ("mesh.n_circumferential", Value::Integer(16))],
    );
    let (e_auto, e16) = (auto / membrane - 1.0, sixteen / membrane - 1.0);
    println!("2 bar: membrane {membrane:.1} N, automatic {e_auto:+.2e}, 16 around {e16:+.2e}");
    assert!(e_auto.abs() < 5e-3, "automatic count: {e_auto:+.2e}");
    assert!(
        e16.abs() > 3e-2,
        "16 around agrees within 3 % ({e16:+.2e}): this test no longer shows the coarse mesh's miss"
    );
}

/// Where 16 around is good enough (8 bar: the design force and that at 4 bar within 0.5 %) the
/// count stays 16, and the choice is logged (category logEvents) with the deviations it found.
#[test]
fn automatic_count_stays_coarse_where_it_can_and_says_what_it_chose() {
    let (mut inst, log): (_, Log) = instance("air_spring", true);
    set(&mut inst, "gas.pressure_design", Value::Real(8e5));
    init(&mut inst);
    let note = log
        .borrow()
        .iter()
        .find(|(_, _, m)| m.contains("mesh.n_circumferential = 0 (automatic)"))
        .cloned();
    let Some((status, category, msg)) = note else {
        panic!("no note of the automatic count: {:?}", log.borrow());
    };
    println!("{msg}");
    assert_eq!(status, Status::Ok);
    assert_eq!(category, "logEvents");
    assert!(msg.contains("16 elements around"), "{msg}");
    assert!(msg.contains("within 0.5 %"), "{msg}");
    assert!(get(&mut inst, "top.fz") > 0.0);
}

/// A count below 8 other than 0 is refused with a message naming the parameter.
#[test]
fn a_count_below_8_is_refused() {
    let scene = common::scene("air_spring");
    let Err(e) = simulation(&scene, &[("mesh.n_circumferential", Value::Integer(5))]) else {
        panic!("5 elements around were accepted");
    };
    assert!(e.contains("mesh.n_circumferential = 5"), "{e}");
    assert!(e.contains("0 (automatic)"), "{e}");
}
