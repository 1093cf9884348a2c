//! The FMI-LS-REF files of a scene's FMU (FMI-LS-REF section "Structure of the FMU Archive":
//! everything under `extra/org.fmi-standard.fmi-ls-ref/`, described in
//! `fmi-ls-manifest.xml` there; the recommended `documentation/fmi-ls-ref.html` beside the
//! FMU's main page, which links it).

use super::declare::{PresetValue, SmokeTest};
use super::manifest::{EXPERIMENTS_TYPE, Experiment, Related, SSV_TYPE, experiments, manifest};
use super::smoke::{SmokeRun, csv, run};
use super::ssv::parameter_set;
use crate::docs::FmuFile;
use crate::docs::xml_text::escape;
use crate::instance::STATE_FORMAT_VERSION;
use crate::scene::{ParamValues, Scene};
use crate::variables::Value;

/// The layered standard's folder inside the FMU.
pub const LS_REF_DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";

/// Paths of the files below [`LS_REF_DIR`] (relative URIs of the manifest).
pub mod paths {
    /// The manifest.
    pub const MANIFEST: &str = "fmi-ls-manifest.xml";
    /// The scene source.
    pub const SCENE: &str = "model/scene.toml";
    /// The default parameter set.
    pub const DEFAULTS: &str = "parameters/defaults.ssv";
    /// The experiments file.
    pub const EXPERIMENTS: &str = "experiments/smoke-test.exp";
    /// Stimuli of the smoke test (relative to the experiments file).
    pub const STIMULI: &str = "smoke-test-in.csv";
    /// Reference result of the smoke test (relative to the experiments file).
    pub const REFERENCE: &str = "smoke-test-ref.csv";
    /// Serialized FMU state after initialization.
    pub const STATE: &str = "states/initialized.state";
}

/// The documentation page of the LS-REF files, `documentation/fmi-ls-ref.html`.
pub const DOC_PAGE: &str = "documentation/fmi-ls-ref.html";

fn param_values(
    scene: &Scene,
    changes: &[(&'static str, PresetValue)],
) -> Result<ParamValues, String> {
    let mut values = ParamValues::defaults(&scene.params);
    for (name, change) in changes {
        let def = scene
            .params
            .iter()
            .find(|p| p.name == *name)
            .ok_or_else(|| format!("preset parameter {name} is no parameter of this scene"))?;
        let v = match (change, def.start) {
            (PresetValue::Set(v), _) => *v,
            (PresetValue::Scale(f), Value::Real(x)) => Value::Real(f * x),
            (PresetValue::Scale(_), _) => {
                return Err(format!("preset scales {name}, which is not Real"));
            }
        };
        values.set(def.name, v);
    }
    scene.validate_params(&values)?;
    Ok(values)
}

fn ssv_of(scene: &Scene, name: &str, description: &str, values: &ParamValues) -> String {
    let list: Vec<(&str, Value)> = scene
        .params
        .iter()
        .filter_map(|p| values.get(p.name).map(|v| (p.name, v)))
        .collect();
    parameter_set(name, description, &list)
}

/// Every FMI-LS-REF file of the FMU of `scene`: the manifest, the scene source, one SSV per
/// parameter preset of its kind (the defaults first), the smoke-test experiment with its
/// stimuli (if the FMU has inputs) and the reference result of the in-process run
/// ([`super::smoke::run`]), the serialized state after initialization where the kind asks for
/// it, and `documentation/fmi-ls-ref.html`. Fails if a preset is invalid or the smoke test
/// does not run.
pub fn ls_ref_files(scene: &Scene) -> Result<Vec<FmuFile>, String> {
    let name = scene.model_name();
    let mut files = Vec::new();
    let mut related = Vec::new();
    let mut put = |path: &str, data: Vec<u8>| {
        files.push(FmuFile {
            path: format!("{LS_REF_DIR}/{path}"),
            data,
        })
    };

    put(paths::SCENE, scene.text.clone().into_bytes());
    related.push(Related::new(
        "application/toml",
        paths::SCENE,
        "model",
        &format!("the flexfmu scene file {name} was built from (flexfmu build scene.toml)"),
    ));
    related.push(Related::new(
        "text/html",
        "../../documentation/index.html",
        "document",
        "what the body is, its variables, validation and limits",
    ));
    related.push(Related::new(
        "text/html",
        "../../documentation/fmi-ls-ref.html",
        "document",
        "what these reference files are and how to use them",
    ));

    // parameter sets
    let defaults = param_values(scene, &[])?;
    put(
        paths::DEFAULTS,
        ssv_of(
            scene,
            "defaults",
            "the scene's default parameter values",
            &defaults,
        )
        .into_bytes(),
    );
    let mut rel = Related::new(
        SSV_TYPE,
        paths::DEFAULTS,
        "parameter",
        "default parameter values",
    );
    rel.labels
        .push(("preset:defaults".into(), "the scene's defaults".into()));
    related.push(rel);
    let presets = scene.body.presets();
    for p in &presets {
        let values =
            param_values(scene, &p.changes).map_err(|e| format!("preset {}: {e}", p.name))?;
        let path = format!("parameters/{}.ssv", p.name);
        put(
            &path,
            ssv_of(scene, p.name, &p.description, &values).into_bytes(),
        );
        let mut rel = Related::new(SSV_TYPE, &path, "parameter", &p.description);
        rel.labels
            .push((format!("preset:{}", p.name), p.description.clone()));
        related.push(rel);
    }

    // smoke test
    let test = scene.body.smoke_test();
    let state_doc = scene.body.initial_state();
    let r = run(scene, &test, state_doc.is_some())?;
    let exp_dir = paths::EXPERIMENTS.rsplit_once('/').map_or("", |(d, _)| d);
    let stimuli = (!r.input_names.is_empty()).then(|| {
        put(
            &format!("{exp_dir}/{}", paths::STIMULI),
            csv(&r.times, &r.input_names, &r.inputs).into_bytes(),
        );
        paths::STIMULI.to_string()
    });
    put(
        &format!("{exp_dir}/{}", paths::REFERENCE),
        csv(&r.times, &r.output_names, &r.outputs).into_bytes(),
    );
    let x = Experiment {
        name: "smoke-test".into(),
        description: smoke_description(&test, &r),
        start_time: r.start_time,
        stop_time: *r.times.last().unwrap_or(&r.start_time),
        step_size: r.step_size,
        parameters: Some(format!("../{}", paths::DEFAULTS)),
        stimuli,
        references: paths::REFERENCE.into(),
    };
    put(
        paths::EXPERIMENTS,
        experiments(
            &format!("{name} smoke test"),
            "re-run with any FMI 2.0 co-simulation master and compare with the reference",
            &[x],
        )
        .into_bytes(),
    );
    related.push(Related::new(
        EXPERIMENTS_TYPE,
        paths::EXPERIMENTS,
        "experiment/smoke-test",
        "smoke test: communication steps of the default step size, stimuli from the CSV",
    ));
    related.push(Related::new(
        "text/csv",
        &format!("{exp_dir}/{}", paths::REFERENCE),
        "result",
        "reference result of the smoke test (every Real output), computed by flexfmu at build time",
    ));
    if let (Some(doc), Some(bytes)) = (state_doc, &r.initial_state) {
        put(paths::STATE, bytes.clone());
        related.push(Related::new(
            "application/octet-stream",
            paths::STATE,
            "serialized-state",
            &format!(
                "fmi2SerializeFMUstate bytes after fmi2ExitInitializationMode with the default parameters ({doc}); \
                 pass them to fmi2DeSerializeFMUstate and fmi2SetFMUstate instead of initializing"
            ),
        ));
    }
    put(paths::MANIFEST, manifest(&related).into_bytes());
    files.push(FmuFile {
        path: DOC_PAGE.into(),
        data: doc_page(scene, &presets_list(&presets), &r, state_doc).into_bytes(),
    });
    Ok(files)
}

fn presets_list(presets: &[super::Preset]) -> Vec<(String, String)> {
    let mut out = vec![(
        "defaults".to_string(),
        "the scene's default parameter values".to_string(),
    )];
    out.extend(
        presets
            .iter()
            .map(|p| (p.name.to_string(), p.description.clone())),
    );
    out
}

fn smoke_description(test: &SmokeTest, r: &SmokeRun) -> String {
    let mut s = format!(
        "{} communication steps of {} s from t = {} s, default parameters",
        test.steps, r.step_size, r.start_time
    );
    if test.stimuli.is_empty() {
        s.push_str(", inputs at their start values");
    } else {
        s.push_str(", stimuli on ");
        s.push_str(&r.input_names.join(", "));
        s.push_str(" (one period over the run; other inputs at their start values)");
    }
    s
}

fn doc_page(
    scene: &Scene,
    presets: &[(String, String)],
    r: &SmokeRun,
    state_doc: Option<&str>,
) -> String {
    let e = escape;
    let d = LS_REF_DIR;
    let mut h = format!(
        "<!DOCTYPE html>\n<html>\n<head><meta charset=\"utf-8\"><title>{0}: reference files \
         (FMI-LS-REF)</title></head>\n<body>\n<h1>{0}: reference files (FMI-LS-REF)</h1>\n\
         <p>The folder <code>{d}/</code> follows the FMI layered standard References \
         (FMI-LS-REF {ver}); <code>{d}/{m}</code> lists every file with its role.</p>\n<ul>\n\
         <li><code>{d}/{s}</code>: the scene file the FMU was built from.</li>\n",
        e(scene.model_name()),
        ver = super::manifest::LS_VERSION,
        m = paths::MANIFEST,
        s = paths::SCENE,
    );
    h.push_str("<li>Parameter sets (SSP 1.0 <code>.ssv</code>, every parameter of the FMU, applied by variable name):<ul>\n");
    for (n, desc) in presets {
        h.push_str(&format!(
            "<li><code>{d}/parameters/{}.ssv</code>: {}</li>\n",
            e(n),
            e(desc)
        ));
    }
    h.push_str("</ul></li>\n");
    h.push_str(&format!(
        "<li><code>{d}/{}</code>: the smoke test, {} communication steps of {} s from t = {} s \
         with the default parameters; inputs {}; the reference result (every Real output at \
         every communication point, row 0 after initialization) was computed by flexfmu's own \
         model at build time. Set the inputs of each row before the step that starts there.</li>\n",
        paths::EXPERIMENTS,
        r.times.len() - 1,
        r.step_size,
        r.start_time,
        if r.input_names.is_empty() {
            "at their start values".to_string()
        } else {
            format!(
                "from <code>{}</code> ({})",
                paths::STIMULI,
                e(&r.input_names.join(", "))
            )
        }
    ));
    if let Some(doc) = state_doc {
        h.push_str(&format!(
            "<li><code>{d}/{}</code>: the FMU state right after <code>fmi2ExitInitializationMode</code> \
             with the default parameters ({}), serialized by <code>fmi2SerializeFMUstate</code> \
             (flexfmu state format {STATE_FORMAT_VERSION}, little-endian on every platform, \
             tied to this FMU's GUID). To start from it: <code>fmi2Instantiate</code>, then \
             <code>fmi2DeSerializeFMUstate</code> and <code>fmi2SetFMUstate</code> instead of \
             the initialization calls, then <code>fmi2DoStep</code> from t = {} s. The state \
             carries the parameter values it was made with: it is only meaningful for the \
             default parameters. Setting it skips the initialization and, for a belt drive, the \
             static pre-load of the mounted belt: the model is built from the scene without \
             it and takes the pre-loaded belt and its reference length from the state.</li>\n",
            paths::STATE,
            e(doc),
            r.start_time
        ));
    }
    h.push_str("</ul>\n</body>\n</html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::variables::{Causality, VarType, VariableTable};

    fn file<'a>(files: &'a [FmuFile], rel: &str) -> &'a str {
        let path = format!("{LS_REF_DIR}/{rel}");
        let f = files
            .iter()
            .find(|f| f.path == path)
            .unwrap_or_else(|| panic!("no {path}"));
        std::str::from_utf8(&f.data).unwrap()
    }

    /// The cantilever: layout, manifest entries, CSV headers and rows, SSV names.
    #[test]
    fn writer_lays_out_the_ls_ref_folder() {
        let scene = Scene::from_toml(include_str!("../../scenes/cantilever.toml")).unwrap();
        let files = ls_ref_files(&scene).unwrap();
        let mut paths: Vec<&str> = files.iter().map(|f| f.path.as_str()).collect();
        paths.sort();
        assert_eq!(
            paths,
            [
                "documentation/fmi-ls-ref.html",
                "extra/org.fmi-standard.fmi-ls-ref/experiments/smoke-test-in.csv",
                "extra/org.fmi-standard.fmi-ls-ref/experiments/smoke-test-ref.csv",
                "extra/org.fmi-standard.fmi-ls-ref/experiments/smoke-test.exp",
                "extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml",
                "extra/org.fmi-standard.fmi-ls-ref/model/scene.toml",
                "extra/org.fmi-standard.fmi-ls-ref/parameters/defaults.ssv",
            ]
        );
        assert_eq!(file(&files, paths::SCENE), scene.text);

        // every manifest source inside the folder exists; roles as the standard names them
        let m = file(&files, paths::MANIFEST);
        assert!(m.contains("fmi-ls:fmi-ls-name=\"org.fmi-standard.fmi-ls-ref\""));
        let mut r = quick_xml::Reader::from_str(m);
        let mut roles = Vec::new();
        loop {
            match r.read_event().unwrap() {
                quick_xml::events::Event::Empty(e) | quick_xml::events::Event::Start(e)
                    if e.name().as_ref() == "Related" =>
                {
                    let attr = |k: &str| {
                        e.attributes()
                            .flatten()
                            .find(|a| a.key.as_ref() == k)
                            .map(|a| a.value.to_string())
                            .unwrap()
                    };
                    let src = attr("source");
                    if !src.starts_with("../") {
                        file(&files, &src);
                    }
                    roles.push(attr("role"));
                }
                quick_xml::events::Event::Eof => break,
                _ => {}
            }
        }
        for role in [
            "model",
            "parameter",
            "experiment/smoke-test",
            "result",
            "document",
        ] {
            assert!(roles.iter().any(|r| r == role), "{role}: {roles:?}");
        }

        // reference: time and every Real output, one row per communication point
        let vars = VariableTable::from_scene(&scene);
        let outputs: Vec<String> = vars
            .vars()
            .iter()
            .filter(|v| v.causality == Causality::Output && v.ty == VarType::Real)
            .map(|v| format!("\"{}\"", v.name))
            .collect();
        let reference = file(&files, &format!("experiments/{}", paths::REFERENCE));
        let mut lines = reference.lines();
        assert_eq!(
            lines.next().unwrap(),
            format!("\"time\",{}", outputs.join(","))
        );
        let test = scene.body.smoke_test();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), test.steps + 1);
        let h = scene.common.experiment.step_size;
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), outputs.len() + 1);
            assert!((row[0] - k as f64 * h).abs() < 1e-12, "{row:?}");
        }
        // the stimulus bends the cantilever: its tip moves
        let tip_y = outputs.iter().position(|n| n == "\"tip.y\"").unwrap() + 1;
        assert!(rows.iter().any(|r| r[tip_y].abs() > 1e-6), "{rows:?}");
        let stimuli = file(&files, &format!("experiments/{}", paths::STIMULI));
        assert_eq!(stimuli.lines().next().unwrap(), "\"time\",\"load.fy\"");

        // the default parameter set names every parameter once, with its default
        let ssv = file(&files, paths::DEFAULTS);
        for p in &scene.params {
            assert_eq!(
                ssv.matches(&format!("<ssv:Parameter name=\"{}\">", p.name))
                    .count(),
                1,
                "{}",
                p.name
            );
        }
        assert!(ssv.contains("<ssv:Integer value=\"8\"/>"), "{ssv}");
    }

    /// Presets are checked against the scene's parameters.
    #[test]
    fn presets_name_real_parameters() {
        let scene = Scene::from_toml(include_str!("../../scenes/cantilever.toml")).unwrap();
        let e = param_values(&scene, &[("no.such", PresetValue::Scale(2.0))]).unwrap_err();
        assert!(e.contains("no.such"), "{e}");
        let e = param_values(&scene, &[("mesh.n_elements", PresetValue::Scale(2.0))]).unwrap_err();
        assert!(e.contains("not Real"), "{e}");
        let v = param_values(&scene, &[("material.E", PresetValue::Scale(2.0))]).unwrap();
        let d = ParamValues::defaults(&scene.params);
        assert_eq!(v.real("material.E"), 2.0 * d.real("material.E"));
    }
}
