//! What `flexfmu advise` writes: the advised scene file, the table (CSV and markdown), the
//! Pareto plot (SVG, error against wall time per simulated second, log-log) and the summary
//! (the converged answers with their order and extrapolation, the families' difference).

use super::scene_edit::{literal, remove_key, set_key};
use super::study::{Advice, show};
use crate::scene::{ParamValues, Scene};
use std::fmt::Write;

/// A family code as the table shows it.
fn family(f: Option<i32>) -> String {
    f.map(|f| f.to_string()).unwrap_or_else(|| "-".into())
}

/// The summary printed before the table: time grid, each family's converged answer (order,
/// extrapolation, uncertainty), the difference between families next to TOL, the choice.
pub fn summary(a: &Advice) -> String {
    let mut s = String::new();
    let span = a.span();
    let _ = writeln!(
        s,
        "output {} over {} s, compared at {} communication points every {:e} s; TOL = {:e}",
        a.output,
        span,
        a.times.len(),
        a.comm_step,
        a.tol
    );
    for f in &a.families {
        let path: Vec<String> = f.path.iter().map(|&i| a.runs[i].config.label()).collect();
        let _ = writeln!(
            s,
            "family {}: converged answer by Richardson extrapolation y* = y3 + (y3 - y2)/(r - 1), r = |y2 - y1|/|y3 - y2| (max over time), observed order p = log2 r = {}, estimated error of the finest run {:.3e}; runs y1..y3: {}",
            family(f.family),
            f.order
                .map(|p| format!("{p:.2}"))
                .unwrap_or_else(|| "n/a".into()),
            f.uncertainty,
            path.join(" | ")
        );
        if let Some(w) = &f.warning {
            let _ = writeln!(s, "  warning: {w}");
        }
    }
    for n in &a.notes {
        let _ = writeln!(s, "{n}");
    }
    for (f, d) in &a.family_differences {
        let _ = writeln!(
            s,
            "difference between the converged answers of family {} (the scene's) and family {f}: {d:.3e} (TOL {:e}): {}",
            family(a.families[0].family),
            a.tol,
            if *d <= a.tol {
                "within TOL, the family may change"
            } else if a.allowed_families.contains(&Some(*f)) {
                "above TOL, family change allowed by --allow-element-change"
            } else {
                "above TOL, the family stays (--allow-element-change to allow it)"
            }
        );
    }
    match a.chosen {
        Some(i) => {
            let r = &a.runs[i];
            let finest = a.families[0].path[2];
            let _ = writeln!(
                s,
                "advice: {} (family {}): error {:.3e} <= TOL {:e}, {:.3e} s wall per simulated second, real-time factor {:.3}, {:.1}x faster than the finest refinement run",
                r.config.label(),
                family(r.config.family),
                r.error,
                a.tol,
                r.wall_per_second(span),
                1.0 / r.wall_per_second(span),
                a.runs[finest].wall / r.wall
            );
        }
        None => {
            let best =
                (0..a.runs.len()).min_by(|&x, &y| a.runs[x].error.total_cmp(&a.runs[y].error));
            let _ = writeln!(
                s,
                "advice: none: no configuration of a family with a trusted converged answer meets TOL {:e} (see the warnings); the most accurate run was {} with error {:.3e}",
                a.tol,
                best.map(|i| a.runs[i].config.label()).unwrap_or_default(),
                best.map(|i| a.runs[i].error).unwrap_or(f64::NAN)
            );
        }
    }
    s
}

/// The table as CSV: one row per run, a column per knob, then family, error, wall time per
/// simulated second, real-time factor, within TOL, Pareto, chosen, failure.
pub fn csv(a: &Advice) -> String {
    let span = a.span();
    let mut s = String::from("configuration,family");
    for k in &a.knobs {
        let _ = write!(s, ",{}", k.param);
    }
    s.push_str(
        ",error,wall_time_per_simulated_second,real_time_factor,within_tol,pareto,chosen,failure\n",
    );
    for (i, r) in a.runs.iter().enumerate() {
        let _ = write!(s, "{},{}", r.config.label(), family(r.config.family));
        for k in &a.knobs {
            // empty where the knob does not apply to the run's family
            let v = r.config.values.iter().find(|(n, _)| *n == k.param);
            let _ = write!(s, ",{}", v.map(|(_, v)| show(*v)).unwrap_or_default());
        }
        let w = r.wall_per_second(span);
        let _ = writeln!(
            s,
            ",{:e},{:e},{:e},{},{},{},{}",
            r.error,
            w,
            1.0 / w,
            r.error <= a.tol,
            a.pareto(i),
            a.chosen == Some(i),
            r.samples
                .as_ref()
                .err()
                .map(|e| e.replace([',', '\n'], ";"))
                .unwrap_or_default()
        );
    }
    s
}

/// The table as markdown, sorted by wall time (`*` Pareto front, `<-` the advice).
pub fn markdown(a: &Advice) -> String {
    let span = a.span();
    let mut idx: Vec<usize> = (0..a.runs.len()).collect();
    idx.sort_by(|&x, &y| a.runs[x].wall.total_cmp(&a.runs[y].wall));
    let mut s = String::from(
        "| configuration | family | error | wall time per simulated second [s] | real-time factor | |\n|---|---|---|---|---|---|\n",
    );
    for i in idx {
        let r = &a.runs[i];
        let w = r.wall_per_second(span);
        let mark = match (a.chosen == Some(i), a.pareto(i)) {
            (true, _) => "<- advice",
            (false, true) => "*",
            _ => "",
        };
        let err = match &r.samples {
            Ok(_) => format!("{:.3e}", r.error),
            Err(e) => format!("failed: {}", e.chars().take(60).collect::<String>()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {err} | {w:.3e} | {:.3} | {mark} |",
            r.config.label(),
            family(r.config.family),
            1.0 / w
        );
    }
    s
}

/// The advised scene: the original text (for another element family: the family's scene,
/// [`super::study::family_scene`]) with the chosen knob values set, a header comment saying
/// where they come from. Checked: the new file parses and its parameter defaults are the
/// chosen values.
pub fn advised_scene(scene: &Scene, a: &Advice) -> Result<String, String> {
    let i = a.chosen.ok_or(
        "no advice: no configuration meets the tolerance against a trusted converged answer (see the summary)",
    )?;
    let r = &a.runs[i];
    let mut text = match r.config.family {
        Some(code) if r.config.family != a.families[0].family => {
            super::study::family_scene(scene, &a.knobs, code)?.text
        }
        _ => scene.text.clone(),
    };
    for (n, v) in &r.config.values {
        let k = a
            .knobs
            .iter()
            .find(|k| k.param == *n)
            .expect("every value is a knob's");
        text = set_key(&text, k.key.table, k.key.key, &literal(&k.key, *v)?);
        for (code, table, key) in k.drops {
            if *v == crate::variables::Value::Integer(*code) {
                text = remove_key(&text, table, key);
            }
        }
    }
    let header = format!(
        "# flexfmu advise --output {} --tol {:e}: {} (error {:.3e} over {} s against the converged answer)\n",
        a.output,
        a.tol,
        r.config.label(),
        r.error,
        a.span()
    );
    let text = header + &text;
    let check = Scene::from_toml(&text).map_err(|e| format!("the advised scene: {}", e.0))?;
    let got = ParamValues::defaults(&check.params);
    for (n, v) in &r.config.values {
        if got.get(n) != Some(*v) {
            return Err(format!(
                "the advised scene does not set {n} = {} (it reads {:?}); the knob's scene key is wrong",
                show(*v),
                got.get(n)
            ));
        }
    }
    Ok(text)
}

/// The Pareto plot as SVG: every successful run (error against wall time per simulated
/// second, log-log; a colour per family), the Pareto front as a line, TOL dashed, the advice
/// circled.
pub fn pareto_svg(a: &Advice) -> String {
    let span = a.span();
    let pts: Vec<(usize, f64, f64)> = a
        .runs
        .iter()
        .enumerate()
        .filter(|(_, r)| r.error.is_finite())
        .map(|(i, r)| (i, r.wall_per_second(span).max(1e-12), r.error.max(1e-16)))
        .collect();
    let (w, h, m) = (640.0, 440.0, 70.0);
    let lg = f64::log10;
    let bounds = |f: &dyn Fn(&(usize, f64, f64)) -> f64, extra: f64| {
        let lo = pts.iter().map(f).fold(extra, f64::min);
        let hi = pts.iter().map(f).fold(extra, f64::max);
        (lg(lo).floor(), lg(hi).ceil().max(lg(lo).floor() + 1.0))
    };
    let (x0, x1) = bounds(&|p| p.1, pts.first().map(|p| p.1).unwrap_or(1.0));
    let (y0, y1) = bounds(&|p| p.2, a.tol);
    let px = |x: f64| m + (lg(x) - x0) / (x1 - x0) * (w - 1.5 * m);
    let py = |y: f64| h - m + (lg(y) - y0) / (y1 - y0) * -(h - 1.5 * m);
    let colors = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd"];
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for e in x0 as i32..=x1 as i32 {
        let x = px(10f64.powi(e));
        let _ = writeln!(
            s,
            "<line x1=\"{x:.1}\" y1=\"{:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#ddd\"/><text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\">1e{e}</text>",
            py(10f64.powf(y0)),
            py(10f64.powf(y1)),
            h - m + 18.0
        );
    }
    for e in y0 as i32..=y1 as i32 {
        let y = py(10f64.powi(e));
        let _ = writeln!(
            s,
            "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#ddd\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">1e{e}</text>",
            px(10f64.powf(x0)),
            px(10f64.powf(x1)),
            m - 6.0,
            y + 4.0
        );
    }
    let ty = py(a.tol);
    let _ = writeln!(
        s,
        "<line x1=\"{:.1}\" y1=\"{ty:.1}\" x2=\"{:.1}\" y2=\"{ty:.1}\" stroke=\"red\" stroke-dasharray=\"6,4\"/><text x=\"{:.1}\" y=\"{:.1}\" fill=\"red\" text-anchor=\"end\">TOL</text>",
        px(10f64.powf(x0)),
        px(10f64.powf(x1)),
        px(10f64.powf(x1)) - 4.0,
        ty - 4.0
    );
    let fam_index = |f: Option<i32>| a.families.iter().position(|x| x.family == f).unwrap_or(0);
    for &(i, x, y) in &pts {
        let c = colors[fam_index(a.runs[i].config.family) % colors.len()];
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3\" fill=\"{c}\" fill-opacity=\"0.6\"><title>{}</title></circle>",
            px(x),
            py(y),
            a.runs[i].config.label()
        );
    }
    let mut front: Vec<&(usize, f64, f64)> = pts.iter().filter(|p| a.pareto(p.0)).collect();
    front.sort_by(|p, q| p.1.total_cmp(&q.1));
    let line: Vec<String> = front
        .iter()
        .map(|p| format!("{:.1},{:.1}", px(p.1), py(p.2)))
        .collect();
    let _ = writeln!(
        s,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"black\"/>",
        line.join(" ")
    );
    if let Some(&(_, x, y)) = pts.iter().find(|p| Some(p.0) == a.chosen) {
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"8\" fill=\"none\" stroke=\"red\" stroke-width=\"2\"/>",
            px(x),
            py(y)
        );
    }
    for (k, f) in a.families.iter().enumerate() {
        let _ = writeln!(
            s,
            "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"4\" fill=\"{}\"/><text x=\"{:.1}\" y=\"{:.1}\">family {}</text>",
            w - 150.0,
            20.0 + 16.0 * k as f64,
            colors[k % colors.len()],
            w - 140.0,
            24.0 + 16.0 * k as f64,
            family(f.family)
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">wall time per simulated second [s]</text>\n<text x=\"16\" y=\"{:.1}\" transform=\"rotate(-90 16 {:.1})\" text-anchor=\"middle\">max error of {} over the run</text>\n</svg>",
        w / 2.0,
        h - 20.0,
        h / 2.0,
        h / 2.0,
        a.output
    );
    s
}
