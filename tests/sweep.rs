//! `flexfmu sweep`: identical numbers from a serial run (a fresh instance per point), the
//! worker threads (instances reused through fmi2Reset), and chunks merged; reductions; the
//! plan; clear errors naming the key for bad sweep files.

use flexfmu::sweep::run::{Reducer, Runner};
use flexfmu::sweep::{
    Reduction, chunk_range, merge_files, parse_chunk, parse_sweep, run_points, table, write_results,
};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("flexfmu_sweep_test_{}_{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A sweep on the pendulum: 3 moduli x 2 meshes x a 4-point Latin hypercube over the
/// density, with a CSV input file absent (the pendulum has no inputs).
const PENDULUM: &str = r#"
scene = "scenes/pendulum.toml"
[run]
stop_time = 0.05
step = 0.01
[[parameters]]
name = "material.E"
linspace = [1e7, 3e7, 3]
[[parameters]]
name = "mesh.n_elements"
values = [2, 3]
[[parameters]]
name = "material.rho"
lhs = [2700.0, 7850.0]
[sample]
points = 4
seed = 3
[[outputs]]
name = "tip.y"
reduce = ["final", "min", "max", "mean", "rms", "max_abs"]
[[outputs]]
name = "energy.total"
reduce = ["final"]
[series]
outputs = ["tip.x"]
points = [1, 20]
"#;

/// A point's result as bits: point, reductions, status, series.
type Bits = (usize, Vec<u64>, String, Vec<Vec<u64>>);

fn bits(r: &[flexfmu::sweep::PointResult]) -> Vec<Bits> {
    r.iter()
        .map(|p| {
            (
                p.point,
                p.values.iter().map(|x| x.to_bits()).collect(),
                p.status.clone(),
                p.series
                    .iter()
                    .map(|row| row.iter().map(|x| x.to_bits()).collect())
                    .collect(),
            )
        })
        .collect()
}

#[test]
fn serial_threads_and_merged_chunks_give_identical_numbers() {
    let sw = parse_sweep(PENDULUM, &root()).unwrap();
    assert_eq!(sw.points.len(), 24);
    // serial: a fresh instance for every point
    let serial: Vec<_> = (0..24).map(|p| Runner::new(&sw).unwrap().run(p)).collect();
    assert!(serial.iter().all(|r| r.status == "ok"), "{serial:?}");
    // the reductions see the motion: the tip falls, the moduli change the answer
    assert!(serial[0].values[0] < -0.005, "{:?}", serial[0].values);
    assert_ne!(serial[0].values[0], serial[8].values[0]);
    assert_eq!(serial[1].series.len(), sw.steps + 1);
    assert!(serial[0].series.is_empty());
    let none = |_: usize, _: usize| {};
    let threads = run_points(&sw, 0..24, 2, &none).unwrap();
    assert_eq!(bits(&serial), bits(&threads));
    // one thread, one instance reset 23 times
    let one = run_points(&sw, 0..24, 1, &none).unwrap();
    assert_eq!(bits(&serial), bits(&one));

    // chunks 1/3..3/3 written and merged equal the whole run written
    let dir = tmp("chunks");
    let whole = dir.join("whole.csv");
    write_results(&sw, &threads, &whole, true).unwrap();
    let mut files = vec![];
    for k in 1..=3 {
        let r = run_points(&sw, chunk_range(24, k, 3), 2, &none).unwrap();
        let f = dir.join(format!("c{k}.csv"));
        write_results(&sw, &r, &f, false).unwrap();
        files.push(f);
    }
    files.reverse(); // any order
    let merged = dir.join("merged.csv");
    merge_files(&files, &merged).unwrap();
    let read = |p: &Path| std::fs::read_to_string(p).unwrap();
    assert_eq!(read(&merged), read(&whole));
    let series: Vec<PathBuf> = (1..=3)
        .map(|k| dir.join(format!("c{k}_series.csv")))
        .collect();
    let merged_series = dir.join("merged_series.csv");
    merge_files(&series, &merged_series).unwrap();
    assert_eq!(read(&merged_series), read(&dir.join("whole_series.csv")));
    // a missing or doubled chunk is refused
    let e = merge_files(&files[..2], &dir.join("x.csv")).unwrap_err();
    assert!(e.contains("missing"), "{e}");
    let e = merge_files(&[files[0].clone(), files[0].clone()], &dir.join("x.csv")).unwrap_err();
    assert!(e.contains("more than one file"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reductions_follow_their_definitions() {
    let mut r = Reducer::default();
    for y in [1.0, -3.0, 2.0] {
        r.push(y);
    }
    assert_eq!(r.get(Reduction::Final), 2.0);
    assert_eq!(r.get(Reduction::Max), 2.0);
    assert_eq!(r.get(Reduction::Min), -3.0);
    assert_eq!(r.get(Reduction::MaxAbs), 3.0);
    assert_eq!(r.get(Reduction::Mean), 0.0);
    assert_eq!(r.get(Reduction::Rms), (14.0f64 / 3.0).sqrt());
}

#[test]
fn a_one_dimensional_sweep_is_plotted_and_the_plan_lists_every_point() {
    let text = r#"
scene = "scenes/pendulum.toml"
[run]
stop_time = 0.02
step = 0.01
[[parameters]]
name = "material.E"
values = [1e7, 2e7, 4e7]
[[outputs]]
name = "tip.y"
reduce = ["min"]
"#;
    let sw = parse_sweep(text, &root()).unwrap();
    let r = run_points(&sw, 0..3, 2, &|_, _| {}).unwrap();
    let dir = tmp("plot");
    let out = dir.join("r.csv");
    let written = write_results(&sw, &r, &out, true).unwrap();
    let svg = std::fs::read_to_string(dir.join("r.svg")).unwrap();
    assert_eq!(written.len(), 2);
    assert!(
        svg.contains("tip.y:min") && svg.contains("<polyline"),
        "{svg}"
    );
    let plan = table::plan_json(&sw, 1..3);
    assert!(plan.contains("[1, [20000000.0]]") && plan.contains("[2, [40000000.0]]"));
    assert!(!plan.contains("[0, ["), "{plan}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_input_csv_is_interpolated_and_checked() {
    let dir = tmp("inputs");
    std::fs::write(dir.join("s.csv"), "time,pulley1.angle\n0,0\n1,2\n").unwrap();
    let scene = root().join("scenes/belt_drive.toml");
    let text = format!(
        "scene = {:?}\n[run]\nstop_time = 0.01\nstep = 0.01\n[inputs]\ncsv = \"s.csv\"\n[[outputs]]\nname = \"pulley1.torque\"\nreduce = [\"final\"]\n",
        scene.display().to_string()
    );
    let sw = parse_sweep(&text, &dir).unwrap();
    let t = sw.inputs.as_ref().unwrap();
    assert_eq!(t.value(0, 0.25), 0.5);
    assert_eq!(t.value(0, -1.0), 0.0);
    assert_eq!(t.value(0, 5.0), 2.0);
    std::fs::write(dir.join("bad.csv"), "time,tip.y\n0,0\n").unwrap();
    let text = "scene = \"../pendulum.toml\"\n[run]\nstop_time = 0.01\nstep = 0.01\n[inputs]\ncsv = \"bad.csv\"\n[[outputs]]\nname = \"tip.y\"\nreduce = [\"final\"]\n";
    std::fs::copy(
        root().join("scenes/pendulum.toml"),
        dir.join("../pendulum.toml"),
    )
    .ok();
    let e = parse_sweep(text, &dir).unwrap_err();
    assert!(e.contains("inputs.csv") && e.contains("tip.y"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_sweep_files_name_the_key() {
    let base = |extra: &str, params: &str| {
        format!(
            "scene = \"scenes/pendulum.toml\"\n{extra}\n[run]\nstop_time = 0.05\nstep = 0.01\n{params}\n[[outputs]]\nname = \"tip.y\"\nreduce = [\"final\"]\n"
        )
    };
    let p = |body: &str| format!("[[parameters]]\n{body}\n");
    let cases: Vec<(String, &str)> = vec![
        (base("colour = 1", ""), "colour"),
        (
            base(
                "",
                &p("name = \"material.E\"\nlinspace = [1, 2, 3]\nvalue = 3.0"),
            ),
            "exactly one of value",
        ),
        (
            base("", &p("name = \"material.Q\"\nvalue = 1.0")),
            "parameters[0].name",
        ),
        (
            base("", &p("name = \"tip.x\"\nvalue = 1.0")),
            "is an output",
        ),
        (
            base("", &p("name = \"mesh.n_elements\"\nlinspace = [2, 8, 4]")),
            "parameters[0].linspace",
        ),
        (
            base("", &p("name = \"mesh.n_elements\"\nvalues = [2, 2.5]")),
            "parameters[0].values",
        ),
        (
            base("", &p("name = \"material.E\"\nlhs = [2e7, 1e7]")),
            "parameters[0].lhs",
        ),
        (
            base("", &p("name = \"material.E\"\nlhs = [1e7, 2e7]")),
            "`sample`",
        ),
        (
            base("", &p("name = \"material.E\"\nvalues = [1e7]\nspread = 2")),
            "spread",
        ),
        (
            base("[series]\noutputs = [\"tip.x\"]\npoints = [3]", ""),
            "series.points[0]",
        ),
        (
            base("", "").replace("reduce = [\"final\"]", "reduce = [\"median\"]"),
            "outputs[0].reduce",
        ),
        (
            base("", "").replace("step = 0.01", "step = 0.03"),
            "run.step",
        ),
        (
            base("", "").replace("stop_time = 0.05", "stop_time = -1.0"),
            "run.stop_time",
        ),
        (
            base("", "").replace("name = \"tip.y\"", "name = \"tip.z\""),
            "outputs[0].name",
        ),
        (
            base("", "").replace("scene = ", "fmu = \"x.fmu\"\nscene = "),
            "exactly one of the keys",
        ),
        (
            base("", "")
                .replace("[run]\n", "")
                .replace("stop_time = 0.05\nstep = 0.01\n", ""),
            "run",
        ),
    ];
    for (text, want) in cases {
        let e = parse_sweep(&text, &root()).unwrap_err();
        assert!(
            e.contains(want),
            "expected `{want}` in: {e}\n--- file:\n{text}"
        );
    }
    assert_eq!(parse_chunk("2/5"), Ok((2, 5)));
    for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
        assert!(parse_chunk(bad).unwrap_err().contains("--chunk"), "{bad}");
    }
}

#[test]
fn a_failing_point_gives_nan_and_its_reason_and_the_instance_goes_on() {
    // a negative modulus is refused when the model is built; the reused instance is reset
    // from the error state and runs the next point
    let text = r#"
scene = "scenes/pendulum.toml"
[run]
stop_time = 0.02
step = 0.01
[[parameters]]
name = "material.E"
values = [2e7, -1e7, 2e7]
[[outputs]]
name = "tip.y"
reduce = ["final", "max_abs"]
"#;
    let sw = parse_sweep(text, &root()).unwrap();
    let r = run_points(&sw, 0..3, 1, &|_, _| {}).unwrap();
    assert_eq!(r[0].status, "ok");
    assert!(r[1].status.contains("material.E"), "{}", r[1].status);
    assert!(r[1].values.iter().all(|x| x.is_nan()));
    assert_eq!(r[2].status, "ok");
    assert_eq!(bits(&r[..1])[0].1, bits(&r[2..])[0].1);
    let csv = table::results_csv(&sw, &r);
    assert!(
        csv.lines()
            .nth(2)
            .unwrap()
            .starts_with("1,-10000000.0,NaN,NaN,"),
        "{csv}"
    );
}
