//! FMU state: `fmi2GetFMUstate` / `fmi2SetFMUstate` and their serialized form. A state holds
//! everything the instance needs to continue bit for bit: the FMI machine state, all variable
//! values (parameters, inputs with their derivatives, cached outputs), time bookkeeping, and
//! the simulation (integrator state, model state: coordinates, velocities, inputs, history).
//!
//! Format: a 16-byte magic, the format version, the scene GUID, the payload length and a
//! 64-bit FNV-1a checksum of the payload, then the payload. A truncated, corrupted or foreign
//! buffer is rejected with a message.

use super::core::Instance;
use crate::fmi2::state_machine::{Call, State};
use crate::guid::fnv1a_64;
use crate::logging::Status;
use crate::snapshot::{StateReader, StateWriter};
use crate::solver::simulation::SolverConfig;
use crate::variables::{Value, VarType};

/// Version of the serialized state format; states of other versions are rejected (2: the
/// belt drive keeps its reference length, the axisymmetric air spring its friction history).
pub const STATE_FORMAT_VERSION: u64 = 2;

const MAGIC: &[u8; 16] = b"flexfmu-state\0\0\0";

fn state_code(s: State) -> u64 {
    match s {
        State::Instantiated => 0,
        State::InitializationMode => 1,
        State::StepComplete => 2,
        State::StepInProgress => 3,
        State::StepFailed => 4,
        State::StepCanceled => 5,
        State::Terminated => 6,
        State::Error => 7,
        State::Fatal => 8,
    }
}

fn state_of(code: u64) -> Option<State> {
    Some(match code {
        0 => State::Instantiated,
        1 => State::InitializationMode,
        2 => State::StepComplete,
        4 => State::StepFailed,
        6 => State::Terminated,
        7 => State::Error,
        _ => return None,
    })
}

fn status_code(s: Status) -> u64 {
    match s {
        Status::Ok => 0,
        Status::Warning => 1,
        Status::Discard => 2,
        Status::Error => 3,
        Status::Fatal => 4,
    }
}

fn status_of(code: u64) -> Option<Status> {
    Some(match code {
        0 => Status::Ok,
        1 => Status::Warning,
        2 => Status::Discard,
        3 => Status::Error,
        4 => Status::Fatal,
        _ => return None,
    })
}

fn write_values(w: &mut StateWriter, values: &[Value]) {
    w.u64(values.len() as u64);
    for v in values {
        match *v {
            Value::Real(x) => {
                w.u64(0);
                w.f64(x);
            }
            Value::Integer(i) => {
                w.u64(1);
                w.u64(i as i64 as u64);
            }
            Value::Boolean(b) => {
                w.u64(2);
                w.u64(u64::from(b));
            }
        }
    }
}

/// Values whose count and types must match the variable table.
fn read_values(r: &mut StateReader, types: &[VarType]) -> Result<Vec<Value>, String> {
    let n = r.u64().map_err(|e| e.to_string())? as usize;
    if n != types.len() {
        return Err(format!(
            "{n} values where the FMU has {} variables",
            types.len()
        ));
    }
    let mut out = Vec::with_capacity(n);
    for ty in types {
        let tag = r.u64().map_err(|e| e.to_string())?;
        let data = r.u64().map_err(|e| e.to_string())?;
        out.push(match (tag, ty) {
            (0, VarType::Real) => Value::Real(f64::from_bits(data)),
            (1, VarType::Integer) => Value::Integer(data as i64 as i32),
            (2, VarType::Boolean) if data <= 1 => Value::Boolean(data == 1),
            _ => {
                return Err(format!(
                    "value of type tag {tag} does not fit a {ty:?} variable"
                ));
            }
        });
    }
    Ok(out)
}

impl Instance {
    /// The complete state as bytes (fmi2GetFMUstate, fmi2SerializeFMUstate).
    pub fn save_fmu_state(&mut self, call: Call) -> Result<Vec<u8>, Status> {
        self.trace(|| format!("{}()", call.name()));
        self.check(call)?;
        self.fresh_wanted();
        let mut p = StateWriter::new();
        p.u64(state_code(self.state));
        write_values(&mut p, &self.values);
        p.f64(self.start_time);
        p.bool(self.dirty);
        p.f64(self.last_successful_time);
        p.bool(self.terminated);
        p.u64(status_code(self.last_step_status));
        p.u64(self.pending_derivatives.len() as u64);
        for &(vr, order, value) in &self.pending_derivatives {
            p.u64(u64::from(vr));
            p.u64(order as u64);
            p.f64(value);
        }
        match &self.previous_outputs {
            Some((t, vals)) => {
                p.bool(true);
                p.f64(*t);
                write_values(&mut p, vals);
            }
            None => p.bool(false),
        }
        match (self.sim.as_mut(), &self.built_with) {
            (Some(sim), Some(built)) => {
                p.bool(true);
                write_values(&mut p, built);
                if let Err(e) = sim.save(&mut p) {
                    return Err(self.error(format!("{}: {e}", call.name())));
                }
            }
            _ => p.bool(false),
        }
        let payload = p.into_bytes();
        let mut w = StateWriter::new();
        let mut out = MAGIC.to_vec();
        w.u64(STATE_FORMAT_VERSION);
        w.str(&self.guid);
        w.u64(payload.len() as u64);
        w.u64(fnv1a_64(&payload));
        out.extend_from_slice(w.bytes());
        out.extend_from_slice(&payload);
        Ok(out)
    }

    /// The payload of `bytes` if they are a state of this FMU (magic, version, GUID, length,
    /// checksum), else a message.
    fn state_payload<'a>(&self, bytes: &'a [u8]) -> Result<&'a [u8], String> {
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err("not a flexfmu FMU state (bad magic)".into());
        }
        let mut r = StateReader::new(&bytes[MAGIC.len()..]);
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let version = r.u64().map_err(e)?;
        if version != STATE_FORMAT_VERSION {
            return Err(format!(
                "state format version {version}, this FMU reads version {STATE_FORMAT_VERSION}"
            ));
        }
        let guid = r.str().map_err(e)?;
        if guid != self.guid {
            return Err(format!(
                "state of another FMU (GUID {guid}, this FMU is {})",
                self.guid
            ));
        }
        let len = r.u64().map_err(e)? as usize;
        let sum = r.u64().map_err(e)?;
        let header = MAGIC.len() + 8 + 8 + guid.len() + 8 + 8;
        let end = header.saturating_add(len);
        if bytes.len() != end {
            let what = if bytes.len() < end {
                "truncated"
            } else {
                "trailing bytes after the"
            };
            return Err(format!(
                "{what} state: {} bytes, its header announces {end}",
                bytes.len()
            ));
        }
        let payload = &bytes[header..end];
        if fnv1a_64(payload) != sum {
            return Err("state checksum mismatch (corrupted data)".into());
        }
        Ok(payload)
    }

    /// Checks serialized bytes before they become an FMU state (fmi2DeSerializeFMUstate).
    pub fn check_fmu_state(&mut self, call: Call, bytes: &[u8]) -> Result<(), Status> {
        self.check(call)?;
        match self.state_payload(bytes) {
            Ok(_) => Ok(()),
            Err(e) => Err(self.error(format!("{}: {e}", call.name()))),
        }
    }

    /// fmi2SetFMUstate: restores a state saved by [`Instance::save_fmu_state`] (of this or
    /// another instance of the same FMU). All or nothing: on error the instance is unchanged
    /// apart from entering the Error state.
    pub fn restore_fmu_state(&mut self, bytes: &[u8]) -> Status {
        if let Err(s) = self.check(Call::SetFmuState) {
            return s;
        }
        match self.try_restore(bytes) {
            Ok(()) => Status::Ok,
            Err(e) => self.error(format!("fmi2SetFMUstate: {e}")),
        }
    }

    fn try_restore(&mut self, bytes: &[u8]) -> Result<(), String> {
        let payload = self.state_payload(bytes)?;
        let mut r = StateReader::new(payload);
        let e = |e: crate::snapshot::SnapshotError| e.to_string();
        let types: Vec<VarType> = self.vars.vars().iter().map(|v| v.ty).collect();
        let machine = state_of(r.u64().map_err(e)?).ok_or("invalid machine state")?;
        let values = read_values(&mut r, &types)?;
        let start_time = r.f64().map_err(e)?;
        let dirty = r.bool().map_err(e)?;
        let last_successful_time = r.f64().map_err(e)?;
        let terminated = r.bool().map_err(e)?;
        let last_step_status = status_of(r.u64().map_err(e)?).ok_or("invalid status")?;
        let n_pending = r.u64().map_err(e)? as usize;
        if n_pending > types.len() * 2 {
            return Err("too many input derivatives".into());
        }
        let mut pending = Vec::with_capacity(n_pending);
        for _ in 0..n_pending {
            let vr = r.u64().map_err(e)?;
            let order = r.u64().map_err(e)?;
            let value = r.f64().map_err(e)?;
            if vr as usize >= types.len() || !(1..=2).contains(&order) {
                return Err("invalid input derivative".into());
            }
            pending.push((vr as u32, order as usize, value));
        }
        let previous_outputs = if r.bool().map_err(e)? {
            let t = r.f64().map_err(e)?;
            Some((t, read_values(&mut r, &types)?))
        } else {
            None
        };
        let mut backup: Option<StateWriter> = None;
        let sim = if r.bool().map_err(e)? {
            let built = read_values(&mut r, &types)?;
            let saved_start = self.start_time;
            self.start_time = start_time;
            let same = self.sim.is_some() && self.built_with.as_ref() == Some(&built);
            let result = if same {
                // Restore into the existing simulation; keep a backup for all-or-nothing.
                let sim = self.sim.as_mut().expect("checked");
                let mut b = StateWriter::new();
                sim.save(&mut b)?;
                let res = sim.restore(&mut r).map(|_| None);
                backup = Some(b);
                res
            } else {
                self.new_simulation(&built, false).and_then(|mut sim| {
                    sim.restore(&mut r)?;
                    Ok(Some((sim, built)))
                })
            };
            self.start_time = saved_start;
            Some(result)
        } else {
            None
        };
        let sim = match (sim, r.finished()) {
            (Some(Ok(s)), true) => Some(s),
            (None, true) => None,
            (res, _) => {
                if let (Some(b), Some(sim)) = (backup, self.sim.as_mut()) {
                    sim.restore(&mut StateReader::new(b.bytes()))?;
                }
                return Err(match res {
                    Some(Err(err)) => err,
                    _ => "trailing data after the state".into(),
                });
            }
        };
        // Commit.
        match sim {
            Some(Some((s, built))) => {
                self.sim = Some(s);
                self.built_with = Some(built);
            }
            Some(None) => {}
            None => {
                self.sim = None;
                self.built_with = None;
            }
        }
        self.state = machine;
        self.values = values;
        self.start_time = start_time;
        self.dirty = dirty;
        self.last_successful_time = last_successful_time;
        self.terminated = terminated;
        self.last_step_status = last_step_status;
        self.pending_derivatives = pending;
        self.previous_outputs = previous_outputs;
        // outputs follow from the restored simulation when they are read
        self.stale.fill(false);
        self.refresh_outputs();
        // Tunable solver settings follow the restored parameter values.
        let params = self.param_values();
        if self.scene.validate_params(&params).is_ok() {
            let cfg = SolverConfig::from_params(&params);
            if let Some(sim) = self.sim.as_mut() {
                sim.set_tunables(&cfg);
            }
        }
        Ok(())
    }
}
