//! `flexfmu advise`: the cheapest configuration of a scene that meets a tolerance on one
//! output, with the evidence (a convergence study, the table, a Pareto plot).
//!
//! The knobs come from the scene's kind ([`crate::kinds::KindScene::knobs`]); the study is in
//! [`study`], input signals in [`signals`], the outputs in [`report`], writing knob values into
//! a scene file in [`scene_edit`].

pub mod knobs;
pub mod report;
pub mod scene_edit;
pub mod signals;
pub mod study;

pub use knobs::{Knob, KnobRole, SceneKey, solver_knobs};
pub use signals::Signals;
pub use study::{Advice, AdviseOptions, advise};
