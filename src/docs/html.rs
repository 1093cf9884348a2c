//! `documentation/index.html`: one XHTML page per FMU, generated from the scene, its variable
//! table, the kind's registry entry ([`crate::kinds::BodyKind::validation`]) and the model's
//! drawing. The page is well-formed XML (a test parses it), so it is also valid XHTML5.

use super::svg::sketch_svg;
use super::terminals::Terminal;
use super::xml_text::escape;
use crate::model::Sketch;
use crate::scene::Scene;
use crate::scene::params::names::*;
use crate::variables::{Causality, VarType, Variable, VariableTable};

/// What each solver setting buys and costs, by parameter name (README, "Solvers: buying
/// accuracy with CPU time"; figures measured there).
const SOLVER_COSTS: &[(&str, &str)] = &[
    (
        SOLVER_STATIC,
        "Static equilibrium before the first step: one Newton solve with load stepping at \
         initialization. Without it the body starts from its reference shape and swings.",
    ),
    (
        SOLVER_INTEGRATOR,
        "Generalized-α (1) damps high frequencies (ρ∞); Newmark (2) conserves energy of \
         linear systems; the midpoint rule (3) conserves energy exactly for the seed-000 \
         element; all three are implicit (a factorization per Newton iteration or fewer). \
         Central differences (4) are explicit and cheap per step but take substeps of 0.8 \
         times the stability limit, which for stiff bodies means very many.",
    ),
    (
        SOLVER_RHO_INF,
        "Numerical damping of generalized-α: 1 none, 0 the most (annihilates the highest \
         frequencies in one step). No cost difference.",
    ),
    (
        SOLVER_MAX_STEP,
        "Largest internal step: the main accuracy-for-time knob. The cost is about \
         proportional to the number of internal steps; the error of the implicit schemes \
         falls as its square.",
    ),
    (
        SOLVER_TOLERANCE,
        "Adaptive internal steps from a local error estimate (0: fixed steps of \
         solver.max_step). Saves steps where the motion is smooth.",
    ),
    (
        SOLVER_NEWTON,
        "Modified Newton (2) keeps the factorization while the iteration contracts, which \
         saved 15–20 % against full Newton (1) on the belt drive.",
    ),
    (
        SOLVER_NEWTON_TOL,
        "Convergence tolerance relative to the body length: tighter costs iterations.",
    ),
    (
        SOLVER_MAX_ITER,
        "Newton iterations before a step is halved (a failed communication step returns \
         fmi2Discard with the state rolled back).",
    ),
    (
        SOLVER_LOAD_STEPS,
        "Load increments of the static solve: more are more robust and slower.",
    ),
    (
        SOLVER_LINEAR,
        "Auto picks a banded LU for chains and rings (cost linear in the element count) or a \
         sparse LU otherwise; forcing one is for benchmarks.",
    ),
];

/// The documentation page of `scene`: `sketch` is the model's drawing with the default
/// parameters, `n_free` its number of free coordinates (none: the model did not build),
/// `terminals` its ports.
pub fn index_html(
    scene: &Scene,
    sketch: &Sketch,
    n_free: Option<usize>,
    terminals: &[Terminal],
) -> String {
    let vars = VariableTable::from_scene(scene);
    let kind = scene.kind();
    let name = scene.model_name();
    let e = escape;
    let mut h = String::new();
    h.push_str(&format!(
        "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n\
         <meta charset=\"UTF-8\"/>\n<title>{} — flexfmu</title>\n<style>\n{}</style>\n</head>\n<body>\n",
        e(name),
        STYLE
    ));
    h.push_str(&format!("<h1>{}</h1>\n", e(name)));
    if !scene.common.fmu.description.is_empty() {
        h.push_str(&format!(
            "<p class=\"lead\">{}</p>\n",
            e(&scene.common.fmu.description)
        ));
    }
    let exp = &scene.common.experiment;
    let count = |c: Causality| vars.vars().iter().filter(|v| v.causality == c).count();
    h.push_str("<table class=\"facts\">\n");
    for (k, v) in [
        ("body kind", format!("{} — {}", kind.name(), kind.summary())),
        ("mesh", sketch.mesh.clone()),
        (
            "free coordinates",
            n_free.map_or_else(|| "—".to_string(), |n| n.to_string()),
        ),
        (
            "variables",
            format!(
                "{} parameters, {} inputs, {} outputs",
                count(Causality::Parameter),
                count(Causality::Input),
                count(Causality::Output)
            ),
        ),
        (
            "default experiment",
            format!(
                "{} s to {} s, communication step {} s",
                exp.start_time, exp.stop_time, exp.step_size
            ),
        ),
        (
            "FMI",
            "2.0 Co-Simulation; variable communication steps, input interpolation, output \
             derivatives, FMU state get/set/serialize, directional derivatives"
                .to_string(),
        ),
        (
            "generated by",
            format!("flexfmu {}", env!("CARGO_PKG_VERSION")),
        ),
    ] {
        h.push_str(&format!("<tr><th>{}</th><td>{}</td></tr>\n", e(k), e(&v)));
    }
    h.push_str("</table>\n");

    h.push_str("<h2>Picture</h2>\n<figure>\n");
    h.push_str(&sketch_svg(
        sketch,
        640.0,
        400.0,
        &format!("{name}: geometry"),
    ));
    h.push_str(
        "\n<figcaption>The model as the FMU builds it with the default parameters, before \
         initialization, drawn from its node positions (a flat body in its plane, a \
         meridian from the front, a spatial body in isometric view).</figcaption>\n</figure>\n",
    );

    h.push_str("<h2>Ports</h2>\n");
    if terminals.is_empty() {
        h.push_str("<p>No ports: the scene has no inputs.</p>\n");
    } else {
        h.push_str(
            "<p>Groups of inputs and outputs that a master connects to one body: also in \
             <code>terminalsAndIcons/terminalsAndIcons.xml</code>.</p>\n<table>\n\
             <tr><th>port</th><th>inputs and outputs</th></tr>\n",
        );
        for t in terminals {
            h.push_str(&format!(
                "<tr><td><code>{}</code></td><td>{}</td></tr>\n",
                e(&t.name),
                e(&t.description())
            ));
        }
        h.push_str("</table>\n");
    }

    for (title, c) in [
        ("Parameters", Causality::Parameter),
        ("Inputs", Causality::Input),
        ("Outputs", Causality::Output),
    ] {
        let rows: Vec<&Variable> = vars.vars().iter().filter(|v| v.causality == c).collect();
        h.push_str(&format!("<h2>{title}</h2>\n"));
        if rows.is_empty() {
            h.push_str("<p>None.</p>\n");
            continue;
        }
        h.push_str(
            "<table>\n<tr><th>name</th><th>type</th><th>variability</th><th>unit</th>\
             <th>start</th><th>min</th><th>max</th><th>description</th></tr>\n",
        );
        for v in rows {
            h.push_str(&variable_row(v, &vars));
        }
        h.push_str("</table>\n");
    }

    h.push_str(&format!(
        "<h2>Validation and limits of the {} kind</h2>\n{}",
        e(kind.name()),
        text_blocks(kind.validation())
    ));

    h.push_str(
        "<h2>Solver settings and what they cost</h2>\n<p>Every scene exposes these as \
         parameters; the values here are this FMU's defaults.</p>\n<table>\n\
         <tr><th>parameter</th><th>default</th><th>effect and cost</th></tr>\n",
    );
    for v in vars.vars().iter().filter(|v| v.name.starts_with("solver.")) {
        let cost = SOLVER_COSTS
            .iter()
            .find(|(n, _)| *n == v.name)
            .map(|(_, c)| *c)
            .unwrap_or(v.description.as_str());
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td></tr>\n",
            e(&v.name),
            v.start.map(|s| e(&s.xml())).unwrap_or_default(),
            e(cost)
        ));
    }
    h.push_str("</table>\n");

    h.push_str(
        "<h2>What this FMU contains</h2>\n<ul>\n\
         <li><code>modelDescription.xml</code>: the variables above.</li>\n\
         <li><code>resources/scene.toml</code>: the scene file the FMU was built from.</li>\n\
         <li><code>binaries/&lt;platform&gt;/</code>: the shared library, one per platform; \
         it needs only the C library.</li>\n\
         <li><code>documentation/licenses/license.txt</code>: licences of flexfmu and of \
         every crate linked into the library.</li>\n\
         <li><code>terminalsAndIcons/terminalsAndIcons.xml</code> and \
         <code>model.png</code>: the ports and the icon.</li>\n\
         <li><code>extra/org.fmi-standard.fmi-ls-ref/</code>: reference files after the FMI \
         layered standard FMI-LS-REF (the scene, parameter sets, a smoke test with its \
         reference result): see <a href=\"fmi-ls-ref.html\">fmi-ls-ref.html</a> and \
         <a href=\"../extra/org.fmi-standard.fmi-ls-ref/fmi-ls-manifest.xml\">the \
         manifest</a>.</li>\n</ul>\n</body>\n</html>\n",
    );
    h
}

fn variable_row(v: &Variable, vars: &VariableTable) -> String {
    let e = escape;
    let ty = match v.ty {
        VarType::Real => "Real",
        VarType::Integer => "Integer",
        VarType::Boolean => "Boolean",
    };
    let num = |x: Option<f64>| x.map(|x| format!("{x}")).unwrap_or_default();
    let mut desc = e(&v.description);
    if !v.depends_on.is_empty() {
        let names: Vec<String> = v
            .depends_on
            .iter()
            .filter_map(|vr| vars.get(*vr))
            .map(|d| format!("<code>{}</code>", e(&d.name)))
            .collect();
        desc.push_str(&format!(" (depends directly on {})", names.join(", ")));
    }
    format!(
        "<tr><td><code>{}</code></td><td>{ty}</td><td>{}</td><td>{}</td><td>{}</td>\
         <td>{}</td><td>{}</td><td>{desc}</td></tr>\n",
        e(&v.name),
        v.variability.as_str(),
        e(v.unit.map(|u| u.name()).unwrap_or("")),
        v.start.map(|s| e(&s.xml())).unwrap_or_default(),
        num(v.min),
        num(v.max),
    )
}

/// Plain text as XHTML: paragraphs separated by blank lines; a paragraph whose lines start
/// with `- ` is a list.
pub fn text_blocks(text: &str) -> String {
    let mut out = String::new();
    for block in text.split("\n\n").map(str::trim).filter(|b| !b.is_empty()) {
        if block.starts_with("- ") {
            out.push_str("<ul>\n");
            for item in block.split("\n- ") {
                let item = item.trim_start_matches("- ").replace('\n', " ");
                out.push_str(&format!("<li>{}</li>\n", escape(item.trim())));
            }
            out.push_str("</ul>\n");
        } else {
            out.push_str(&format!("<p>{}</p>\n", escape(&block.replace('\n', " "))));
        }
    }
    out
}

const STYLE: &str = "body { font-family: sans-serif; max-width: 60em; margin: 2em auto; \
padding: 0 1em; color: #222; }\n\
table { border-collapse: collapse; margin: 1em 0; }\n\
th, td { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: left; vertical-align: top; }\n\
table.facts th { background: #f3f3f3; }\n\
code { font-size: 0.95em; }\n\
p.lead { font-size: 1.1em; }\n";

#[cfg(test)]
mod tests {
    use super::text_blocks;

    #[test]
    fn paragraphs_and_lists() {
        let t = "One\nline.\n\n- a\n- b < c\n  more\n\nEnd.";
        assert_eq!(
            text_blocks(t),
            "<p>One line.</p>\n<ul>\n<li>a</li>\n<li>b &lt; c   more</li>\n</ul>\n<p>End.</p>\n"
        );
    }
}
