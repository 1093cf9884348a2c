//! Body kinds. A kind (planar beam, 3D beam, belt drive, ...) is one module here plus one
//! line in [`REGISTRY`]: its scene tables (strict: every key is used or rejected), parameters,
//! inputs and outputs with what they mean to its model, and the model. The scene reader, the
//! variable table, the XML writer, the FMI layer and the instance only see the traits below;
//! nothing outside a kind's module matches on the kind.
//!
//! Recipe for a new kind: `DEVELOPERS.md`, section "Adding a body kind".

/// Declares a kind's registry entry `$kind` (implementing [`BodyKind`]) and implements
/// [`KindScene`] for its tables `$tables` (with `validation`: the kind's validation figures
/// and limits, usually `include_str!("validation.txt")`), from the kind module's `scene::{check, params, io}`
/// and `$model::build(&tables, &params)` (or, for a kind with several model types, an
/// expression `build: |tables, params| ...` giving the boxed model).
macro_rules! body_kind {
    (
        $(#[$doc:meta])*
        $kind:ident {
            tables: $tables:ty,
            model: $model:ty,
            name: $name:literal,
            summary: $summary:literal,
            validation: $validation:expr,
            legacy: |$t:ident| $legacy:expr
            $(, presets: |$ps:ident| $presets:expr)?
            $(, smoke_test: |$sm:ident| $smoke:expr)?
            $(, initial_state: $istate:expr)?
            $(, build_to_restore: |$rs:ident, $rp:ident| $rbuild:expr)?
            $(, knobs: |$kn:ident| $knobs:expr)?
            $(, family_scene: |$fs:ident, $ftext:ident, $fcode:ident| $fscene:expr)? $(,)?
        }
    ) => {
        body_kind! {
            $(#[$doc])*
            $kind {
                tables: $tables,
                build: |s, p| Ok(Box::new(<$model>::build(s, p)?)),
                name: $name,
                summary: $summary,
                validation: $validation,
                legacy: |$t| $legacy
                $(, presets: |$ps| $presets)?
                $(, smoke_test: |$sm| $smoke)?
                $(, initial_state: $istate)?
                $(, build_to_restore: |$rs, $rp| $rbuild)?
                $(, knobs: |$kn| $knobs)?
            }
        }
    };
    (
        $(#[$doc:meta])*
        $kind:ident {
            tables: $tables:ty,
            build: |$s:ident, $p:ident| $build:expr,
            name: $name:literal,
            summary: $summary:literal,
            validation: $validation:expr,
            legacy: |$t:ident| $legacy:expr
            $(, presets: |$ps:ident| $presets:expr)?
            $(, smoke_test: |$sm:ident| $smoke:expr)?
            $(, initial_state: $istate:expr)?
            $(, build_to_restore: |$rs:ident, $rp:ident| $rbuild:expr)?
            $(, knobs: |$kn:ident| $knobs:expr)?
            $(, family_scene: |$fs:ident, $ftext:ident, $fcode:ident| $fscene:expr)? $(,)?
        }
    ) => {
        $(#[$doc])*
        pub struct $kind;

        impl $crate::kinds::BodyKind for $kind {
            fn name(&self) -> &'static str {
                $name
            }

            fn summary(&self) -> &'static str {
                $summary
            }

            fn validation(&self) -> &'static str {
                $validation
            }

            fn claims_legacy(&self, $t: &toml::Table) -> Option<$crate::kinds::LegacyClaim> {
                $legacy
            }

            fn tables(&self) -> &'static [&'static str] {
                $crate::scene::table_names::<$tables>()
            }

            fn parse(
                &self,
                text: &str,
            ) -> Result<std::sync::Arc<dyn $crate::kinds::KindScene>, Vec<String>> {
                let s: $tables = $crate::scene::parse_strict(text, $name)?;
                scene::check(&s)?;
                Ok(std::sync::Arc::new(s))
            }
        }

        impl $crate::kinds::KindScene for $tables {
            fn kind(&self) -> &'static dyn $crate::kinds::BodyKind {
                &$kind
            }

            fn params(&self) -> Result<Vec<$crate::scene::ParamDef>, String> {
                scene::params(self)
            }

            fn io(&self) -> Vec<$crate::variables::IoVariable> {
                scene::io(self).into_vars()
            }

            fn build_model(
                &self,
                params: &$crate::scene::ParamValues,
            ) -> Result<Box<dyn $crate::model::Model>, String> {
                let ($s, $p) = (self, params);
                $build
            }

            fn as_any(&self) -> &dyn std::any::Any {
                self
            }

            $(
                fn presets(&self) -> Vec<$crate::ls_ref::Preset> {
                    let $ps = self;
                    $presets
                }
            )?

            $(
                fn smoke_test(&self) -> $crate::ls_ref::SmokeTest {
                    let $sm = self;
                    $smoke
                }
            )?

            $(
                fn build_model_to_restore(
                    &self,
                    params: &$crate::scene::ParamValues,
                ) -> Result<Box<dyn $crate::model::Model>, String> {
                    let ($rs, $rp) = (self, params);
                    $rbuild
                }
            )?

            $(
                fn initial_state(&self) -> Option<&'static str> {
                    $istate
                }
            )?

            $(
                fn knobs(&self) -> Vec<$crate::advise::Knob> {
                    let $kn = self;
                    $knobs
                }
            )?

            $(
                fn family_scene(
                    &self,
                    text: &str,
                    code: i32,
                ) -> Option<Result<String, String>> {
                    let ($fs, $ftext, $fcode) = (self, text, code);
                    $fscene
                }
            )?
        }
    };
}

pub mod air_spring;
pub mod beam_2d;
pub mod beam_3d;
pub mod belt_3d;
pub mod belt_drive;
pub mod energy;
pub mod shell;

use crate::model::Model;
use crate::scene::ParamDef;
use crate::scene::ParamValues;
use crate::units::Unit;
use crate::variables::{Causality, IoVariable};
use std::any::Any;
use std::fmt::Debug;
use std::sync::Arc;

/// Every body kind flexfmu knows, in the order `flexfmu` lists them. A new kind adds one line.
pub static REGISTRY: &[&dyn BodyKind] = &[
    &beam_2d::Beam2dKind,
    &beam_3d::Beam3dKind,
    &belt_drive::BeltDriveKind,
    &shell::ShellKind,
    &air_spring::AirSpringKind,
    &belt_3d::Belt3dKind,
];

/// The kind named `name` (the scene key `kind = "..."`).
pub fn by_name(name: &str) -> Option<&'static dyn BodyKind> {
    REGISTRY.iter().copied().find(|k| k.name() == name)
}

/// The names of all kinds, for messages.
pub fn names() -> String {
    REGISTRY
        .iter()
        .map(|k| format!("\"{}\"", k.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// How a kind recognises a scene file without a `kind` key, weakest first: a claim by the
/// kind's own characteristic tables outranks one by the element type alone (which several
/// kinds' files share).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum LegacyClaim {
    /// By `[element] type`.
    ElementType,
    /// By tables (and the shape of their keys) only this kind has.
    Tables,
}

/// A body kind: reads its scenes.
pub trait BodyKind: Sync {
    /// The kind's name: the scene key `kind = "..."`, its module and its README entry.
    fn name(&self) -> &'static str;

    /// One line on what the kind models.
    fn summary(&self) -> &'static str;

    /// What the kind is validated against, with the measured figures, and where it stops
    /// being valid: plain text, paragraphs separated by blank lines, list items starting with
    /// `- ` (the kind's `validation.txt`, written into every FMU's documentation page).
    fn validation(&self) -> &'static str;

    /// For scene files without a `kind` key (written before the key existed): whether the
    /// tables are this kind's by its old rule, stated from its own keys only (element type,
    /// belt tables), and how strongly. The scene reader takes the one kind with the strongest
    /// claim.
    fn claims_legacy(&self, tables: &toml::Table) -> Option<LegacyClaim>;

    /// The top-level keys a scene of this kind may have (its tables, `kind` and the common
    /// `fmu`, `experiment`, `solver`), from its scene struct.
    fn tables(&self) -> &'static [&'static str];

    /// Parses a scene file of this kind strictly (every key known to the kind, with the right
    /// type) and checks it; errors name the key, its table and the kind.
    fn parse(&self, text: &str) -> Result<Arc<dyn KindScene>, Vec<String>>;
}

/// A parsed and checked scene of one kind: declares its variables and builds its model.
pub trait KindScene: Debug + Send + Sync + Any {
    /// The kind.
    fn kind(&self) -> &'static dyn BodyKind;

    /// The kind's parameters, with the scene's values as defaults (the `solver.*` parameters
    /// are added by the scene reader).
    fn params(&self) -> Result<Vec<ParamDef>, String>;

    /// The inputs and outputs, in the order of [`KindIo`].
    fn io(&self) -> Vec<IoVariable>;

    /// The model with validated parameter values. Errors name the parameter or scene key.
    fn build_model(&self, params: &ParamValues) -> Result<Box<dyn Model>, String>;

    /// The model about to receive a saved state (fmi2SetFMUstate or a deserialized state
    /// into a new simulation): a kind may skip setup that the state carries (the belt's static
    /// pre-load); by default the same as [`Self::build_model`].
    fn build_model_to_restore(&self, params: &ParamValues) -> Result<Box<dyn Model>, String> {
        self.build_model(params)
    }

    /// For tests and tools that need the kind's own tables.
    fn as_any(&self) -> &dyn Any;

    /// Named parameter sets besides the defaults (FMI-LS-REF `.ssv` files in every FMU of the
    /// kind, [`crate::ls_ref`]): none unless the kind has natural presets.
    fn presets(&self) -> Vec<crate::ls_ref::Preset> {
        Vec::new()
    }

    /// The smoke-test experiment shipped in every FMU ([`crate::ls_ref`]): unless the kind
    /// gives stimuli, its inputs stay at their start values.
    fn smoke_test(&self) -> crate::ls_ref::SmokeTest {
        crate::ls_ref::SmokeTest::default()
    }

    /// Whether the FMU ships its serialized state after initialization (with the default
    /// parameters), and what that state is; `None` (the default): it does not.
    fn initial_state(&self) -> Option<&'static str> {
        None
    }

    /// The parameters `flexfmu advise` varies in its convergence study (element family,
    /// counts, integrator, steps, tolerances: [`crate::advise::Knob`]); by default the solver
    /// knobs every kind has.
    fn knobs(&self) -> Vec<crate::advise::Knob> {
        crate::advise::solver_knobs()
    }

    /// The scene text of element family `code` (a value of the kind's family knob), derived
    /// from this scene's text `text`, when setting the family key (and removing the keys the
    /// knob drops) is not enough, e.g. when the family needs tables computed from this scene;
    /// `None` (the default): setting the key is enough.
    fn family_scene(&self, _text: &str, _code: i32) -> Option<Result<String, String>> {
        None
    }
}

/// The inputs and outputs of a scene as a kind declares them: the variables and, for each
/// input and output in the same order, what it means to the kind's model (`I`, `O`: the
/// kind's own role types). The model is built from the same tables by the same function, so
/// an input's index in the variable table is its index here.
#[derive(Clone, Debug)]
pub struct KindIo<I, O> {
    vars: Vec<IoVariable>,
    /// What each input drives, by input index.
    pub inputs: Vec<I>,
    /// What each output reports, by output index.
    pub outputs: Vec<O>,
}

impl<I, O> Default for KindIo<I, O> {
    fn default() -> Self {
        Self {
            vars: Vec::new(),
            inputs: Vec::new(),
            outputs: Vec::new(),
        }
    }
}

impl<I, O> KindIo<I, O> {
    /// Declares a continuous Real input.
    pub fn input(
        &mut self,
        name: String,
        start: f64,
        unit: Unit,
        description: String,
        role: I,
    ) -> &mut IoVariable {
        self.inputs.push(role);
        self.push(name, Causality::Input, Some(start), unit, description)
    }

    /// Declares a continuous Real output (add direct feedthrough with
    /// [`IoVariable::depending_on`]).
    pub fn output(
        &mut self,
        name: String,
        unit: Unit,
        description: String,
        role: O,
    ) -> &mut IoVariable {
        self.outputs.push(role);
        self.push(name, Causality::Output, None, unit, description)
    }

    fn push(
        &mut self,
        name: String,
        causality: Causality,
        start: Option<f64>,
        unit: Unit,
        description: String,
    ) -> &mut IoVariable {
        self.vars.push(IoVariable {
            name,
            causality,
            start,
            unit,
            description,
            depends_on: vec![],
        });
        self.vars.last_mut().expect("just pushed")
    }

    /// The variables, inputs and outputs interleaved in declaration order.
    pub fn vars(&self) -> &[IoVariable] {
        &self.vars
    }

    /// The variables, consuming the declaration.
    pub fn into_vars(self) -> Vec<IoVariable> {
        self.vars
    }
}

/// Reads the string value of `[element] type`, if any (legacy kind detection).
pub fn legacy_element_type(tables: &toml::Table) -> Option<&str> {
    tables.get("element")?.as_table()?.get("type")?.as_str()
}
