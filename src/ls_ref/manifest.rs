//! The FMI-LS-REF manifest `fmi-ls-manifest.xml` (FMI-LS-REF section "Layered Standard
//! Manifest File": root `fmiReferences` with the `fmi-ls:` name, version and description
//! attributes, one `Related` element per file with `type` (MIME), `source` (URI relative to
//! the manifest), `role` and `description`, optional `Label`s; schema
//! `fmi3LayeredStandardReferenceManifest.xsd`), the experiments file (`.exp`, MIME type
//! `application/x-ma-hs-experiments`, section "Role experiment"; the format is the one of the
//! standard's former appendix "Experiments Format", now MA-HS-Experiments: `Experiments` with
//! `Experiment` elements carrying `startTime`, `stopTime`, `stepSize` and `Parameters`,
//! `Stimuli`, `References` sources, CSV by default) and `documentation/fmi-ls-ref.html`
//! (section "Documentation").

use crate::docs::xml_text::escape;

/// `fmi-ls-name` of the layered standard.
pub const LS_NAME: &str = "org.fmi-standard.fmi-ls-ref";
/// `fmi-ls-version` this writer follows.
pub const LS_VERSION: &str = "1.0.0-alpha.1";
/// `fmi-ls-description`, fixed by the schema.
pub const LS_DESCRIPTION: &str =
    "Layered Standard providing information on related files included in an FMU.";
/// MIME type of experiment files.
pub const EXPERIMENTS_TYPE: &str = "application/x-ma-hs-experiments";
/// MIME type of SSV parameter sets.
pub const SSV_TYPE: &str = "application/x-ssp-parameter-set";

/// One related file of the manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct Related {
    /// MIME type.
    pub ty: String,
    /// URI relative to the manifest.
    pub source: String,
    /// Role (`model`, `parameter`, `experiment/smoke-test`, `result`, `serialized-state`, ...).
    pub role: String,
    /// For users.
    pub description: String,
    /// Labels (name, description).
    pub labels: Vec<(String, String)>,
}

impl Related {
    /// A related file without labels.
    pub fn new(ty: &str, source: &str, role: &str, description: &str) -> Self {
        Self {
            ty: ty.into(),
            source: source.into(),
            role: role.into(),
            description: description.into(),
            labels: Vec::new(),
        }
    }
}

/// The manifest listing `related`.
pub fn manifest(related: &[Related]) -> String {
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <fmiReferences xmlns:fmi-ls=\"http://fmi-standard.org/fmi-ls-manifest\" \
         fmi-ls:fmi-ls-name=\"{LS_NAME}\" fmi-ls:fmi-ls-version=\"{LS_VERSION}\" \
         fmi-ls:fmi-ls-description=\"{LS_DESCRIPTION}\">\n"
    );
    for r in related {
        let attrs = format!(
            "type=\"{}\" source=\"{}\" role=\"{}\" description=\"{}\"",
            escape(&r.ty),
            escape(&r.source),
            escape(&r.role),
            escape(&r.description)
        );
        if r.labels.is_empty() {
            s.push_str(&format!("  <Related {attrs}/>\n"));
        } else {
            s.push_str(&format!("  <Related {attrs}>\n"));
            for (n, d) in &r.labels {
                s.push_str(&format!(
                    "    <Label name=\"{}\" description=\"{}\"/>\n",
                    escape(n),
                    escape(d)
                ));
            }
            s.push_str("  </Related>\n");
        }
    }
    s.push_str("</fmiReferences>\n");
    s
}

/// One experiment of an experiments file.
#[derive(Clone, Debug, PartialEq)]
pub struct Experiment {
    /// Name.
    pub name: String,
    /// For users.
    pub description: String,
    /// [s]
    pub start_time: f64,
    /// [s]
    pub stop_time: f64,
    /// Communication step [s].
    pub step_size: f64,
    /// SSV parameter set (relative URI), if any.
    pub parameters: Option<String>,
    /// Stimuli CSV (relative URI), if the FMU has inputs.
    pub stimuli: Option<String>,
    /// Reference result CSV (relative URI).
    pub references: String,
}

/// The experiments file `name` holding `experiments`.
pub fn experiments(name: &str, description: &str, experiments: &[Experiment]) -> String {
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Experiments name=\"{}\" description=\"{}\">\n",
        escape(name),
        escape(description)
    );
    for x in experiments {
        s.push_str(&format!(
            "  <Experiment name=\"{}\" description=\"{}\" startTime=\"{:e}\" stopTime=\"{:e}\" stepSize=\"{:e}\">\n",
            escape(&x.name),
            escape(&x.description),
            x.start_time,
            x.stop_time,
            x.step_size
        ));
        if let Some(p) = &x.parameters {
            s.push_str(&format!("    <Parameters source=\"{}\"/>\n", escape(p)));
        }
        if let Some(p) = &x.stimuli {
            s.push_str(&format!("    <Stimuli source=\"{}\"/>\n", escape(p)));
        }
        s.push_str(&format!(
            "    <References source=\"{}\"/>\n  </Experiment>\n",
            escape(&x.references)
        ));
    }
    s.push_str("</Experiments>\n");
    s
}
