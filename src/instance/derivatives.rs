//! Derivatives at a communication point: directional derivatives of outputs with respect to
//! inputs (`fmi2GetDirectionalDerivative`), input derivatives for extrapolation inside a step
//! (`fmi2SetRealInputDerivatives`) and output time derivatives
//! (`fmi2GetRealOutputDerivatives`).
//!
//! In Step Mode the directional derivative is the partial derivative of the output function
//! with the states frozen (FMI 2.0 section 2.1.9 and 4.1): analytic from the model's linearized
//! equations where the model provides it (e.g. the tangent stiffness at a motion port), else a
//! central difference of the output function. In Initialization Mode the unknowns depend on
//! the knowns (inputs and parameters) through the whole initialization, including the static
//! solve; there the derivative is a central difference through the initialization.

use super::core::Instance;
use crate::fmi2::state_machine::{Call, State};
use crate::logging::Status;
use crate::variables::{Causality, Role, Value, VarType};

use crate::solver::simulation::FD_REL;

impl Instance {
    fn real_output(&mut self, call: Call, vr: u32) -> Result<usize, Status> {
        match self.vars.get(vr).map(|v| (v.ty, v.role)) {
            Some((VarType::Real, Role::Output(k))) => Ok(k),
            Some(_) => {
                let name = self
                    .vars
                    .get(vr)
                    .map(|v| v.name.clone())
                    .unwrap_or_default();
                Err(self.error(format!(
                    "{}: {name} (value reference {vr}) is not a Real output",
                    call.name()
                )))
            }
            None => Err(self.error(format!("{}: unknown value reference {vr}", call.name()))),
        }
    }

    /// fmi2GetDirectionalDerivative: `dv_unknown = (∂unknowns/∂knowns) dv_known`.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Status {
        let call = Call::GetDirectionalDerivative;
        if let Err(s) = self.check(call) {
            return s;
        }
        let mut outs = Vec::with_capacity(unknowns.len());
        for &vr in unknowns {
            match self.real_output(call, vr) {
                Ok(k) => outs.push(k),
                Err(s) => return s,
            }
        }
        let init = self.state == State::InitializationMode;
        for (&vr, &dv) in knowns.iter().zip(dv_known) {
            let ok = match self.vars.get(vr) {
                Some(v) => {
                    v.ty == VarType::Real
                        && (v.causality == Causality::Input
                            || (init && v.causality == Causality::Parameter))
                }
                None => false,
            };
            if !ok {
                return self.error(format!(
                    "{}: value reference {vr} is not a Real input{}",
                    call.name(),
                    if init { " or parameter" } else { "" }
                ));
            }
            if !dv.is_finite() {
                return self.error(format!("{}: seed {dv} is not finite", call.name()));
            }
        }
        let result = if init {
            self.directional_in_initialization(unknowns, knowns, dv_known)
        } else {
            self.directional_at_communication_point(unknowns, knowns, dv_known)
        };
        match result {
            Ok(d) => {
                dv_unknown.copy_from_slice(&d);
                Status::Ok
            }
            Err(e) => self.error(format!("{}: {e}", call.name())),
        }
    }

    fn directional_at_communication_point(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
    ) -> Result<Vec<f64>, String> {
        let mut out = vec![0.0; unknowns.len()];
        for (&kvr, &dv) in knowns.iter().zip(dv_known) {
            if dv == 0.0 {
                continue;
            }
            let Role::Input(input) = self.vars.vars()[kvr as usize].role else {
                unreachable!("checked");
            };
            let u = match self.values[kvr as usize] {
                Value::Real(x) => x,
                _ => unreachable!("checked"),
            };
            for (i, &uvr) in unknowns.iter().enumerate() {
                let var = &self.vars.vars()[uvr as usize];
                // ModelStructure: no direct feedthrough, no partial derivative.
                if !var.depends_on.contains(&kvr) {
                    continue;
                }
                let Role::Output(output) = var.role else {
                    unreachable!("checked");
                };
                let sim = self.sim.as_mut().ok_or("no simulation")?;
                let d = sim.output_input_partial(output, input, u)?;
                out[i] += d * dv;
            }
        }
        Ok(out)
    }

    /// Initialization Mode: inputs through the linearized static equilibrium (or directly, if
    /// there is none); parameters by central differences through the initialization.
    fn directional_in_initialization(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
    ) -> Result<Vec<f64>, String> {
        let (mut inputs, mut params) = (Vec::new(), Vec::new());
        for (&vr, &dv) in knowns.iter().zip(dv_known) {
            match (self.vars.vars()[vr as usize].role, self.values[vr as usize]) {
                (Role::Input(k), Value::Real(u)) => inputs.push((k, u, dv)),
                _ => params.push((vr, dv)),
            }
        }
        let mut out = vec![0.0; unknowns.len()];
        if inputs.iter().any(|(_, _, d)| *d != 0.0) {
            if self.ensure_built().is_err() {
                return Err("the initialization fails at the current values".into());
            }
            let kinds: Vec<_> = unknowns
                .iter()
                .map(|&vr| match self.vars.vars()[vr as usize].role {
                    Role::Output(k) => k,
                    _ => unreachable!("checked"),
                })
                .collect();
            let sim = self.sim.as_mut().ok_or("no simulation")?;
            let d = sim.linearized_output_response(&inputs, &kinds)?;
            out.iter_mut().zip(d).for_each(|(o, d)| *o += d);
        }
        if params.iter().any(|(_, d)| *d != 0.0) {
            let (k, d): (Vec<u32>, Vec<f64>) = params.into_iter().unzip();
            let dp = self.directional_through_initialization(unknowns, &k, &d)?;
            out.iter_mut().zip(dp).for_each(|(o, d)| *o += d);
        }
        Ok(out)
    }

    /// Central difference along the seed through the whole initialization (parameters).
    fn directional_through_initialization(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
    ) -> Result<Vec<f64>, String> {
        // One central difference along the seed direction; the step grows until the response
        // stands clear of round-off (inputs such as a zero load have no scale of their own).
        let mut h = f64::INFINITY;
        for (&vr, &dv) in knowns.iter().zip(dv_known) {
            if dv != 0.0 {
                let u = match self.values[vr as usize] {
                    Value::Real(x) => x,
                    _ => 0.0,
                };
                h = h.min(FD_REL * u.abs().max(1e-3) / dv.abs());
            }
        }
        if !h.is_finite() {
            return Ok(vec![0.0; unknowns.len()]);
        }
        let base = self.build_inputs();
        let mut eval = |h: f64| -> Result<Vec<f64>, String> {
            let mut values = base.clone();
            for (&vr, &dv) in knowns.iter().zip(dv_known) {
                if let Value::Real(x) = &mut values[vr as usize] {
                    *x += h * dv;
                }
            }
            let sim = self.new_simulation(&values, true)?;
            Ok(unknowns
                .iter()
                .map(|&vr| match self.vars.vars()[vr as usize].role {
                    Role::Output(k) => sim.output(k),
                    _ => unreachable!("checked"),
                })
                .collect())
        };
        let y0 = eval(0.0)?;
        let size = y0.iter().fold(1e-9f64, |m, y| m.max(y.abs()));
        for _ in 0..8 {
            let yp = eval(h)?;
            let ym = eval(-h)?;
            let change = yp
                .iter()
                .zip(&ym)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            if change >= 1e-7 * size {
                return Ok(yp
                    .iter()
                    .zip(&ym)
                    .map(|(a, b)| (a - b) / (2.0 * h))
                    .collect());
            }
            h *= 100.0;
        }
        // The unknowns do not respond to the knowns in this direction.
        Ok(vec![0.0; unknowns.len()])
    }

    /// fmi2SetRealInputDerivatives: derivatives (order 1 or 2) of inputs at the current
    /// communication point; the inputs are extrapolated as polynomials inside the next step.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Status {
        let call = Call::SetRealInputDerivatives;
        if let Err(s) = self.check(call) {
            return s;
        }
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let kind = match self.vars.get(vr).map(|v| (v.ty, v.role)) {
                Some((VarType::Real, Role::Input(k))) => k,
                _ => {
                    return self.error(format!(
                        "{}: value reference {vr} is not a Real input",
                        call.name()
                    ));
                }
            };
            if !(1..=2).contains(&order) {
                return self.error(format!(
                    "{}: derivative order {order} not supported (1 or 2)",
                    call.name()
                ));
            }
            if !value.is_finite() {
                return self.error(format!("{}: value {value} is not finite", call.name()));
            }
            let order = order as usize;
            if self.state == State::StepComplete {
                if let Some(sim) = self.sim.as_mut()
                    && let Err(e) = sim.set_input_derivative(kind, order, value)
                {
                    return self.error(format!("{}: {e}", call.name()));
                }
            } else {
                self.pending_derivatives
                    .retain(|(r, o, _)| !(*r == vr && *o == order));
                self.pending_derivatives.push((vr, order, value));
                self.dirty = true;
            }
        }
        Status::Ok
    }

    /// fmi2GetRealOutputDerivatives (first order): from the model where it provides the rate,
    /// else the backward difference over the last communication step.
    pub fn get_real_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        out: &mut [f64],
    ) -> Status {
        let call = Call::GetRealOutputDerivatives;
        if let Err(s) = self.check(call) {
            return s;
        }
        for (i, (&vr, &order)) in vrs.iter().zip(orders).enumerate() {
            let kind = match self.real_output(call, vr) {
                Ok(k) => k,
                Err(s) => return s,
            };
            if order != 1 {
                return self.error(format!(
                    "{}: order {order} requested, maxOutputDerivativeOrder is 1",
                    call.name()
                ));
            }
            self.wanted[vr as usize] = true;
            self.fresh(vr);
            let Some(sim) = self.sim.as_ref() else {
                return self.error(format!("{}: no simulation", call.name()));
            };
            // by differences: 0 where there is no previous value (the first step, or an
            // output first read after the last step)
            out[i] = match sim.output_derivative(kind) {
                Some(d) => d,
                None => match (&self.previous_outputs, self.values[vr as usize]) {
                    (Some((tp, prev)), Value::Real(y)) if sim.time() > *tp => {
                        match prev[vr as usize] {
                            Value::Real(yp) if yp.is_finite() => (y - yp) / (sim.time() - tp),
                            _ => 0.0,
                        }
                    }
                    _ => 0.0,
                },
            };
        }
        Status::Ok
    }
}
