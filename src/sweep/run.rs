//! Running the points of a sweep: worker threads, each with one [`Instance`] reused through
//! `reset` (fmi2Reset), called in the order an FMI importer calls the C API.

use super::spec::{Reduction, Sweep};
use crate::fmi2::state_machine::Call;
use crate::instance::Instance;
use crate::logging::Status;
use crate::scene::Scene;
use crate::variables::{Causality, Value, VarType};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The result of one point.
#[derive(Clone, Debug, PartialEq)]
pub struct PointResult {
    /// Point index in the sweep.
    pub point: usize,
    /// The reductions, output by output in the order of [`Sweep::header`]; NaN when the run
    /// failed.
    pub values: Vec<f64>,
    /// `ok`, or why the run stopped.
    pub status: String,
    /// Time series kept for this point: per communication point the time and the series
    /// outputs (empty when the point is not in `series.points`).
    pub series: Vec<Vec<f64>>,
}

/// Running statistics of one output over a run (see [`Reduction`] for the definitions).
#[derive(Clone, Debug)]
pub struct Reducer {
    last: f64,
    max: f64,
    min: f64,
    max_abs: f64,
    sum: f64,
    sum_sq: f64,
    count: usize,
}

impl Default for Reducer {
    fn default() -> Self {
        Self {
            last: f64::NAN,
            max: f64::NAN,
            min: f64::NAN,
            max_abs: f64::NAN,
            sum: 0.0,
            sum_sq: 0.0,
            count: 0,
        }
    }
}

impl Reducer {
    /// Adds the value at the next communication point.
    pub fn push(&mut self, y: f64) {
        if self.count == 0 {
            (self.max, self.min, self.max_abs) = (y, y, y.abs());
        } else {
            if y > self.max {
                self.max = y;
            }
            if y < self.min {
                self.min = y;
            }
            if y.abs() > self.max_abs {
                self.max_abs = y.abs();
            }
        }
        self.last = y;
        self.sum += y;
        self.sum_sq += y * y;
        self.count += 1;
    }

    /// The value of a reduction.
    pub fn get(&self, r: Reduction) -> f64 {
        let n = self.count as f64;
        match r {
            Reduction::Final => self.last,
            Reduction::Max => self.max,
            Reduction::Min => self.min,
            Reduction::MaxAbs => self.max_abs,
            Reduction::Mean => self.sum / n,
            Reduction::Rms => (self.sum_sq / n).sqrt(),
        }
    }
}

/// One worker's instance and the last error message its logger received.
pub struct Runner<'a> {
    sweep: &'a Sweep,
    inst: Instance,
    last_error: Rc<RefCell<String>>,
    used: bool,
    /// Value references read every communication point: the reduced outputs, then the
    /// series outputs.
    read: Vec<u32>,
}

impl<'a> Runner<'a> {
    /// A runner with its own instance of the sweep's scene.
    pub fn new(sweep: &'a Sweep) -> Result<Self, String> {
        let scene = Scene::from_toml(&sweep.scene_text).map_err(|e| e.0)?;
        let last_error: Rc<RefCell<String>> = Rc::default();
        let sink = last_error.clone();
        let inst = Instance::from_scene(
            "sweep",
            scene,
            false,
            Box::new(move |s, _, m| {
                if s >= Status::Warning {
                    *sink.borrow_mut() = m.to_string();
                }
            }),
        );
        let mut read: Vec<u32> = sweep.outputs.iter().map(|o| o.vr).collect();
        if let Some(series) = &sweep.series {
            read.extend(series.outputs.iter().map(|(_, vr)| *vr));
        }
        Ok(Self {
            sweep,
            inst,
            last_error,
            used: false,
            read,
        })
    }

    fn ok(&self, what: &str, s: Status) -> Result<(), String> {
        // fmpy, the Python front end's importer, goes on after a Warning: so does the sweep
        if s <= Status::Warning {
            Ok(())
        } else {
            Err(format!(
                "{what}: {s:?}: {}",
                self.last_error.borrow().replace([',', '\n', '\r'], ";")
            ))
        }
    }

    /// Runs point `p`: fmi2Reset (after the first), fmi2SetupExperiment, the settings, fmi2EnterInitializationMode,
    /// the CSV inputs at the start time, fmi2ExitInitializationMode, then per step the CSV
    /// inputs at `t_k` and fmi2DoStep(`t_k`, `step`), reading the outputs after
    /// initialization and after every step; fmi2Terminate.
    pub fn run(&mut self, p: usize) -> PointResult {
        let sw = self.sweep;
        let keep_series = sw.series.as_ref().is_some_and(|s| s.points.contains(&p));
        let mut reducers = vec![Reducer::default(); sw.outputs.len()];
        let mut series = Vec::new();
        let status = match self.simulate(p, &mut reducers, keep_series.then_some(&mut series)) {
            Ok(()) => "ok".to_string(),
            Err(e) => {
                reducers = vec![Reducer::default(); sw.outputs.len()];
                e
            }
        };
        let values = sw
            .outputs
            .iter()
            .zip(&reducers)
            .flat_map(|(o, r)| o.reductions.iter().map(|&red| r.get(red)))
            .collect();
        PointResult {
            point: p,
            values,
            status,
            series,
        }
    }

    fn simulate(
        &mut self,
        p: usize,
        reducers: &mut [Reducer],
        mut series: Option<&mut Vec<Vec<f64>>>,
    ) -> Result<(), String> {
        let sw = self.sweep;
        if self.used {
            let s = self.inst.reset();
            self.ok("fmi2Reset", s)?;
        }
        self.used = true;
        let s = self
            .inst
            .setup_experiment(None, sw.start_time, Some(sw.stop_time));
        self.ok("fmi2SetupExperiment", s)?;
        for (setting, &value) in sw.settings.iter().zip(&sw.points[p]) {
            let call = match setting.ty {
                VarType::Real => Call::SetReal,
                VarType::Integer => Call::SetInteger,
                VarType::Boolean => Call::SetBoolean,
            };
            let s = self.inst.set(call, &[setting.vr], &[value]);
            self.ok(&format!("setting {}", setting.name), s)?;
            debug_assert!(setting.causality != Causality::Output);
        }
        let s = self.inst.enter_initialization_mode();
        self.ok("fmi2EnterInitializationMode", s)?;
        self.set_inputs(sw.start_time)?;
        let s = self.inst.exit_initialization_mode();
        self.ok("fmi2ExitInitializationMode", s)?;
        self.record(sw.start_time, reducers, series.as_deref_mut())?;
        for k in 0..sw.steps {
            let t = sw.time(k);
            if k > 0 {
                self.set_inputs(t)?;
            }
            let s = self.inst.do_step(t, sw.step);
            self.ok(&format!("fmi2DoStep at t = {t} s"), s)?;
            self.record(sw.time(k + 1), reducers, series.as_deref_mut())?;
        }
        let s = self.inst.terminate();
        self.ok("fmi2Terminate", s)
    }

    fn set_inputs(&mut self, t: f64) -> Result<(), String> {
        let Some(table) = &self.sweep.inputs else {
            return Ok(());
        };
        let vrs: Vec<u32> = table.columns.iter().map(|c| c.1).collect();
        let vals: Vec<Value> = (0..vrs.len())
            .map(|c| Value::Real(table.value(c, t)))
            .collect();
        let s = self.inst.set(Call::SetReal, &vrs, &vals);
        self.ok(&format!("setting the inputs at t = {t} s"), s)
    }

    fn record(
        &mut self,
        t: f64,
        reducers: &mut [Reducer],
        series: Option<&mut Vec<Vec<f64>>>,
    ) -> Result<(), String> {
        let mut y = vec![0.0; self.read.len()];
        let s = self
            .inst
            .get(Call::GetReal, VarType::Real, &self.read, &mut |i, v| {
                if let Value::Real(x) = v {
                    y[i] = x;
                }
            });
        self.ok("fmi2GetReal", s)?;
        for (r, &v) in reducers.iter_mut().zip(&y) {
            r.push(v);
        }
        if let Some(series) = series {
            let mut row = vec![t];
            row.extend_from_slice(&y[reducers.len()..]);
            series.push(row);
        }
        Ok(())
    }
}

/// Runs the points `range` of `sweep` on `threads` worker threads (each one instance, reused),
/// calling `progress(done, total)` after every point. Results are in point order.
pub fn run_points(
    sweep: &Sweep,
    range: std::ops::Range<usize>,
    threads: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<PointResult>, String> {
    let total = range.len();
    let next = AtomicUsize::new(range.start);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<PointResult>> = Mutex::new(Vec::with_capacity(total));
    let failure: Mutex<Option<String>> = Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..threads.max(1).min(total.max(1)) {
            s.spawn(|| {
                let mut runner = match Runner::new(sweep) {
                    Ok(r) => r,
                    Err(e) => {
                        *failure.lock().expect("no panics hold the lock") = Some(e);
                        return;
                    }
                };
                loop {
                    let p = next.fetch_add(1, Ordering::SeqCst);
                    if p >= range.end {
                        break;
                    }
                    let r = runner.run(p);
                    results.lock().expect("no panics hold the lock").push(r);
                    progress(done.fetch_add(1, Ordering::SeqCst) + 1, total);
                }
            });
        }
    });
    if let Some(e) = failure.into_inner().expect("threads joined") {
        return Err(e);
    }
    let mut r = results.into_inner().expect("threads joined");
    r.sort_by_key(|p| p.point);
    Ok(r)
}
