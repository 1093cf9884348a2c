//! What an FMU carries besides its model description and library (FMI 2.0.4, section 2.3):
//! `documentation/index.html` ([`html`]) with a drawing of the body ([`svg`]),
//! `documentation/licenses/` ([`licenses`]), `model.png` ([`png`]),
//! `terminalsAndIcons/terminalsAndIcons.xml` ([`terminals`]) and the OSP side file
//! ([`osp`]). [`files`] assembles them for a scene. Everything derives from the scene, its
//! variable table and the model's own drawing ([`crate::model::Model::sketch`]): nothing
//! here knows a body kind.

pub mod files;
pub mod html;
pub mod license_collector;
pub mod licenses;
pub mod osp;
pub mod png;
pub mod svg;
pub mod terminals;
pub mod xml_text;

pub use files::{FmuFile, documentation_files};
