//! Instance lifecycle, variable access, stepping and status.

use crate::fmi2::state_machine::{Call, State};
use crate::logging::{LogFilter, Status, status_category};
use crate::model::{build_model, build_model_to_restore};
use crate::model_description::scene_guid;
use crate::scene::params::ParamVariability;
use crate::scene::{ParamValues, Scene};
use crate::solver::simulation::{MAX_SUBSTEPS, Simulation, SolverConfig};
use crate::variables::{Causality, Role, Value, VarType, Variability, Variable, VariableTable};
use std::path::{Path, PathBuf};

/// Receives every message that passes the log filter: status, category, text.
pub type LogSink = Box<dyn FnMut(Status, &str, &str)>;

/// Status kinds of fmi2Get*Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    /// fmi2DoStepStatus
    DoStepStatus,
    /// fmi2PendingStatus
    PendingStatus,
    /// fmi2LastSuccessfulTime
    LastSuccessfulTime,
    /// fmi2Terminated
    Terminated,
}

/// The scene file inside an FMU's resources.
pub const SCENE_FILE: &str = "scene.toml";

/// Turns an `fmuResourceLocation` URI (`file:///…`, `file://localhost/…`, `file:/…`) or a
/// plain path into a directory path, decoding `%XX` escapes.
pub fn resource_dir_from_uri(uri: &str) -> Result<PathBuf, String> {
    let rest = if let Some(r) = uri.strip_prefix("file://localhost/") {
        format!("/{r}")
    } else if let Some(r) = uri.strip_prefix("file:///") {
        format!("/{r}")
    } else if let Some(r) = uri.strip_prefix("file://") {
        return Err(format!(
            "fmuResourceLocation \"{uri}\": remote host \"{}\" not supported",
            r.split('/').next().unwrap_or("")
        ));
    } else if let Some(r) = uri.strip_prefix("file:") {
        r.to_string()
    } else if uri.contains("://") {
        return Err(format!(
            "fmuResourceLocation \"{uri}\": only file URIs are supported"
        ));
    } else {
        uri.to_string()
    };
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).unwrap_or("zz");
            if let Ok(b) = u8::from_str_radix(hex, 16) {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    let s =
        String::from_utf8(out).map_err(|_| format!("fmuResourceLocation \"{uri}\": not UTF-8"))?;
    Ok(PathBuf::from(s))
}

/// One FMU instance.
pub struct Instance {
    pub(super) name: String,
    pub(super) guid: String,
    pub(super) scene: Scene,
    pub(super) vars: VariableTable,
    pub(super) values: Vec<Value>,
    logging_on_at_start: bool,
    filter: LogFilter,
    sink: LogSink,
    pub(super) state: State,
    pub(super) start_time: f64,
    pub(super) sim: Option<Simulation>,
    /// Parameter and input values the simulation was built with.
    pub(super) built_with: Option<Vec<Value>>,
    /// Parameters or inputs changed since the simulation was built (Initialization Mode).
    pub(super) dirty: bool,
    /// Input derivatives set before the simulation exists (applied when it is built).
    pub(super) pending_derivatives: Vec<(u32, usize, f64)>,
    /// Outputs and time before the last step (fallback output derivatives); an output that
    /// had never been read then is NaN (its derivative is not available by differences).
    pub(super) previous_outputs: Option<(f64, Vec<Value>)>,
    /// Per variable: an output whose stored value is older than the simulation (computed
    /// when it is read: an importer pays only for the outputs it reads).
    pub(super) stale: Vec<bool>,
    /// Per variable: an output whose derivative the importer has asked for
    /// (fmi2GetRealOutputDerivatives); these are brought up to date before each step for the
    /// derivatives by differences. Others are not: with direct feedthrough a value at the new
    /// inputs can cost a condensation (the air spring's force), which a master that reads the
    /// force only after the step should not pay.
    pub(super) wanted: Vec<bool>,
    pub(super) last_successful_time: f64,
    pub(super) terminated: bool,
    pub(super) last_step_status: Status,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("name", &self.name)
            .field("state", &self.state)
            .finish()
    }
}

impl Instance {
    /// fmi2Instantiate for Co-Simulation: reads the scene from the resource directory and
    /// checks the GUID. On error the message explains why (the caller logs it).
    pub fn new(
        name: &str,
        guid: &str,
        resource_dir: &Path,
        logging_on: bool,
        sink: LogSink,
    ) -> Result<Self, String> {
        let path = resource_dir.join(SCENE_FILE);
        let scene = Scene::from_path(&path).map_err(|e| e.0)?;
        let expected = scene_guid(&scene);
        if guid != expected {
            return Err(format!(
                "GUID mismatch: the importer passed {guid} but the FMU's scene has {expected} (modelDescription.xml and resources/{SCENE_FILE} do not belong together)"
            ));
        }
        Ok(Self::from_scene(name, scene, logging_on, sink))
    }

    /// An instance of an already parsed scene (no GUID check).
    pub fn from_scene(name: &str, scene: Scene, logging_on: bool, sink: LogSink) -> Self {
        let vars = VariableTable::from_scene(&scene);
        let values = vars
            .vars()
            .iter()
            .map(|v| v.start.unwrap_or(Value::Real(0.0)))
            .collect();
        let mut inst = Self {
            name: name.to_string(),
            guid: scene_guid(&scene),
            scene,
            vars,
            values,
            logging_on_at_start: logging_on,
            filter: LogFilter::new(logging_on),
            sink,
            state: State::Instantiated,
            start_time: 0.0,
            sim: None,
            built_with: None,
            dirty: true,
            pending_derivatives: Vec::new(),
            previous_outputs: None,
            stale: Vec::new(),
            wanted: Vec::new(),
            last_successful_time: 0.0,
            terminated: false,
            last_step_status: Status::Ok,
        };
        inst.stale = vec![false; inst.values.len()];
        inst.wanted = vec![false; inst.values.len()];
        inst.info(format!(
            "instantiated \"{}\" ({} variables)",
            inst.scene.model_name(),
            inst.vars.vars().len()
        ));
        inst
    }

    /// Instance name given at instantiation.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Current state.
    pub fn state(&self) -> State {
        self.state
    }

    /// The variable table.
    pub fn variables(&self) -> &VariableTable {
        &self.vars
    }

    /// Delivers a message if the filter lets it pass.
    pub fn log(&mut self, status: Status, category: &str, msg: &str) {
        if self.filter.passes(status, category) {
            (self.sink)(status, category, msg);
        }
    }

    /// Logs an FMI call in the category `logCalls` (only formatted when that category is on).
    pub fn trace(&mut self, f: impl FnOnce() -> String) {
        if self.filter.passes(Status::Ok, "logCalls") {
            let msg = f();
            (self.sink)(Status::Ok, "logCalls", &msg);
        }
    }

    fn info(&mut self, msg: impl AsRef<str>) {
        self.log(Status::Ok, "logEvents", msg.as_ref());
    }

    /// Logs an error, enters the Error state and returns fmi2Error.
    pub fn error(&mut self, msg: impl AsRef<str>) -> Status {
        self.log(Status::Error, status_category(Status::Error), msg.as_ref());
        if self.state != State::Fatal {
            self.state = State::Error;
        }
        Status::Error
    }

    /// After a panic inside a call: log, enter Fatal, return fmi2Fatal.
    pub fn fatal(&mut self, msg: impl AsRef<str>) -> Status {
        self.state = State::Fatal;
        self.log(Status::Fatal, status_category(Status::Fatal), msg.as_ref());
        Status::Fatal
    }

    /// Checks the state machine; on violation logs and returns the error status.
    pub fn check(&mut self, call: Call) -> Result<(), Status> {
        if call.allowed_in(self.state) {
            Ok(())
        } else {
            let msg = format!(
                "{} is not allowed in state {} (FMI 2.0 Co-Simulation state machine)",
                call.name(),
                self.state.name()
            );
            Err(if self.state == State::Fatal {
                self.log(Status::Error, "logStatusError", &msg);
                Status::Error
            } else {
                self.error(msg)
            })
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        if let Err(s) = self.check(Call::SetDebugLogging) {
            return s;
        }
        match self.filter.set(on, categories) {
            Ok(()) => Status::Ok,
            Err(e) => self.error(e),
        }
    }

    /// fmi2SetupExperiment (the tolerance is only logged: Newton tolerances are parameters).
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status {
        self.trace(|| format!("fmi2SetupExperiment({tolerance:?}, {start:?}, {stop:?})"));
        if let Err(s) = self.check(Call::SetupExperiment) {
            return s;
        }
        if !start.is_finite() || stop.is_some_and(|s| !s.is_finite() || s < start) {
            return self.error(format!(
                "fmi2SetupExperiment: invalid times (startTime = {start}, stopTime = {stop:?})"
            ));
        }
        self.start_time = start;
        self.last_successful_time = start;
        self.info(format!(
            "setup experiment: startTime = {start}, stopTime = {stop:?}, tolerance = {tolerance:?}"
        ));
        Status::Ok
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Status {
        self.trace(|| "fmi2EnterInitializationMode()".into());
        if let Err(s) = self.check(Call::EnterInitializationMode) {
            return s;
        }
        self.state = State::InitializationMode;
        Status::Ok
    }

    /// Parameter values taken from a value vector.
    pub(super) fn param_values_of(&self, values: &[Value]) -> ParamValues {
        let mut params = ParamValues::defaults(&self.scene.params);
        for (v, val) in self.vars.vars().iter().zip(values) {
            if let Role::Parameter(name) = v.role {
                params.set(name, *val);
            }
        }
        params
    }

    /// Current parameter values.
    pub(super) fn param_values(&self) -> ParamValues {
        self.param_values_of(&self.values)
    }

    /// A simulation built from the parameters and inputs in `values`. With `initialize`, the
    /// static equilibrium (if asked) and consistent accelerations are solved; without, the
    /// caller restores a saved state into it.
    pub(super) fn new_simulation(
        &mut self,
        values: &[Value],
        initialize: bool,
    ) -> Result<Simulation, String> {
        let params = self.param_values_of(values);
        // without initialization the simulation is about to receive a saved state: the kind
        // may skip setup the state carries (the belt's static pre-load)
        let mut model = if initialize {
            build_model(&self.scene, &params)?
        } else {
            build_model_to_restore(&self.scene, &params)?
        };
        for (v, val) in self.vars.vars().iter().zip(values) {
            if let (Role::Input(kind), Value::Real(x)) = (v.role, val) {
                model.set_input(kind, *x);
            }
        }
        if let Some(note) = model.build_note() {
            self.info(note);
        }
        let mut sim = Simulation::new(model, SolverConfig::from_params(&params), self.start_time)?;
        if initialize {
            for &(vr, order, value) in &self.pending_derivatives {
                if let Role::Input(kind) = self.vars.vars()[vr as usize].role {
                    sim.set_input_derivative(kind, order, value)?;
                }
            }
            if let Some(report) = sim.initialize()? {
                self.info(report);
            }
        }
        Ok(sim)
    }

    /// Parameter and input values (the part of `values` a simulation is built from).
    pub(super) fn build_inputs(&self) -> Vec<Value> {
        self.vars
            .vars()
            .iter()
            .zip(&self.values)
            .map(|(v, val)| match v.causality {
                Causality::Output => Value::Real(0.0),
                _ => *val,
            })
            .collect()
    }

    /// Builds the model from the current parameters and inputs, solves the static equilibrium
    /// if asked, and refreshes the outputs.
    fn build(&mut self) -> Result<(), String> {
        let values = self.build_inputs();
        let sim = self.new_simulation(&values, true)?;
        self.sim = Some(sim);
        self.built_with = Some(values);
        self.dirty = false;
        self.refresh_outputs();
        Ok(())
    }

    pub(super) fn ensure_built(&mut self) -> Result<(), Status> {
        if self.sim.is_none() || self.dirty {
            self.sim = None;
            self.built_with = None;
            if let Err(e) = self.build() {
                return Err(self.error(format!("initialization failed: {e}")));
            }
        }
        Ok(())
    }

    /// Marks the outputs with direct feedthrough from input `vr` (after it was set) for
    /// recomputation.
    fn refresh_feedthrough(&mut self, vr: u32) {
        if self.sim.is_some() {
            for (v, stale) in self.vars.vars().iter().zip(self.stale.iter_mut()) {
                if matches!(v.role, Role::Output(_)) && v.depends_on.contains(&vr) {
                    *stale = true;
                }
            }
        }
    }

    /// Marks every output for recomputation (after the simulation changed). Nothing is
    /// computed here: [`Self::fresh`] computes an output when it is read, so an importer
    /// that reads one force does not pay for, say, a stiffness output's condensation.
    pub(super) fn refresh_outputs(&mut self) {
        if self.sim.is_some() {
            for (v, stale) in self.vars.vars().iter().zip(self.stale.iter_mut()) {
                *stale = matches!(v.role, Role::Output(_));
            }
        }
    }

    /// Brings the stored value of variable `vr` up to date if it is a stale output.
    pub(super) fn fresh(&mut self, vr: u32) {
        let i = vr as usize;
        if self.stale[i] {
            if let (Some(sim), Role::Output(kind)) = (&self.sim, self.vars.vars()[i].role) {
                self.values[i] = Value::Real(sim.output(kind));
            }
            self.stale[i] = false;
        }
    }

    /// Brings every output whose derivative the importer has asked for up to date.
    pub(super) fn fresh_wanted(&mut self) {
        for i in 0..self.values.len() {
            if self.wanted[i] {
                self.fresh(i as u32);
            }
        }
    }

    /// fmi2ExitInitializationMode: parameters are checked, the model built and, with
    /// `solver.static_equilibrium`, brought into static equilibrium; outputs are valid after.
    pub fn exit_initialization_mode(&mut self) -> Status {
        self.trace(|| "fmi2ExitInitializationMode()".into());
        if let Err(s) = self.check(Call::ExitInitializationMode) {
            return s;
        }
        if let Err(s) = self.ensure_built() {
            return s;
        }
        self.last_successful_time = self.start_time;
        self.state = State::StepComplete;
        Status::Ok
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Status {
        if let Err(s) = self.check(Call::Terminate) {
            return s;
        }
        self.state = State::Terminated;
        if let Some(stats) = self.sim.as_ref().map(|s| s.stats()) {
            self.info(format!(
                "solver statistics: {} steps, {} rejected, {} Newton iterations, {} factorizations",
                stats.steps, stats.rejected, stats.newton.iterations, stats.newton.factorizations
            ));
        }
        Status::Ok
    }

    /// fmi2Reset: back to the state right after instantiation.
    pub fn reset(&mut self) -> Status {
        if let Err(s) = self.check(Call::Reset) {
            return s;
        }
        self.values = self
            .vars
            .vars()
            .iter()
            .map(|v| v.start.unwrap_or(Value::Real(0.0)))
            .collect();
        self.filter = LogFilter::new(self.logging_on_at_start);
        self.state = State::Instantiated;
        self.start_time = 0.0;
        self.sim = None;
        self.built_with = None;
        self.dirty = true;
        self.pending_derivatives.clear();
        self.previous_outputs = None;
        self.stale.fill(false);
        self.wanted.fill(false);
        self.last_successful_time = 0.0;
        self.terminated = false;
        self.last_step_status = Status::Ok;
        Status::Ok
    }

    fn variable(&mut self, call: Call, vr: u32, ty: VarType) -> Result<Variable, Status> {
        match self.vars.get(vr) {
            None => Err(self.error(format!(
                "{}: unknown value reference {vr} (this FMU has {} variables)",
                call.name(),
                self.vars.vars().len()
            ))),
            Some(v) if v.ty != ty => {
                let msg = format!(
                    "{}: value reference {vr} ({}) is a {:?} variable, not {:?}",
                    call.name(),
                    v.name,
                    v.ty,
                    ty
                );
                Err(self.error(msg))
            }
            Some(v) => Ok(v.clone()),
        }
    }

    /// fmi2GetReal / Integer / Boolean: reads values into `out`.
    pub fn get(
        &mut self,
        call: Call,
        ty: VarType,
        vrs: &[u32],
        out: &mut dyn FnMut(usize, Value),
    ) -> Status {
        self.trace(|| format!("{}({vrs:?})", call.name()));
        if let Err(s) = self.check(call) {
            return s;
        }
        let mut needs_outputs = false;
        for &vr in vrs {
            match self.variable(call, vr, ty) {
                Ok(v) => needs_outputs |= v.causality == Causality::Output,
                Err(s) => return s,
            }
        }
        if needs_outputs
            && self.state == State::InitializationMode
            && let Err(s) = self.ensure_built()
        {
            return s;
        }
        for (i, &vr) in vrs.iter().enumerate() {
            self.fresh(vr);
            out(i, self.values[vr as usize]);
        }
        Status::Ok
    }

    /// fmi2SetReal / Integer / Boolean.
    pub fn set(&mut self, call: Call, vrs: &[u32], values: &[Value]) -> Status {
        self.trace(|| format!("{}({vrs:?}, {values:?})", call.name()));
        if let Err(s) = self.check(call) {
            return s;
        }
        for (&vr, &val) in vrs.iter().zip(values) {
            let v = match self.variable(call, vr, val.ty()) {
                Ok(v) => v,
                Err(s) => return s,
            };
            if let Value::Real(x) = val
                && !x.is_finite()
            {
                return self.error(format!(
                    "{}: {} = {x} is not a finite number",
                    call.name(),
                    v.name
                ));
            }
            let allowed = match (self.state, v.causality) {
                (_, Causality::Output) => false,
                (State::Instantiated | State::InitializationMode, _) => true,
                (State::StepComplete, Causality::Input) => true,
                (State::StepComplete, Causality::Parameter) => {
                    v.variability == Variability::Tunable
                }
                _ => false,
            };
            if !allowed {
                let why = match v.causality {
                    Causality::Output => "it is an output".to_string(),
                    Causality::Parameter => format!(
                        "it is a fixed parameter: set it before fmi2ExitInitializationMode (state is {})",
                        self.state.name()
                    ),
                    Causality::Input => format!("not in state {}", self.state.name()),
                };
                return self.error(format!("{}: cannot set {}: {why}", call.name(), v.name));
            }
            let old = self.values[vr as usize];
            if v.causality == Causality::Input
                && self.state == State::StepComplete
                && matches!((old, val), (Value::Real(a), Value::Real(b)) if a.to_bits() == b.to_bits())
            {
                // the same value again (importers resend inputs every step): nothing changes
                continue;
            }
            self.values[vr as usize] = val;
            if v.causality == Causality::Input {
                // a new value clears the derivatives set for the old one
                self.pending_derivatives.retain(|(r, _, _)| *r != vr);
            }
            if self.state == State::StepComplete {
                if let Err(s) = self.apply_running(&v, val, old) {
                    return s;
                }
                if v.causality == Causality::Input {
                    self.refresh_feedthrough(vr);
                }
            } else {
                self.dirty = true;
            }
        }
        Status::Ok
    }

    /// Applies an input or tunable parameter to a running simulation.
    fn apply_running(&mut self, v: &Variable, val: Value, old: Value) -> Result<(), Status> {
        match (v.role, val) {
            (Role::Input(kind), Value::Real(x)) => {
                if let Some(sim) = self.sim.as_mut() {
                    sim.set_input(kind, x);
                }
                Ok(())
            }
            (Role::Parameter(_), _) => {
                let params = self.param_values();
                if let Err(e) = self.scene.validate_params(&params) {
                    self.values[v.vr as usize] = old;
                    return Err(self.error(e));
                }
                let cfg = SolverConfig::from_params(&params);
                if let Some(sim) = self.sim.as_mut() {
                    sim.set_tunables(&cfg);
                }
                debug_assert!(
                    self.scene
                        .params
                        .iter()
                        .any(|p| p.name == v.name && p.variability == ParamVariability::Tunable)
                );
                self.info(format!("tunable parameter {} set to {:?}", v.name, val));
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// fmi2DoStep: advances from `t` by `h`. Returns Discard (and enters stepFailed, with
    /// fmi2Terminated true and the state at the last successful time) when the step cannot be
    /// completed.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        self.trace(|| format!("fmi2DoStep({t:?}, {h:?})"));
        if let Err(s) = self.check(Call::DoStep) {
            return s;
        }
        if !h.is_finite() || h <= 0.0 || !t.is_finite() {
            return self.error(format!(
                "fmi2DoStep: communicationStepSize must be a finite number > 0 (got {h}) at a finite currentCommunicationPoint (got {t})"
            ));
        }
        let Some(sim) = self.sim.as_mut() else {
            return self.error("fmi2DoStep: no simulation (initialization did not complete)");
        };
        let now = sim.time();
        if (t - now).abs() > 1e-9 * now.abs().max(h).max(1e-3) {
            let msg = format!(
                "fmi2DoStep: currentCommunicationPoint = {t} s but the FMU is at t = {now} s"
            );
            return self.error(msg);
        }
        let max_step = sim.config().max_step;
        if h / max_step > MAX_SUBSTEPS {
            let msg = format!(
                "fmi2DoStep: a communication step of {h} s needs more than {MAX_SUBSTEPS:e} internal steps of solver.max_step = {max_step} s; use shorter communication steps or a larger solver.max_step"
            );
            return self.error(msg);
        }
        self.fresh_wanted();
        match self.previous_outputs.as_mut() {
            Some((tp, vals)) => {
                *tp = now;
                vals.copy_from_slice(&self.values);
            }
            None => self.previous_outputs = Some((now, self.values.clone())),
        }
        if let Some((_, vals)) = self.previous_outputs.as_mut() {
            for (val, &stale) in vals.iter_mut().zip(&self.stale) {
                if stale {
                    *val = Value::Real(f64::NAN);
                }
            }
        }
        let Some(sim) = self.sim.as_mut() else {
            return Status::Error;
        };
        let result = sim.advance(t + h);
        self.refresh_outputs();
        match result {
            Ok(()) => {
                self.last_successful_time = t + h;
                self.last_step_status = Status::Ok;
                Status::Ok
            }
            Err(e) => {
                self.last_successful_time = e.reached;
                self.terminated = true;
                self.last_step_status = Status::Discard;
                self.state = State::StepFailed;
                self.log(
                    Status::Discard,
                    status_category(Status::Discard),
                    &format!(
                        "fmi2DoStep from t = {t} s by {h} s: {}; the state is kept at the last successful time {} s (fmi2LastSuccessfulTime) and the unit terminates (fmi2Terminated = true)",
                        e.message, e.reached
                    ),
                );
                Status::Discard
            }
        }
    }

    /// fmi2CancelStep (no asynchronous steps: always an error).
    pub fn cancel_step(&mut self) -> Status {
        if let Err(s) = self.check(Call::CancelStep) {
            return s;
        }
        self.error("fmi2CancelStep: flexfmu never runs steps asynchronously")
    }

    fn status_check(&mut self, call: Call) -> Result<(), Status> {
        self.check(call)
    }

    fn not_available(&mut self, call: Call, kind: StatusKind) -> Status {
        self.log(
            Status::Discard,
            status_category(Status::Discard),
            &format!(
                "{}: status {kind:?} is not available from this slave",
                call.name()
            ),
        );
        Status::Discard
    }

    /// fmi2GetStatus.
    pub fn get_status(&mut self, kind: StatusKind) -> Result<Status, Status> {
        self.status_check(Call::GetStatus)?;
        Err(self.not_available(Call::GetStatus, kind))
    }

    /// fmi2GetRealStatus.
    pub fn get_real_status(&mut self, kind: StatusKind) -> Result<f64, Status> {
        self.status_check(Call::GetRealStatus)?;
        match kind {
            StatusKind::LastSuccessfulTime => Ok(self.last_successful_time),
            k => Err(self.not_available(Call::GetRealStatus, k)),
        }
    }

    /// fmi2GetIntegerStatus.
    pub fn get_integer_status(&mut self, kind: StatusKind) -> Result<i32, Status> {
        self.status_check(Call::GetIntegerStatus)?;
        Err(self.not_available(Call::GetIntegerStatus, kind))
    }

    /// fmi2GetBooleanStatus.
    pub fn get_boolean_status(&mut self, kind: StatusKind) -> Result<bool, Status> {
        self.status_check(Call::GetBooleanStatus)?;
        match kind {
            StatusKind::Terminated => Ok(self.terminated),
            k => Err(self.not_available(Call::GetBooleanStatus, k)),
        }
    }

    /// fmi2GetStringStatus.
    pub fn get_string_status(
        &mut self,
        kind: StatusKind,
    ) -> Result<&'static std::ffi::CStr, Status> {
        self.status_check(Call::GetStringStatus)?;
        Err(self.not_available(Call::GetStringStatus, kind))
    }

    /// fmi2GetString / fmi2SetString: there are no String variables.
    pub fn no_strings(&mut self, call: Call, vrs: &[u32]) -> Status {
        if let Err(s) = self.check(call) {
            return s;
        }
        match vrs.first() {
            None => Status::Ok,
            Some(&vr) => match self.vars.get(vr) {
                Some(v) => {
                    let msg = format!(
                        "{}: {} (value reference {vr}) is {:?}, not a String",
                        call.name(),
                        v.name,
                        v.ty
                    );
                    self.error(msg)
                }
                None => self.error(format!(
                    "{}: unknown value reference {vr} (this FMU has no String variables)",
                    call.name()
                )),
            },
        }
    }

    /// The capability flags of this FMU.
    pub fn capabilities(&self) -> crate::model_description::Capabilities {
        crate::model_description::Capabilities::ALL
    }

    /// A capability this FMU does not have (yet): error with a clear message.
    pub fn unsupported(&mut self, call: Call, flag: &str) -> Status {
        if let Err(s) = self.check(call) {
            return s;
        }
        self.error(format!(
            "{}: not supported by this FMU ({flag} = false in modelDescription.xml)",
            call.name()
        ))
    }

    /// Status of the last doStep.
    pub fn last_step_status(&self) -> Status {
        self.last_step_status
    }

    /// Current simulation time [s], if the simulation exists.
    pub fn time(&self) -> Option<f64> {
        self.sim.as_ref().map(|s| s.time())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_uris() {
        assert_eq!(
            resource_dir_from_uri("file:///tmp/a%20b/resources").unwrap(),
            PathBuf::from("/tmp/a b/resources")
        );
        assert_eq!(
            resource_dir_from_uri("file://localhost/x/y").unwrap(),
            PathBuf::from("/x/y")
        );
        assert_eq!(
            resource_dir_from_uri("file:/x/y/").unwrap(),
            PathBuf::from("/x/y/")
        );
        assert_eq!(
            resource_dir_from_uri("/plain/path").unwrap(),
            PathBuf::from("/plain/path")
        );
        assert!(resource_dir_from_uri("file://server/share").is_err());
        assert!(resource_dir_from_uri("http://x/y").is_err());
    }
}
