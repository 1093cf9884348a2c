//! The convergence study of `flexfmu advise`: runs a grid of configurations of a scene's knobs
//! in process ([`Simulation`], no FMU), estimates each element family's converged answer by
//! Richardson extrapolation on its three finest refinement runs, measures every
//! configuration's error on one output against its family's answer, and picks the cheapest
//! configuration within the tolerance.

use super::knobs::{Knob, KnobRole};
use super::signals::Signals;
use crate::model::build_model;
use crate::scene::{ParamValues, Scene};
use crate::solver::simulation::{Simulation, SolverConfig};
use crate::variables::{Role, Value, VariableTable};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// What to study.
#[derive(Clone, Debug)]
pub struct AdviseOptions {
    /// The output whose error counts (a variable name such as `tip.y`).
    pub output: String,
    /// Admissible error on that output, max over the run [the output's unit].
    pub tol: f64,
    /// End of the run [s] (default: the scene's `[experiment] stop_time`).
    pub stop_time: Option<f64>,
    /// Input time histories (default: inputs stay at their start values).
    pub inputs: Option<Signals>,
    /// Allow a different element family than the scene's even when the families' converged
    /// answers differ by more than `tol`.
    pub allow_element_change: bool,
    /// Refinement levels per ladder (at least 3: Richardson needs three).
    pub levels: usize,
    /// How many of the levels are finer than the scene's own values (the others coarser).
    pub finer: usize,
    /// Knobs (parameter names) kept at the scene's values instead of studied.
    pub keep: Vec<String>,
    /// Worker threads.
    pub jobs: usize,
    /// Progress bar on stderr.
    pub progress: bool,
}

impl AdviseOptions {
    /// Defaults for `output` and `tol`: the scene's stop time, no inputs, 4 levels of which 1
    /// finer than the scene, as many threads as cores (at most 2), a progress bar.
    pub fn new(output: &str, tol: f64) -> Self {
        Self {
            output: output.to_string(),
            tol,
            stop_time: None,
            inputs: None,
            allow_element_change: false,
            levels: 4,
            finer: 1,
            keep: Vec::new(),
            jobs: std::thread::available_parallelism()
                .map(|n| n.get().min(2))
                .unwrap_or(1),
            progress: true,
        }
    }
}

/// One configuration: the knob values and where it sits in the ladders.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Parameter values set over the scene's defaults, in the order of the knobs.
    pub values: Vec<(&'static str, Value)>,
    /// Element family code (`None`: the kind has no family knob).
    pub family: Option<i32>,
    /// Mesh level (0 = coarsest).
    pub mesh_level: usize,
    /// Step level (0 = coarsest); adaptive runs use the coarsest step as their cap.
    pub step_level: usize,
    /// Whether every discrete variant has the scene's value.
    pub scene_variant: bool,
    /// Adaptive runs: index into the tolerance ladder.
    pub tol_level: Option<usize>,
}

impl Config {
    /// `param=value` pairs separated by spaces.
    pub fn label(&self) -> String {
        self.values
            .iter()
            .map(|(n, v)| format!("{n}={}", show(*v)))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// A value as the table shows it.
pub fn show(v: Value) -> String {
    match v {
        Value::Real(x) => format!("{x:e}"),
        Value::Integer(i) => i.to_string(),
        Value::Boolean(b) => b.to_string(),
    }
}

/// A configuration's run.
#[derive(Clone, Debug)]
pub struct Run {
    /// The configuration.
    pub config: Config,
    /// The output at the common time points, or why the run failed.
    pub samples: Result<Vec<f64>, String>,
    /// Wall time of the time stepping [s] (initialization excluded).
    pub wall: f64,
    /// Max over time of |output − family's converged answer| (infinite for a failed run).
    pub error: f64,
}

impl Run {
    /// Wall time per simulated second [s/s].
    pub fn wall_per_second(&self, span: f64) -> f64 {
        self.wall / span
    }
}

/// The converged answer of one element family.
#[derive(Clone, Debug)]
pub struct FamilyAnswer {
    /// Family code (`None`: the kind has none).
    pub family: Option<i32>,
    /// Indices into [`Advice::runs`] of the refinement runs used, coarse to fine.
    pub path: [usize; 3],
    /// Observed order p = log2(‖y₂ − y₁‖ / ‖y₃ − y₂‖) per halving of (1/count, step); `None`
    /// when the two finest runs agree exactly or no convergence was observed.
    pub order: Option<f64>,
    /// The extrapolated answer at the common time points.
    pub answer: Vec<f64>,
    /// Estimated error of the finest run, ‖answer − y₃‖ (max over time).
    pub uncertainty: f64,
    /// A warning when the finest levels do not converge.
    pub warning: Option<String>,
}

/// The result of a study.
#[derive(Clone, Debug)]
pub struct Advice {
    /// The options it ran with.
    pub output: String,
    /// Tolerance.
    pub tol: f64,
    /// The knobs studied.
    pub knobs: Vec<Knob>,
    /// Common time points [s] (communication points of every run).
    pub times: Vec<f64>,
    /// Communication step of the study [s].
    pub comm_step: f64,
    /// Every run.
    pub runs: Vec<Run>,
    /// Each family's converged answer, the scene's family first.
    pub families: Vec<FamilyAnswer>,
    /// Max over time of the difference between the scene's family's converged answer and
    /// each other family's, by family code.
    pub family_differences: Vec<(i32, f64)>,
    /// Families the choice may use.
    pub allowed_families: Vec<Option<i32>>,
    /// Index into `runs` of the cheapest configuration within `tol` among allowed families.
    pub chosen: Option<usize>,
    /// Families left out (their refinement failed), with why.
    pub notes: Vec<String>,
}

impl Advice {
    /// Simulated time span [s].
    pub fn span(&self) -> f64 {
        self.times[self.times.len() - 1] - self.times[0]
    }

    /// The family answer the run `i` is measured against.
    pub fn answer_of(&self, i: usize) -> &FamilyAnswer {
        let f = self.runs[i].config.family;
        self.families
            .iter()
            .find(|a| a.family == f)
            .expect("every family has an answer")
    }

    /// Whether run `i` is on the Pareto front (no other successful run is both faster and at
    /// most as wrong).
    pub fn pareto(&self, i: usize) -> bool {
        let r = &self.runs[i];
        r.error.is_finite()
            && !self.runs.iter().enumerate().any(|(j, o)| {
                j != i
                    && o.error.is_finite()
                    && o.wall <= r.wall
                    && o.error <= r.error
                    && (o.wall < r.wall || o.error < r.error)
            })
    }
}

/// The error of `samples` against `answer`: max over the common time points.
pub fn max_difference(samples: &[f64], answer: &[f64]) -> f64 {
    samples
        .iter()
        .zip(answer)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// Richardson extrapolation of three runs `y1`, `y2`, `y3` (coarse to fine, each refinement
/// halving the discretization parameters): with r = ‖y₂ − y₁‖∞ / ‖y₃ − y₂‖∞ the observed
/// order is p = log₂ r and the answer y* = y₃ + (y₃ − y₂)/(r − 1) at every time point
/// (Richardson 1911; the observed-order form, e.g. Roache, "Verification and Validation in
/// Computational Science and Engineering", 1998, ch. 5). Returns (answer, order, uncertainty
/// ‖y* − y₃‖∞, warning). Runs that agree to round-off ([`ROUND_OFF`]) have converged: the
/// answer is the finest run, without an order. Without observed convergence (r ≤ 1.1) the answer is the finest run,
/// its uncertainty ‖y₃ − y₂‖∞, with a warning; an order below [`MIN_ORDER`] warns too (a
/// family with a warning gets no advice).
pub fn richardson(
    y1: &[f64],
    y2: &[f64],
    y3: &[f64],
) -> (Vec<f64>, Option<f64>, f64, Option<String>) {
    let d12 = max_difference(y2, y1);
    let d23 = max_difference(y3, y2);
    // converged to round-off (a quasi-static model whose answer does not depend on the
    // refined knob, e.g. the air spring's table level under the step ladder): the finest run
    // is the answer
    let size = y3.iter().fold(0.0f64, |m, y| m.max(y.abs()));
    if d23 == 0.0 || (d23 <= ROUND_OFF * size && d12 <= ROUND_OFF * size) {
        return (y3.to_vec(), None, d23, None);
    }
    let r = d12 / d23;
    if r.is_nan() || r <= 1.1 {
        return (
            y3.to_vec(),
            None,
            d23,
            Some(format!(
                "no convergence observed on the three finest levels (differences {d12:.3e} then {d23:.3e}): no advice; add finer levels (--finer) or keep the knob that does not converge (--keep)"
            )),
        );
    }
    let answer = y3
        .iter()
        .zip(y2)
        .map(|(c, b)| c + (c - b) / (r - 1.0))
        .collect();
    let p = r.log2();
    let warning = (p < MIN_ORDER).then(|| {
        format!(
            "observed order {p:.2} is below {MIN_ORDER}: the finest levels are not in the asymptotic range, the extrapolation is not trusted and no advice is given; add finer levels (--finer) or keep the knob that does not converge (--keep)"
        )
    });
    (answer, Some(p), d23 / (r - 1.0), warning)
}

/// Differences between refinement runs below this fraction of the output's largest magnitude
/// count as round-off: the runs have converged (Richardson's ratio of two round-off
/// differences means nothing).
pub const ROUND_OFF: f64 = 1e-10;

/// The smallest observed order at which the extrapolated answer is trusted (below it the
/// three finest runs are not in the asymptotic range and the advisor gives no advice).
pub const MIN_ORDER: f64 = 0.5;

/// The value of a knob at a ladder level for a base value.
fn count_at(base: i32, min: i32, offset: i32) -> i32 {
    if base == 0 {
        // 0 = the model chooses (the air spring's automatic count around): it stays its choice
        return 0;
    }
    let v = base as f64 * 2f64.powi(offset);
    (v.round() as i32).max(min)
}

/// Runs the study. Errors: an unknown output (the message lists the scene's outputs), a bad
/// tolerance or level count, a refinement run that fails.
pub fn advise(scene: &Scene, opts: &AdviseOptions) -> Result<Advice, String> {
    let vars = VariableTable::from_scene(scene);
    let outputs: Vec<&str> = vars
        .vars()
        .iter()
        .filter(|v| matches!(v.role, Role::Output(_)))
        .map(|v| v.name.as_str())
        .collect();
    match vars.by_name(&opts.output).map(|v| v.role) {
        Some(Role::Output(_)) => {}
        _ => {
            return Err(format!(
                "--output {}: not an output of scene `{}`; its outputs are: {}",
                opts.output,
                scene.model_name(),
                outputs.join(", ")
            ));
        }
    }
    if !(opts.tol.is_finite() && opts.tol > 0.0) {
        return Err(format!(
            "--tol {}: the tolerance must be a positive finite number (in the unit of {})",
            opts.tol, opts.output
        ));
    }
    if opts.levels < 3 || opts.finer >= opts.levels {
        return Err(format!(
            "--levels {} --finer {}: Richardson extrapolation needs at least 3 levels, and at least one level must not be finer than the scene",
            opts.levels, opts.finer
        ));
    }
    let t0 = scene.common.experiment.start_time;
    let stop = opts.stop_time.unwrap_or(scene.common.experiment.stop_time);
    if !(stop.is_finite() && stop > t0) {
        return Err(format!(
            "--stop-time {stop}: must be finite and after the start time {t0} s"
        ));
    }
    let defaults = ParamValues::defaults(&scene.params);
    // a knob is studied when some family's scene has it (the scene's own family first); the
    // family knob must be a parameter of the scene itself
    let all: Vec<Knob> = scene
        .body
        .knobs()
        .into_iter()
        .filter(|k| {
            defaults.get(k.param).is_some()
                || (!matches!(k.role, KnobRole::Family(_)) && k.families.is_some())
        })
        .collect();
    for name in &opts.keep {
        if !all.iter().any(|k| k.param == name) {
            return Err(format!(
                "--keep {name}: not a knob of scene `{}`; its knobs are: {}",
                scene.model_name(),
                all.iter().map(|k| k.param).collect::<Vec<_>>().join(", ")
            ));
        }
    }
    let wanted: Vec<Knob> = all
        .into_iter()
        .filter(|k| !opts.keep.iter().any(|n| n == k.param))
        .collect();
    let levels = opts.levels;
    let coarse = (levels - 1 - opts.finer) as i32;
    let base_step = wanted
        .iter()
        .find(|k| k.role == KnobRole::Step)
        .map(|k| defaults.real(k.param));
    let comm_step = base_step
        .map(|h| h * 2f64.powi(coarse))
        .unwrap_or(0.0)
        .max(scene.common.experiment.step_size)
        .min(stop - t0);
    let n_points = ((stop - t0) / comm_step - 1e-9).ceil() as usize;
    let times: Vec<f64> = (0..=n_points)
        .map(|i| (t0 + i as f64 * comm_step).min(stop))
        .collect();

    // the ladders
    let scene_family = wanted.iter().find_map(|k| match k.role {
        KnobRole::Family(_) => Some(defaults.integer(k.param)),
        _ => None,
    });
    let mut families: Vec<Option<i32>> = vec![scene_family];
    for k in &wanted {
        if let KnobRole::Family(codes) = k.role {
            families.extend(
                codes
                    .iter()
                    .filter(|c| Some(**c) != scene_family)
                    .map(|c| Some(*c)),
            );
        }
    }
    // each family runs on its own scene file (the family key set, the other family's options
    // removed, or the kind's own derivation), so that the kind's scene checks and table-driven
    // model choices apply; a family whose scene is refused is left out with the reason
    let mut dropped = Vec::new();
    let mut scenes = vec![FamilyScene::new(scene_family, scene.clone(), opts)?];
    for f in families.iter().skip(1) {
        let code = f.expect("other families have codes");
        match family_scene(scene, &wanted, code).and_then(|sc| FamilyScene::new(*f, sc, opts)) {
            Ok(fs) => scenes.push(fs),
            Err(e) => dropped.push(format!("family {code} left out: {e}")),
        }
    }
    let families: Vec<Option<i32>> = scenes.iter().map(|f| f.family).collect();
    // the knobs some family's scene has
    let knobs: Vec<Knob> = wanted
        .into_iter()
        .filter(|k| scenes.iter().any(|f| f.has(k)))
        .collect();
    // whether a family's refinement refines a count (the table level has none)
    let family_has_count = |f: Option<i32>| {
        scenes.iter().any(|s| {
            s.family == f
                && knobs
                    .iter()
                    .any(|k| matches!(k.role, KnobRole::Count { .. }) && s.has(k))
        })
    };
    // variant combinations: every code of every variant knob (the scene's value included)
    let mut variants: Vec<Vec<(&'static str, Value)>> = vec![vec![]];
    for k in &knobs {
        if let KnobRole::Variant(codes) = k.role {
            let own = defaults.integer(k.param);
            let mut list = vec![own];
            list.extend(codes.iter().filter(|c| **c != own));
            variants = variants
                .into_iter()
                .flat_map(|v| {
                    list.iter().map(move |c| {
                        let mut v = v.clone();
                        v.push((k.param, Value::Integer(*c)));
                        v
                    })
                })
                .collect();
        }
    }
    let has_tolerance = knobs.iter().any(|k| k.role == KnobRole::Tolerance);
    let has_count = knobs
        .iter()
        .any(|k| matches!(k.role, KnobRole::Count { .. }));
    let has_step = knobs.iter().any(|k| k.role == KnobRole::Step);
    if !has_count && !has_step {
        return Err(
            "nothing to refine: every count and the step are kept (--keep); Richardson extrapolation needs a ladder"
                .into(),
        );
    }
    // a knob kept at the scene's value has one level, which every refinement level shares
    let mesh_levels = |f: Option<i32>| {
        if family_has_count(f) {
            0..levels
        } else {
            levels - 1..levels
        }
    };
    let step_levels = if has_step {
        0..levels
    } else {
        levels - 1..levels
    };
    let mut configs = Vec::new();
    for family in &families {
        let fs = scenes
            .iter()
            .find(|s| s.family == *family)
            .expect("a scene per family");
        for m in mesh_levels(*family) {
            for (vi, variant) in variants.iter().enumerate() {
                let steps = step_levels.clone().map(|s| (s, None));
                let adaptive = (0..levels)
                    .filter(|_| has_tolerance && has_step && vi == 0)
                    .map(|k| (0, Some(k)));
                for (s, tl) in steps.chain(adaptive) {
                    let mut values = Vec::new();
                    for k in knobs.iter().filter(|k| fs.has(k)) {
                        let defaults = &fs.defaults;
                        let v = match k.role {
                            KnobRole::Family(_) => Value::Integer(family.expect("family knob")),
                            KnobRole::Variant(_) => {
                                match variant.iter().find(|(n, _)| *n == k.param) {
                                    Some((_, v)) => *v,
                                    None => defaults.get(k.param).expect("filtered"),
                                }
                            }
                            KnobRole::Count { min } => Value::Integer(count_at(
                                defaults.integer(k.param),
                                min,
                                m as i32 - coarse,
                            )),
                            KnobRole::Step => {
                                Value::Real(defaults.real(k.param) * 2f64.powi(coarse - s as i32))
                            }
                            KnobRole::Tolerance => Value::Real(match tl {
                                Some(k) => 1e-2 * 10f64.powi(-(k as i32)),
                                None => 0.0,
                            }),
                        };
                        values.push((k.param, v));
                    }
                    configs.push(Config {
                        values,
                        family: *family,
                        mesh_level: m,
                        step_level: s,
                        scene_variant: vi == 0,
                        tol_level: tl,
                    });
                }
            }
        }
    }
    // identical configurations (a count clamped at its minimum) run once
    let mut unique: Vec<Config> = Vec::new();
    for c in configs {
        if !unique.iter().any(|u| u.values == c.values) {
            unique.push(c);
        }
    }
    let configs = unique;

    let results = run_all(&scenes, &configs, &times, opts)?;
    let mut runs: Vec<Run> = configs
        .into_iter()
        .zip(results)
        .map(|(config, (samples, wall))| Run {
            config,
            samples,
            wall,
            error: f64::INFINITY,
        })
        .collect();

    // each family's answer from its refinement path (mesh level = step level, scene variants,
    // fixed steps), three finest levels
    let mut answers = Vec::new();
    'family: for family in &families {
        let find = |l: usize| {
            runs.iter().position(|r| {
                r.config.family == *family
                    && r.config.scene_variant
                    && r.config.tol_level.is_none()
                    && (!family_has_count(*family) || r.config.mesh_level == l)
                    && (!has_step || r.config.step_level == l)
            })
        };
        let path: Vec<usize> = (levels - 3..levels).filter_map(find).collect();
        let path: [usize; 3] = path
            .try_into()
            .map_err(|_| "internal: refinement path incomplete".to_string())?;
        let mut ys = Vec::new();
        for &i in &path {
            match &runs[i].samples {
                Ok(y) => ys.push(y.clone()),
                Err(e) if !answers.is_empty() => {
                    // another family than the scene's: left out of the advice, said why
                    dropped.push(format!(
                        "family {} left out: its refinement run {} failed: {e}",
                        family.map(|f| f.to_string()).unwrap_or_default(),
                        runs[i].config.label()
                    ));
                    continue 'family;
                }
                Err(e) => {
                    return Err(format!(
                        "the refinement run {} failed, so there is no converged answer{}: {e}",
                        runs[i].config.label(),
                        family
                            .map(|f| format!(" for family {f}"))
                            .unwrap_or_default()
                    ));
                }
            }
        }
        let (answer, order, uncertainty, warning) = richardson(&ys[0], &ys[1], &ys[2]);
        answers.push(FamilyAnswer {
            family: *family,
            path,
            order,
            answer,
            uncertainty,
            warning,
        });
    }
    runs.retain(|r| answers.iter().any(|a| a.family == r.config.family));
    for r in &mut runs {
        let a = answers
            .iter()
            .find(|a| a.family == r.config.family)
            .expect("answer per family");
        r.error = match &r.samples {
            Ok(y) => max_difference(y, &a.answer),
            Err(_) => f64::INFINITY,
        };
    }
    // the path indices after dropping families' runs
    for a in &mut answers {
        let f = a.family;
        for (slot, l) in a.path.iter_mut().zip(levels - 3..levels) {
            *slot = runs
                .iter()
                .position(|r| {
                    r.config.family == f
                        && r.config.scene_variant
                        && r.config.tol_level.is_none()
                        && (!family_has_count(f) || r.config.mesh_level == l)
                        && (!has_step || r.config.step_level == l)
                })
                .expect("path runs kept");
        }
    }
    let family_differences: Vec<(i32, f64)> = answers[1..]
        .iter()
        .map(|a| {
            (
                a.family.expect("other families have codes"),
                max_difference(&a.answer, &answers[0].answer),
            )
        })
        .collect();
    let mut allowed = vec![scene_family];
    for (f, d) in &family_differences {
        if opts.allow_element_change || *d <= opts.tol {
            allowed.push(Some(*f));
        }
    }
    // only families whose answer is trusted (no warning) are advised
    let trusted: Vec<Option<i32>> = answers
        .iter()
        .filter(|a| a.warning.is_none())
        .map(|a| a.family)
        .collect();
    let chosen = (0..runs.len())
        .filter(|&i| {
            runs[i].error <= opts.tol
                && allowed.contains(&runs[i].config.family)
                && trusted.contains(&runs[i].config.family)
        })
        .min_by(|&a, &b| runs[a].wall.total_cmp(&runs[b].wall));
    Ok(Advice {
        output: opts.output.clone(),
        tol: opts.tol,
        knobs,
        times,
        comm_step,
        runs,
        families: answers,
        family_differences,
        allowed_families: allowed,
        chosen,
        notes: dropped,
    })
}

/// The scene of family `code`: the kind's derivation when it has one
/// ([`crate::kinds::KindScene::family_scene`]), otherwise the scene's text with the family
/// knob set to `code` (and the keys it drops removed); parsed and checked.
pub fn family_scene(scene: &Scene, knobs: &[Knob], code: i32) -> Result<Scene, String> {
    use super::scene_edit::{literal, remove_key, set_key};
    if let Some(derived) = scene.body.family_scene(&scene.text, code) {
        let text = derived.map_err(|e| format!("its scene cannot be derived: {e}"))?;
        return Scene::from_toml(&text).map_err(|e| format!("its scene is refused: {}", e.0));
    }
    let mut text = scene.text.clone();
    for k in knobs
        .iter()
        .filter(|k| matches!(k.role, KnobRole::Family(_)))
    {
        text = set_key(
            &text,
            k.key.table,
            k.key.key,
            &literal(&k.key, Value::Integer(code))?,
        );
        for (c, table, key) in k.drops {
            if *c == code {
                text = remove_key(&text, table, key);
            }
        }
    }
    Scene::from_toml(&text).map_err(|e| format!("its scene is refused: {}", e.0))
}

/// One element family's scene with what the study needs of it.
struct FamilyScene {
    /// Family code (`None`: the kind has none).
    family: Option<i32>,
    /// The scene the family's runs start from.
    scene: Scene,
    /// Its parameter defaults.
    defaults: ParamValues,
    /// Index of the studied output among its outputs.
    output: usize,
    /// The input signals against its inputs.
    signals: Option<Signals>,
}

impl FamilyScene {
    fn new(family: Option<i32>, scene: Scene, opts: &AdviseOptions) -> Result<Self, String> {
        let output = match VariableTable::from_scene(&scene)
            .by_name(&opts.output)
            .map(|v| v.role)
        {
            Some(Role::Output(k)) => k,
            _ => return Err(format!("its scene has no output `{}`", opts.output)),
        };
        let signals = match &opts.inputs {
            Some(s) => Some(s.for_scene(&scene)?),
            None => None,
        };
        Ok(Self {
            family,
            defaults: ParamValues::defaults(&scene.params),
            scene,
            output,
            signals,
        })
    }

    /// Whether the knob is varied in this family's runs: it applies to the family and the
    /// family's scene has the parameter.
    fn has(&self, k: &Knob) -> bool {
        k.applies_to(self.family) && self.defaults.get(k.param).is_some()
    }
}

/// Runs every configuration on `opts.jobs` threads (largest estimated cost first), with a
/// progress bar on stderr; returns (samples or failure, wall time of the stepping) by index.
#[allow(clippy::type_complexity)]
fn run_all(
    scenes: &[FamilyScene],
    configs: &[Config],
    times: &[f64],
    opts: &AdviseOptions,
) -> Result<Vec<(Result<Vec<f64>, String>, f64)>, String> {
    // estimated cost: counts over the step
    let cost = |c: &Config| {
        c.values.iter().fold(1.0, |acc, (_, v)| {
            acc * match v {
                Value::Integer(i) if *i > 0 => *i as f64,
                _ => 1.0,
            }
        }) * 2f64.powi(c.step_level as i32)
    };
    let mut order: Vec<usize> = (0..configs.len()).collect();
    order.sort_by(|&a, &b| cost(&configs[b]).total_cmp(&cost(&configs[a])));
    let results: Mutex<Vec<Option<(Result<Vec<f64>, String>, f64)>>> =
        Mutex::new(vec![None; configs.len()]);
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let started = Instant::now();
    let progress = |n: usize| {
        if opts.progress {
            let total = configs.len();
            let width = 30;
            let filled = n * width / total.max(1);
            let el = started.elapsed().as_secs_f64();
            eprint!(
                "\radvise: [{}{}] {n}/{total} runs, {el:.0} s",
                "#".repeat(filled),
                " ".repeat(width - filled)
            );
            if n == total {
                eprintln!();
            }
        }
    };
    progress(0);
    std::thread::scope(|s| {
        for _ in 0..opts.jobs.max(1) {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(&i) = order.get(k) else { break };
                    let fs = scenes
                        .iter()
                        .find(|f| f.family == configs[i].family)
                        .expect("a scene per family");
                    let r = run_one(
                        &fs.scene,
                        &configs[i],
                        fs.output,
                        times,
                        fs.signals.as_ref(),
                    );
                    results.lock().expect("no panics while locked")[i] = Some(r);
                    progress(done.fetch_add(1, Ordering::SeqCst) + 1);
                }
            });
        }
    });
    Ok(results
        .into_inner()
        .expect("threads joined")
        .into_iter()
        .map(|r| r.expect("every configuration ran"))
        .collect())
}

/// One run: the scene with the configuration's values, inputs from `signals` (value and
/// slope at each communication point), the output at every time point.
pub fn run_one(
    scene: &Scene,
    config: &Config,
    output: usize,
    times: &[f64],
    signals: Option<&Signals>,
) -> (Result<Vec<f64>, String>, f64) {
    let mut params = ParamValues::defaults(&scene.params);
    for (n, v) in &config.values {
        params.set(n, *v);
    }
    let mut wall = 0.0;
    let samples = (|| {
        let model = build_model(scene, &params)?;
        let mut sim = Simulation::new(model, SolverConfig::from_params(&params), times[0])?;
        let set_inputs = |sim: &mut Simulation, t: f64| -> Result<(), String> {
            if let Some(s) = signals {
                for (c, (k, _, _)) in s.columns.iter().enumerate() {
                    let (v, slope) = s.at(c, t);
                    sim.set_input(*k, v);
                    sim.set_input_derivative(*k, 1, slope)?;
                }
            }
            Ok(())
        };
        set_inputs(&mut sim, times[0])?;
        sim.initialize()?;
        let clock = Instant::now();
        let mut y = Vec::with_capacity(times.len());
        y.push(sim.output(output));
        for w in times.windows(2) {
            set_inputs(&mut sim, w[0])?;
            sim.advance(w[1])
                .map_err(|e| format!("at t = {} s: {}", e.reached, e.message))?;
            let v = sim.output(output);
            if !v.is_finite() {
                return Err(format!("the output is not finite at t = {} s", w[1]));
            }
            y.push(v);
        }
        wall = clock.elapsed().as_secs_f64();
        Ok(y)
    })();
    (samples, wall)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Synthetic runs y_h(t) = sin t + C(t) h^2 with h = 1, 1/2, 1/4: the observed order is 2
    /// and the extrapolation recovers sin t (to rounding).
    #[test]
    fn richardson_recovers_a_second_order_limit() {
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.1).collect();
        let run = |h: f64| -> Vec<f64> { t.iter().map(|t| t.sin() + (1.0 + t) * h * h).collect() };
        let (y, p, unc, warn) = richardson(&run(1.0), &run(0.5), &run(0.25));
        assert!(warn.is_none());
        assert!((p.unwrap() - 2.0).abs() < 1e-12, "{p:?}");
        let exact: Vec<f64> = t.iter().map(|t| t.sin()).collect();
        assert!(max_difference(&y, &exact) < 1e-12);
        // the finest run's error is (1 + 4.9)/16
        assert!((unc - 5.9 / 16.0).abs() < 1e-12, "{unc}");
        // no convergence: a warning
        let (_, p, _, warn) = richardson(&run(0.25), &run(0.5), &run(1.0));
        assert!(p.is_none() && warn.is_some());
    }
}
