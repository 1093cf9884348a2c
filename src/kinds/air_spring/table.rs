//! Level 3 of the air spring (`model.fidelity = 3`): the bellows as a table of its
//! characteristic at a reference gauge pressure `p_ref` — effective area `A(z)`, bag volume
//! `V(z)` and volume compliance `C(z) = ∂V/∂p_g` over the plate height `z` — with the gas law of
//! [`crate::gas`] on top (issue 11, item 4; `shared/reference/air-spring-physics.md` §0.3: the
//! table must carry `V(z, p)`, not only `A_e(z)`, or the stiffness misses the bag's swelling).
//!
//! Per step the gauge pressure solves `p_g = p_gas(V(z) + C(z)(p_g − p_ref))` (scalar Newton
//! with the gas's `dp/dV`), and `F = p_g A(z)`. The derivatives are analytic:
//! `dp_g/dz = P' (V' + C'(p_g − p_ref)) / (1 − P' C)` with `P' = dp/dV` of the gas,
//! `dF/dz = A dp_g/dz + p_g A'`. Between the table's heights the curves are cubic Hermite
//! interpolants with centred-difference slopes (C¹); beyond its ends they continue linearly.
//!
//! [`generate`] builds the table from the membrane level (constant-pressure equilibria at
//! every height and at `p_ref (1 ± 1 %)` for the compliance): `flexfmu air-spring-table`.

use super::model::AirSpring;
use super::scene::{Input, Output, io, names::*};
use super::{AirSpringScene, PlateInput, TableSection};
use crate::gas::{Gas, GasLaw, GasParams, Reservoir};
use crate::integrators::DynState;
use crate::linalg::CscPattern;
use crate::model::{JacobianCoeffs, MechanicalSystem, Model, ModelError};
use crate::scene::{ParamValues, Scene};
use crate::snapshot::{StateReader, StateWriter};

/// A C¹ cubic Hermite interpolant with centred-difference slopes, linear beyond its ends.
#[derive(Clone, Debug)]
pub struct Hermite {
    x: Vec<f64>,
    y: Vec<f64>,
    d: Vec<f64>,
}

impl Hermite {
    /// Through the points `(x_i, y_i)`, `x` strictly increasing, at least two points.
    pub fn new(x: &[f64], y: &[f64]) -> Self {
        let n = x.len();
        let sec = |i: usize| (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
        let d = (0..n)
            .map(|i| {
                if i == 0 {
                    sec(0)
                } else if i == n - 1 {
                    sec(n - 2)
                } else {
                    (y[i + 1] - y[i - 1]) / (x[i + 1] - x[i - 1])
                }
            })
            .collect();
        Self {
            x: x.to_vec(),
            y: y.to_vec(),
            d,
        }
    }

    /// Value and slope at `t`.
    pub fn eval(&self, t: f64) -> (f64, f64) {
        let n = self.x.len();
        if t <= self.x[0] {
            return (self.y[0] + self.d[0] * (t - self.x[0]), self.d[0]);
        }
        if t >= self.x[n - 1] {
            return (
                self.y[n - 1] + self.d[n - 1] * (t - self.x[n - 1]),
                self.d[n - 1],
            );
        }
        let i = self.x.partition_point(|&xi| xi <= t).clamp(1, n - 1) - 1;
        let h = self.x[i + 1] - self.x[i];
        let s = (t - self.x[i]) / h;
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (
            2.0 * s3 - 3.0 * s2 + 1.0,
            s3 - 2.0 * s2 + s,
            -2.0 * s3 + 3.0 * s2,
            s3 - s2,
        );
        let (d00, d10, d01, d11) = (
            6.0 * s2 - 6.0 * s,
            3.0 * s2 - 4.0 * s + 1.0,
            -6.0 * s2 + 6.0 * s,
            3.0 * s2 - 2.0 * s,
        );
        let (y0, y1, m0, m1) = (self.y[i], self.y[i + 1], self.d[i], self.d[i + 1]);
        (
            h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1,
            (d00 * y0 + d01 * y1) / h + d10 * m0 + d11 * m1,
        )
    }
}

/// The gas parameters of a scene's parameter values (every level).
pub(super) fn gas_params(p: &ParamValues, scene: &AirSpringScene) -> GasParams {
    let law = match p.integer(GAS_MODEL) {
        2 => GasLaw::Energy {
            heat_transfer: p.real(GAS_HEAT_TRANSFER),
        },
        _ => GasLaw::Polytropic {
            n: p.real(GAS_POLYTROPIC_EXPONENT),
        },
    };
    let reservoir = scene.reservoir.as_ref().map(|_| Reservoir {
        volume: p.real(RESERVOIR_VOLUME),
        orifice_diameter: p.real(ORIFICE_DIAMETER),
        cd: p.real(ORIFICE_CD),
        pipe_length: p.real(PIPE_LENGTH),
        pipe_diameter: p.real(PIPE_DIAMETER),
    });
    GasParams {
        law,
        ambient_pressure: p.real(AMBIENT_PRESSURE),
        ambient_temperature: p.real(AMBIENT_TEMPERATURE),
        inner_volume: p.real(GAS_INNER_VOLUME),
        reservoir,
    }
}

/// A gas error with the parameters the gas follows from (the component does not know the
/// scene's names).
pub(super) fn gas_error(e: impl std::fmt::Display, p: &GasParams) -> String {
    let mut keys = vec![
        GAS_PRESSURE_DESIGN,
        SPRING_DESIGN_HEIGHT,
        GAS_MODEL,
        GAS_POLYTROPIC_EXPONENT,
        GAS_HEAT_TRANSFER,
        GAS_INNER_VOLUME,
        AMBIENT_PRESSURE,
        AMBIENT_TEMPERATURE,
    ];
    if p.reservoir.is_some() {
        keys.extend([
            RESERVOIR_VOLUME,
            ORIFICE_DIAMETER,
            ORIFICE_CD,
            PIPE_LENGTH,
            PIPE_DIAMETER,
        ]);
    }
    format!("{e} (the gas follows from {})", keys.join(", "))
}

/// The outputs that only the gas decides (every level): pressures, volume, temperature, mass,
/// the reservoir's pressure and the gas energy relative to the ambient (`U + p_a (V − V_charge)`,
/// `v_charge` [m³] the bag volume at the charge); `None` for the others.
pub(super) fn gas_output(o: Output, gas: &Gas, v_charge: f64) -> Option<f64> {
    let e = gas.committed();
    Some(match o {
        Output::Pressure => e.p_abs,
        Output::PressureGauge => e.p_gauge,
        Output::Volume => e.volume,
        Output::Temperature => e.temperature,
        Output::Mass => e.mass,
        Output::ReservoirPressure => e.reservoir_pressure,
        Output::GasEnergy => {
            e.internal_energy + gas.params().ambient_pressure * (e.volume - v_charge)
        }
        _ => return None,
    })
}

/// The state of the table model at one height and pressure.
#[derive(Clone, Copy, Debug, Default)]
struct Point {
    /// Gauge pressure [Pa].
    p_g: f64,
    /// Membrane (table) volume [m³].
    v: f64,
    /// Force on the plate [N].
    force: f64,
    /// `dF/dz` [N/m].
    dfdz: f64,
    /// `dV/dz` [m²].
    dvdz: f64,
}

/// The air spring as an effective-area table with the gas law.
pub struct AirSpringTable {
    area: Hermite,
    volume: Hermite,
    compliance: Hermite,
    p_ref: f64,
    gas: Gas,
    inputs: Vec<Input>,
    outputs: Vec<Output>,
    plate: PlateInput,
    initialized: bool,
    /// The state at the end of the step the last residual evaluated: `(t, height, point)`.
    trial: Option<(f64, f64, Point)>,
    t: f64,
    height: f64,
    point: Point,
    plate_work: f64,
    /// Bag volume at the charge [m³].
    v_charge: f64,
    pattern: CscPattern,
}

impl std::fmt::Debug for AirSpringTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AirSpringTable")
            .field("t", &self.t)
            .finish()
    }
}

impl AirSpringTable {
    /// The model of a table scene, charged at the design state.
    pub fn build(scene: &AirSpringScene, p: &ParamValues) -> Result<Self, String> {
        let t: &TableSection = scene
            .table
            .as_ref()
            .ok_or("table: model.fidelity = 3 needs a [table]")?;
        let hd = p.real(SPRING_DESIGN_HEIGHT);
        let pd = p.real(GAS_PRESSURE_DESIGN);
        let mut m = Self {
            area: Hermite::new(&t.height, &t.effective_area),
            volume: Hermite::new(&t.height, &t.volume),
            compliance: Hermite::new(&t.height, &t.volume_compliance),
            p_ref: t.reference_pressure,
            gas: Gas::new(gas_params(p, scene), pd, 1.0)
                .map_err(|e| gas_error(e, &gas_params(p, scene)))?,
            inputs: vec![],
            outputs: vec![],
            plate: PlateInput::at_rest(hd),
            initialized: false,
            trial: None,
            t: 0.0,
            height: hd,
            point: Point::default(),
            plate_work: 0.0,
            v_charge: 0.0,
            pattern: CscPattern::from_entries(0, vec![]),
        };
        let io = io(scene);
        m.inputs = io.inputs;
        m.outputs = io.outputs;
        let vd = m.table_volume(hd, pd);
        if vd.is_nan() || vd <= 0.0 {
            return Err(format!(
                "table.volume, table.volume_compliance, table.reference_pressure: the bag volume at {SPRING_DESIGN_HEIGHT} = {hd} m and {GAS_PRESSURE_DESIGN} = {pd} Pa is {vd} m3"
            ));
        }
        m.gas
            .charge(pd, vd)
            .map_err(|e| gas_error(e, m.gas.params()))?;
        m.v_charge = m.gas.committed().volume;
        let mut point = m
            .solve(hd, None)
            .map_err(|e| format!("table at the design state: {e}"))?;
        (point.dfdz, point.dvdz) = m.derivatives(hd, point.p_g, m.gas.committed().dp_dv);
        m.point = point;
        Ok(m)
    }

    /// `V(z) + C(z)(p_g − p_ref)` [m³].
    fn table_volume(&self, z: f64, p_g: f64) -> f64 {
        self.volume.eval(z).0 + self.compliance.eval(z).0 * (p_g - self.p_ref)
    }

    /// The gas pressure [Pa absolute] and `dp/dV` at the membrane volume `v`: after a step of
    /// `dt` from the committed gas, or at rest (`None`).
    fn gas_at(&self, dt: Option<f64>, v: f64) -> Result<(f64, f64), String> {
        match dt {
            Some(dt) => self.gas.pressure(dt, v).map_err(|e| e.to_string()),
            None => self.gas.static_pressure(v).map_err(|e| e.to_string()),
        }
    }

    /// Pressure, volume and force at height `z` after a step of `dt` (or at rest); the
    /// derivatives are left 0: they are instantaneous and come from the committed gas
    /// ([`Self::derivatives`] in `accept`).
    fn solve(&self, z: f64, dt: Option<f64>) -> Result<Point, String> {
        let pa = self.gas.params().ambient_pressure;
        // the table at z once: only the pressure changes in the iteration
        let c = self.compliance.eval(z).0;
        let vol = self.volume.eval(z).0;
        let table_volume = |p_g: f64| vol + c * (p_g - self.p_ref);
        let mut p_g = self.gas.committed().p_gauge;
        let mut ok = false;
        for _ in 0..50 {
            let v = table_volume(p_g);
            let (p, dpdv) = self.gas_at(dt, v)?;
            let f = p_g - (p - pa);
            let step = f / (1.0 - dpdv * c);
            p_g -= step;
            if !p_g.is_finite() {
                break;
            }
            // the last step is below round-off: p_g and dp/dV are those of the last volume
            if step.abs() <= 1e-12 * (p_g.abs() + pa) {
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(format!("no gas pressure at height {z} m"));
        }
        let (a, _) = self.area.eval(z);
        Ok(Point {
            p_g,
            v: table_volume(p_g),
            force: p_g * a,
            dfdz: 0.0,
            dvdz: 0.0,
        })
    }

    /// `dF/dz` [N/m] and `dV/dz` [m²] at height `z` and gauge pressure `p_g` for the gas's
    /// `dp/dV` [Pa/m³]: `dp_g/dz = P' (V' + C'(p_g − p_ref)) / (1 − P' C)`.
    fn derivatives(&self, z: f64, p_g: f64, dpdv: f64) -> (f64, f64) {
        let (c, dc) = self.compliance.eval(z);
        let (_, dvol) = self.volume.eval(z);
        let (a, da) = self.area.eval(z);
        let dvz = dvol + dc * (p_g - self.p_ref);
        let dp = dpdv * dvz / (1.0 - dpdv * c);
        (a * dp + p_g * da, dvz + c * dp)
    }

    /// The plate height and the gas state at `t` (solved once per time and kept as the
    /// step's trial).
    fn trial_at(&mut self, t: f64) -> Result<(f64, Point), ModelError> {
        let z = self.plate.motion(t).0;
        if let Some((tt, zz, p)) = self.trial
            && tt == t
            && zz == z
        {
            return Ok((z, p));
        }
        let dt = self.initialized.then(|| (t - self.t).max(0.0));
        let p = self.solve(z, dt).map_err(|_| ModelError::NonFinite)?;
        self.trial = Some((t, z, p));
        Ok((z, p))
    }

    fn value(&self, o: Output) -> f64 {
        if let Some(v) = gas_output(o, &self.gas, self.v_charge) {
            return v;
        }
        let e = self.gas.committed();
        match o {
            Output::TopFz => {
                let z = self.plate.motion(self.t).0;
                self.point.force + self.point.dfdz * (z - self.height)
            }
            Output::Height => self.height,
            Output::EffectiveArea => self.area.eval(self.height).0,
            Output::VolumetricArea => self.point.dvdz,
            Output::Stiffness => -self.point.dfdz,
            Output::PlateWork => self.plate_work,
            Output::Dissipated => e.heat_out + e.loss_work,
            // gas outputs are above; the membrane's do not exist at this level
            _ => f64::NAN,
        }
    }
}

impl MechanicalSystem for AirSpringTable {
    fn n_free(&self) -> usize {
        0
    }

    /// No coordinates: every integrator steps only the gas.
    fn set_quasi_static(&mut self, _on: bool) -> bool {
        true
    }

    fn pattern(&self) -> &CscPattern {
        &self.pattern
    }

    fn scales(&self) -> &[f64] {
        &[]
    }

    /// No mechanical coordinates (the table has no inertia and no shape): the gas is solved
    /// for the plate at `t` here, so that a height where it has no state (a table extrapolated
    /// to a non-positive volume, a non-converged pressure) fails the step, which is then cut
    /// or discarded with the state rolled back; [`Model::accept`] commits this trial.
    fn residual(
        &mut self,
        t: f64,
        _q: &[f64],
        _v: &[f64],
        _a: &[f64],
        _load_factor: f64,
        _r: &mut [f64],
        _jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        self.trial_at(t).map(|_| ())
    }

    fn midpoint_residual(
        &mut self,
        _t_a: f64,
        _t_b: f64,
        _q_a: &[f64],
        _q_b: &[f64],
        _v: &[f64],
        _a: &[f64],
        _r: &mut [f64],
        _jac: Option<(JacobianCoeffs, &mut [f64])>,
    ) -> Result<(), ModelError> {
        Ok(())
    }
}

impl Model for AirSpringTable {
    /// No wall: the cylinder of the effective radius `√(A_e/π)` at the current height, from
    /// the piston base to the top plate.
    fn sketch(&self) -> crate::model::Sketch {
        let mut s = crate::model::Sketch::new(
            "no mesh: effective-area, volume and compliance tables over the height",
        );
        let h = self.height;
        let r = (self.area.eval(h).0 / std::f64::consts::PI).max(0.0).sqrt();
        let p = |x: f64, z: f64| nalgebra::Vector3::new(x, 0.0, z);
        s.line([p(r, 0.0), p(r, h)]);
        s.line([p(-r, 0.0), p(-r, h)]);
        s.line([p(-1.15 * r, h), p(1.15 * r, h)]);
        s.line([p(-1.15 * r, 0.0), p(1.15 * r, 0.0)]);
        s
    }

    fn set_input(&mut self, input: usize, value: f64) {
        self.plate.set(self.inputs[input], value, self.t);
    }

    fn set_input_derivative(
        &mut self,
        input: usize,
        order: usize,
        value: f64,
    ) -> Result<(), String> {
        self.plate.set_derivative(self.inputs[input], order, value);
        Ok(())
    }

    fn output(&self, output: usize) -> f64 {
        self.value(self.outputs[output])
    }

    fn output_derivative(&self, output: usize) -> Option<f64> {
        match self.outputs[output] {
            Output::Height => Some(self.plate.motion(self.t).1),
            Output::TopFz => Some(self.point.dfdz * self.plate.motion(self.t).1),
            _ => None,
        }
    }

    /// The table has no coordinates, hence no accelerations to restart when an input jumps
    /// (a restart would only solve the gas once more at the step's start).
    fn input_restarts_accelerations(&self, _input: usize) -> bool {
        false
    }

    fn output_input_derivative(&mut self, output: usize, input: usize) -> Option<f64> {
        match (self.outputs[output], self.inputs[input]) {
            (Output::TopFz, Input::TopZ) => Some(self.point.dfdz),
            (Output::TopFz, Input::TopVz) => {
                Some(self.point.dfdz * self.plate.velocity_lever(self.t))
            }
            _ => None,
        }
    }

    /// Steps the gas to the new plate height (at rest for the first state): the trial the
    /// residual of the step solved.
    fn accept(&mut self, state: &mut DynState) {
        let dt = (state.t - self.t).max(0.0);
        let Ok((z, point)) = self.trial_at(state.t) else {
            // the residual at this time succeeded, so its trial exists; nothing to commit
            return;
        };
        let committed = if self.initialized {
            self.gas.commit(dt, point.v).map(|_| ())
        } else {
            self.gas.set_static(point.v)
        };
        if committed.is_err() {
            return;
        }
        // The outputs' derivatives are instantaneous, as levels 1 and 2 report them: the gas
        // compressed at its committed state without time for heat or flow (the step's `dp/dV`
        // above carries the heat exchange and the orifice flow of a step of `dt`, and the rest
        // state's is isothermal for the energy law and includes the reservoir).
        let mut point = point;
        (point.dfdz, point.dvdz) = self.derivatives(z, point.p_g, self.gas.committed().dp_dv);
        if self.initialized {
            self.plate_work -= 0.5 * (self.point.force + point.force) * (z - self.height);
        }
        self.point = point;
        self.height = z;
        self.t = state.t;
        self.initialized = true;
    }

    fn free_state(&self, _q: &mut [f64], _v: &mut [f64]) {}

    fn save(&self, w: &mut StateWriter) -> Result<(), String> {
        w.f64(self.t);
        self.plate.save(w);
        w.bool(self.initialized);
        for x in [
            self.height,
            self.plate_work,
            self.point.p_g,
            self.point.v,
            self.point.force,
            self.point.dfdz,
            self.point.dvdz,
        ] {
            w.f64(x);
        }
        self.gas.save(w);
        Ok(())
    }

    fn restore(&mut self, r: &mut StateReader) -> Result<(), String> {
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        self.t = r.f64().map_err(e)?;
        self.plate = PlateInput::restore(r).map_err(e)?;
        self.trial = None;
        self.initialized = r.bool().map_err(e)?;
        for x in [
            &mut self.height,
            &mut self.plate_work,
            &mut self.point.p_g,
            &mut self.point.v,
            &mut self.point.force,
            &mut self.point.dfdz,
            &mut self.point.dvdz,
        ] {
            *x = r.f64().map_err(e)?;
        }
        self.gas.restore(r).map_err(e)?;
        Ok(())
    }
}

/// A level-3 scene generated from the membrane scene `text`: the characteristic at the
/// gauge pressure `pressure` [Pa] (default `gas.pressure_design`) at the heights `heights`
/// [m] (increasing), computed with the scene's default parameters and `elements` elements
/// along the sleeve (default: the scene's); `name` is the new FMU's
/// model name. `progress(done, total)` is called after every height. The new scene is the old
/// one with `model.fidelity = 3` and the `[table]`; its membrane tables stay as the record of
/// where the table came from.
pub fn generate(
    text: &str,
    heights: &[f64],
    pressure: Option<f64>,
    elements: Option<usize>,
    name: &str,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<String, String> {
    let scene = Scene::from_toml(text).map_err(|e| e.0)?;
    let tables: &AirSpringScene = scene
        .tables()
        .ok_or("air-spring-table: the scene is not of kind \"air_spring\"")?;
    if super::scene::is_table(tables) {
        return Err("air-spring-table: the scene is already a table (model.fidelity = 3)".into());
    }
    if heights.len() < 4 || heights.windows(2).any(|w| w[1] <= w[0] || w[1].is_nan()) {
        return Err("air-spring-table: give at least 4 increasing heights".into());
    }
    let mut params = ParamValues::defaults(&scene.params);
    if let Some(n) = elements {
        params.set(
            MESH_N_MERIDIONAL,
            crate::variables::Value::Integer(i32::try_from(n).map_err(|e| e.to_string())?),
        );
        scene
            .validate_params(&params)
            .map_err(|e| format!("air-spring-table --elements: {e}"))?;
    }
    let mut model = AirSpring::build(tables, &params)?;
    let p_ref = pressure.unwrap_or(params.real(GAS_PRESSURE_DESIGN));
    let inner = params.real(GAS_INNER_VOLUME);
    let (mut area, mut volume, mut compliance) = (vec![], vec![], vec![]);
    let dp = 0.01 * p_ref;
    for (k, &h) in heights.iter().enumerate() {
        let (_, v_minus) = model.equilibrium_at(h, p_ref - dp)?;
        let (_, v_plus) = model.equilibrium_at(h, p_ref + dp)?;
        let (f, v) = model.equilibrium_at(h, p_ref)?;
        area.push(f / p_ref);
        volume.push(v - inner);
        compliance.push((v_plus - v_minus) / (2.0 * dp));
        progress(k + 1, heights.len());
    }
    let mut out = tables.clone();
    out.model.fidelity = 3;
    out.fmu.model_name = name.to_string();
    out.fmu.description = format!(
        "{} - level 3: effective-area table from the membrane level at {p_ref} Pa",
        tables.fmu.description
    );
    out.table = Some(TableSection {
        source: format!(
            "flexfmu air-spring-table: membrane level ({} elements) of model {}, constant-pressure equilibria at {p_ref} Pa and +/- 1 % for the compliance",
            params.integer(MESH_N_MERIDIONAL),
            tables.fmu.model_name
        ),
        reference_pressure: p_ref,
        height: heights.to_vec(),
        effective_area: area,
        volume,
        volume_compliance: compliance,
    });
    let body = toml::to_string(&out).map_err(|e| e.to_string())?;
    Ok(format!(
        "# Air spring, level 3 (effective-area table with the gas law), generated by\n# `flexfmu air-spring-table` from the membrane scene {}: do not edit the table by hand.\n\n{body}",
        tables.fmu.model_name
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interpolant reproduces a cubic's values at the nodes, is C¹, and its slope is the
    /// derivative of its value (finite differences).
    #[test]
    fn hermite_is_c1_and_consistent() {
        let x: Vec<f64> = (0..8)
            .map(|i| 0.1 * i as f64 + 0.01 * (i * i) as f64)
            .collect();
        let y: Vec<f64> = x.iter().map(|t| t * t * t - t).collect();
        let h = Hermite::new(&x, &y);
        for i in 0..x.len() {
            assert!((h.eval(x[i]).0 - y[i]).abs() < 1e-14);
        }
        for k in 0..200 {
            let t = -0.05 + 1.5 * k as f64 / 200.0;
            let e = 1e-7;
            let fd = (h.eval(t + e).0 - h.eval(t - e).0) / (2.0 * e);
            assert!((fd - h.eval(t).1).abs() < 1e-6, "{t}");
        }
        // slope continuous at an inner node
        let d1 = h.eval(x[3] - 1e-12).1;
        let d2 = h.eval(x[3] + 1e-12).1;
        assert!((d1 - d2).abs() < 1e-9);
    }
}
