//! Motion ports: coordinates of a body whose position and velocity the co-simulation master
//! prescribes (inputs), and the force the body exerts on the driver (outputs), with the
//! interface Jacobian that tells the master how that force changes with the prescribed motion.
//!
//! A port has up to [`MAX_PORT_COORDS`] **channels**, one per prescribed signal: two for a
//! planar point (x, y), three for a 3D point or a rigidly translated group of nodes (x, y, z).
//! A channel drives one or several full coordinates (its **members**): member `i` sits at
//! `x_i = X_i + (u − u_ref)`, `u` the channel's prescribed position, `u_ref` its reference value
//! and `X_i` the member's reference coordinate; a channel of one coordinate with
//! `u_ref = X_i` is that coordinate itself (`x_i = u`). The channel's reaction is the sum of
//! its members' residuals, and its rows of the interface Jacobian are the sums over its
//! members' rows and columns (the incidence matrix of the group). Inputs of a port are, in this
//! order, the position of every channel and then the velocity of every channel (planar:
//! x, y, vx, vy; 3D point: x, y, z, vx, vy, vz); its outputs are the force on the driver per
//! channel (fx, fy[, fz]).
//!
//! **Interface Jacobian** (after Sicklinger, Belsky, Engelmann, Elmqvist, Olsson, Wüchner,
//! Bletzinger: "Interface Jacobian-based Co-Simulation", IJNME 98, 2014): the change of the port
//! reactions after one Newmark step of size `h` when the prescribed port trajectory is shifted
//! by a constant displacement (the port's acceleration is given by the inputs, so it does not
//! change), with the interior responding:
//! `K_int = K_cc − S_cf S_ff⁻¹ K_fc`, `S = K_T + (4/h²) M` (`c` the port channels, `f` the
//! free coordinates; `K_cc = Bᵀ K B` with the 0/1 incidence `B` of members to channels). The
//! model supplies its rows and free–free matrix through [`PortHost`]; the condensation runs
//! once per communication point (when a motion input is set, or after a state restore), never
//! per internal step.

use std::collections::BTreeMap;

use crate::linalg::{LinearSolver, SolverKind};
use crate::model::MechanicalSystem;
use crate::model::inputs::{InputSignal, prescribed};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};

/// Most channels of one port: a 3D pose (three positions, three rotations).
pub const MAX_PORT_COORDS: usize = 6;

/// What a model provides to its [`Ports`]: all at its committed state.
pub trait PortHost: MechanicalSystem {
    /// Free index of full coordinate `full`, `None` if it is constrained (ports are).
    fn free_index(&self, full: usize) -> Option<usize>;

    /// Residual `M a + f_int − f_ext` [N] of the committed state at the full coordinates
    /// `coords` of one port (its members), into `out` (same length): the force the driver
    /// applies to the body to enforce the motion.
    fn port_residual(&self, coords: &[usize], out: &mut [f64]);

    /// Rows of `K_T + c_m M` (`c_m` [1/s²]) of the committed state at the full coordinates
    /// `coords` of one port (its members): `add(k, column, value)` for every entry of row
    /// `coords[k]` at full `column` (entries of the same column are summed by the caller, in
    /// call order).
    fn port_rows(&self, coords: &[usize], c_m: f64, add: &mut dyn FnMut(usize, usize, f64));

    /// Values of the free–free iteration matrix `K_T + c_m M` of the committed state in the
    /// model's pattern ([`MechanicalSystem::pattern`]), into `vals` (length `nnz`).
    fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]);
}

/// One channel of a port for [`Ports::grouped`]: the full coordinates it drives and its
/// reference value `u_ref` (the members follow `x_i = X_i + (u − u_ref)`).
#[derive(Clone, Debug)]
pub struct Channel {
    /// Full coordinate indices (members), at least one.
    pub members: Vec<usize>,
    /// Reference value of the prescribed position [m] (its start value).
    pub reference: f64,
}

/// The motion ports of a model.
#[derive(Debug, Default)]
pub struct Ports {
    /// Full coordinate indices of all members, channel after channel, port after port.
    members: Vec<usize>,
    /// Channel `k` has `members[member_offsets[k]..member_offsets[k + 1]]`.
    member_offsets: Vec<usize>,
    /// Channel of every member.
    member_channel: Vec<usize>,
    /// Reference coordinate `X_i` of every member [m].
    member_reference: Vec<f64>,
    /// `X_i − u_ref` of every member [m] (0 for a channel of one coordinate).
    member_offset: Vec<f64>,
    /// Channel of a member's full coordinate.
    channel_of: BTreeMap<usize, usize>,
    /// Port `p` has channels `offsets[p]..offsets[p + 1]`.
    offsets: Vec<usize>,
    /// Reference value `u_ref` of every channel (start of the static load ramp) [m].
    reference: Vec<f64>,
    /// Inputs per port: the position of each channel, then its velocity (so input signal
    /// `2 offsets[p] + component` is component `component` of port `p`).
    signals: Vec<InputSignal>,
    /// Committed time [s] and channel positions and velocities.
    t: f64,
    q: Vec<f64>,
    v: Vec<f64>,
    /// Keep ports at their committed positions (see `Model::hold_prescribed_motion`).
    hold: bool,
    interface: Interface,
}

impl Clone for Ports {
    fn clone(&self) -> Self {
        Self {
            members: self.members.clone(),
            member_offsets: self.member_offsets.clone(),
            member_channel: self.member_channel.clone(),
            member_reference: self.member_reference.clone(),
            member_offset: self.member_offset.clone(),
            channel_of: self.channel_of.clone(),
            offsets: self.offsets.clone(),
            reference: self.reference.clone(),
            signals: self.signals.clone(),
            t: self.t,
            q: self.q.clone(),
            v: self.v.clone(),
            hold: self.hold,
            interface: Interface {
                h: self.interface.h,
                matrix: self.interface.matrix.clone(),
                ..Interface::default()
            },
        }
    }
}

/// The condensed interface matrix and its work buffers.
#[derive(Debug, Default)]
struct Interface {
    /// Step size of the condensation [s] (the last communication step).
    h: f64,
    /// `K_int` (n × n over all port channels, row-major) at the committed state [N/m].
    matrix: Option<Vec<f64>>,
    solver: Option<LinearSolver>,
    /// Values of `S_ff`.
    vals: Vec<f64>,
    /// Rows of `S` at the port channels restricted to the free coordinates (n × n_free).
    s_rows: Vec<f64>,
    /// One column of `K_fc`, then `S_ff⁻¹ K_fc` (n_free).
    x: Vec<f64>,
}

impl Ports {
    /// Ports at the given full coordinates (one list per port, one coordinate per channel),
    /// starting at rest at the reference configuration `q0` (full vector) at time 0; `h` [s]
    /// is the first communication step size.
    /// At most [`MAX_PORT_COORDS`] coordinates per port.
    pub fn new(ports: &[Vec<usize>], q0: &[f64], h: f64) -> Self {
        let ports: Vec<Vec<Channel>> = ports
            .iter()
            .map(|p| {
                p.iter()
                    .map(|&i| Channel {
                        members: vec![i],
                        reference: q0[i],
                    })
                    .collect()
            })
            .collect();
        Self::grouped(&ports, q0, h)
    }

    /// Ports of channels that may drive several full coordinates each (a rigidly translated
    /// group of nodes), starting at rest at the channels' reference values; the members'
    /// reference coordinates are their values in `q0` (full vector); `h` [s] is the first
    /// communication step size. At most [`MAX_PORT_COORDS`] channels per port; a full
    /// coordinate belongs to one channel at most.
    pub fn grouped(ports: &[Vec<Channel>], q0: &[f64], h: f64) -> Self {
        assert!(
            ports.iter().all(|p| p.len() <= MAX_PORT_COORDS),
            "a port has at most {MAX_PORT_COORDS} channels"
        );
        let mut s = Self {
            offsets: vec![0],
            member_offsets: vec![0],
            interface: Interface {
                h,
                ..Interface::default()
            },
            ..Self::default()
        };
        for p in ports {
            for c in p {
                assert!(
                    !c.members.is_empty(),
                    "a channel drives a coordinate at least"
                );
                let k = s.reference.len();
                for &i in &c.members {
                    let before = s.channel_of.insert(i, k);
                    assert!(before.is_none(), "coordinate {i} is in two port channels");
                    s.members.push(i);
                    s.member_channel.push(k);
                    s.member_reference.push(q0[i]);
                    s.member_offset.push(q0[i] - c.reference);
                }
                s.member_offsets.push(s.members.len());
                s.reference.push(c.reference);
            }
            s.offsets.push(s.reference.len());
            s.signals
                .extend(p.iter().map(|c| InputSignal::constant(c.reference)));
            s.signals
                .extend(p.iter().map(|_| InputSignal::constant(0.0)));
        }
        s.q = s.reference.clone();
        s.v = vec![0.0; s.reference.len()];
        s
    }

    /// Number of ports.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there are no ports.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Full coordinate indices of port `port`: the members of its channels, channel after
    /// channel (for ports of one coordinate per channel: the channels' coordinates).
    pub fn coords(&self, port: usize) -> &[usize] {
        let (a, b) = (self.offsets[port], self.offsets[port + 1]);
        &self.members[self.member_offsets[a]..self.member_offsets[b]]
    }

    /// Full coordinate indices driven by channel `axis` of port `port`.
    pub fn channel_members(&self, port: usize, axis: usize) -> &[usize] {
        let k = self.offsets[port] + axis;
        &self.members[self.member_offsets[k]..self.member_offsets[k + 1]]
    }

    /// Number of channels of port `port`.
    pub fn n_channels(&self, port: usize) -> usize {
        self.offsets[port + 1] - self.offsets[port]
    }

    /// Committed position [m] of channel `axis` of port `port` (the prescribed position of the
    /// last accepted state).
    pub fn position(&self, port: usize, axis: usize) -> f64 {
        self.q[self.offsets[port] + axis]
    }

    /// The input signal of `component` (positions, then velocities) of port `port`.
    pub fn signal_mut(&mut self, port: usize, component: usize) -> &mut InputSignal {
        &mut self.signals[2 * self.offsets[port] + component]
    }

    /// Position and velocity signals of channel `k` (over all ports).
    fn signals_of(&self, k: usize) -> (&InputSignal, &InputSignal) {
        let p = self.port_of(k);
        let (off, d) = (self.offsets[p], self.offsets[p + 1] - self.offsets[p]);
        let base = 2 * off + (k - off);
        (&self.signals[base], &self.signals[base + d])
    }

    fn port_of(&self, k: usize) -> usize {
        self.offsets.partition_point(|&o| o <= k) - 1
    }

    /// Channel `k`'s prescribed position, velocity and acceleration at time `t` [s] (the
    /// committed position and velocity while held at the committed time).
    fn motion(&self, k: usize, t: f64) -> (f64, f64, f64) {
        let (pos, vel) = self.signals_of(k);
        let (mut p, mut pd, pdd) = prescribed(pos, vel, t);
        if self.hold && t == self.t {
            (p, pd) = (self.q[k], self.v[k]);
        }
        (p, pd, pdd)
    }

    /// Keeps ports at their committed positions while set (`Model::hold_prescribed_motion`).
    pub fn hold(&mut self, hold: bool) {
        self.hold = hold;
    }

    /// Records the committed state (full vectors) at time `t` [s]; call after
    /// [`Ports::apply`] in `Model::accept` and after a restore. Clears the interface matrix.
    ///
    /// A channel's committed position is read from its first member: the prescribed position
    /// itself when that member sits where [`Ports::apply`] puts it (bit for bit), else
    /// `x_i − (X_i − u_ref)`.
    pub fn commit(&mut self, t: f64, q: &[f64], v: &[f64]) {
        for k in 0..self.reference.len() {
            let m = self.member_offsets[k];
            let (i, o) = (self.members[m], self.member_offset[m]);
            let (p, _, _) = self.motion(k, t);
            self.q[k] = if q[i] == p + o { p } else { q[i] - o };
            self.v[k] = v[i];
        }
        self.t = t;
        self.interface.matrix = None;
    }

    /// Writes the prescribed motion at time `t` [s] into full position (and, if given,
    /// velocity and acceleration) vectors; in a static solve (`lambda` < 1) positions are
    /// ramped from the reference configuration.
    pub fn apply(
        &self,
        t: f64,
        lambda: f64,
        mut q: Option<&mut [f64]>,
        mut v: Option<&mut [f64]>,
        mut a: Option<&mut [f64]>,
    ) {
        for k in 0..self.reference.len() {
            let (p, pd, pdd) = self.motion(k, t);
            for m in self.member_offsets[k]..self.member_offsets[k + 1] {
                let i = self.members[m];
                if let Some(q) = q.as_deref_mut() {
                    // exactly `p + o` when fully applied (`p` for a channel of one
                    // coordinate: q0 + (p - q0) can differ from p in the last bit, and
                    // `force` relies on q = p at the committed state)
                    q[i] = if lambda == 1.0 {
                        p + self.member_offset[m]
                    } else {
                        self.member_reference[m] + lambda * (p - self.reference[k])
                    };
                }
                if let Some(v) = v.as_deref_mut() {
                    v[i] = pd;
                }
                if let Some(a) = a.as_deref_mut() {
                    a[i] = pdd;
                }
            }
        }
    }

    /// Writes the mean of the prescribed positions at `t_a` and `t_b` [s] into a full position
    /// vector (the configuration of the implicit midpoint rule).
    pub fn apply_mean(&self, t_a: f64, t_b: f64, q: &mut [f64]) {
        for k in 0..self.reference.len() {
            let (pa, pb) = (self.motion(k, t_a).0, self.motion(k, t_b).0);
            for m in self.member_offsets[k]..self.member_offsets[k + 1] {
                let o = self.member_offset[m];
                q[self.members[m]] = 0.5 * ((pa + o) + (pb + o));
            }
        }
    }

    /// Sets the step size of the condensation to the coming communication step.
    pub fn begin_communication_step(&mut self, t0: f64, t1: f64) {
        if t1 > t0 && (t1 - t0) != self.interface.h {
            self.interface.h = t1 - t0;
        }
    }

    /// Computes the interface Jacobian at the committed state unless it is current.
    pub fn update_interface<H: PortHost>(&mut self, host: &mut H) {
        if self.interface.matrix.is_none() && !self.is_empty() {
            let m = self.condense(host);
            self.interface.matrix = Some(m);
        }
    }

    /// Channel of row `r` of the rows of port `port` ([`PortHost::port_rows`] of
    /// [`Ports::coords`]).
    fn row_channel(&self, port: usize, r: usize) -> usize {
        self.member_channel[self.member_offsets[self.offsets[port]] + r]
    }

    /// `K_int = K_cc − S_cf S_ff⁻¹ K_fc` over the channels; if `S_ff` cannot be factorized,
    /// `K_cc` (the frozen-interior stiffness) is returned.
    fn condense<H: PortHost>(&mut self, host: &mut H) -> Vec<f64> {
        let n = self.reference.len();
        let n_free = host.n_free();
        let c_m = 4.0 / (self.interface.h * self.interface.h);
        // K_cc
        let mut k = vec![0.0; n * n];
        for p in 0..self.len() {
            host.port_rows(self.coords(p), 0.0, &mut |r, col, val| {
                if let Some(&j) = self.channel_of.get(&col) {
                    k[self.row_channel(p, r) * n + j] += val;
                }
            });
        }
        // S_ff
        let mut vals = std::mem::take(&mut self.interface.vals);
        vals.clear();
        vals.resize(host.pattern().nnz(), 0.0);
        host.free_matrix(c_m, &mut vals);
        let solver = match self.interface.solver.take() {
            Some(s) => Some(s),
            None => LinearSolver::new(host.pattern(), SolverKind::Auto).ok(),
        };
        if let Some(mut solver) = solver {
            if solver.factor(host.pattern(), &vals).is_ok() {
                // S rows (S is symmetric, so its rows at the ports give S_cf).
                let mut s_rows = std::mem::take(&mut self.interface.s_rows);
                s_rows.clear();
                s_rows.resize(n * n_free, 0.0);
                let mut x = std::mem::take(&mut self.interface.x);
                let hr: &H = host;
                for p in 0..self.len() {
                    hr.port_rows(self.coords(p), c_m, &mut |r, col, val| {
                        if let Some(f) = hr.free_index(col) {
                            s_rows[self.row_channel(p, r) * n_free + f] += val;
                        }
                    });
                }
                for j in 0..n {
                    // column j of K_fc = row j of K_cf (K_T is symmetric)
                    x.clear();
                    x.resize(n_free, 0.0);
                    let p = self.port_of(j);
                    hr.port_rows(self.coords(p), 0.0, &mut |r, col, val| {
                        if let (true, Some(f)) = (self.row_channel(p, r) == j, hr.free_index(col)) {
                            x[f] += val;
                        }
                    });
                    solver.solve_in_place(&mut x);
                    for i in 0..n {
                        k[i * n + j] -= s_rows[i * n_free..(i + 1) * n_free]
                            .iter()
                            .zip(&x)
                            .map(|(a, b)| a * b)
                            .sum::<f64>();
                    }
                }
                self.interface.s_rows = s_rows;
                self.interface.x = x;
            }
            self.interface.solver = Some(solver);
        }
        self.interface.vals = vals;
        k
    }

    /// Force [N] on the driver at port `port`, channel `axis`, with the current inputs: the
    /// committed reaction (from [`PortHost::port_residual`], summed over the channel's
    /// members), extrapolated with the interface Jacobian if the inputs moved a port since the
    /// last commit (then [`Ports::update_interface`] must have run, which setting a motion
    /// input does).
    pub fn force<H: PortHost>(&self, host: &H, port: usize, axis: usize) -> f64 {
        let coords = self.coords(port);
        let mut buf = [0.0; MAX_PORT_COORDS];
        let mut long = Vec::new();
        let r: &mut [f64] = if coords.len() <= MAX_PORT_COORDS {
            &mut buf[..coords.len()]
        } else {
            long.resize(coords.len(), 0.0);
            &mut long
        };
        host.port_residual(coords, r);
        let row = self.offsets[port] + axis;
        let reaction: f64 = r
            .iter()
            .enumerate()
            .filter(|&(m, _)| self.row_channel(port, m) == row)
            .map(|(_, x)| x)
            .sum();
        let n = self.reference.len();
        let mut extra = 0.0;
        for j in 0..n {
            let (pos, vel) = self.signals_of(j);
            let (p, _, _) = prescribed(pos, vel, self.t);
            let d = p - self.q[j];
            if d != 0.0 {
                let k = self
                    .interface
                    .matrix
                    .as_ref()
                    .expect("computed when an input moved a port");
                extra += k[row * n + j] * d;
            }
        }
        -(reaction + extra)
    }

    /// Time derivative [N/s] of the stiffness part of the force on the driver at `port`,
    /// `axis`: `−K_c v` at the committed state (inertia rates neglected); `v` full velocities.
    pub fn force_rate<H: PortHost>(&self, host: &H, port: usize, axis: usize, v: &[f64]) -> f64 {
        let row = self.offsets[port] + axis;
        let mut sum = 0.0;
        host.port_rows(self.coords(port), 0.0, &mut |r, col, val| {
            if self.row_channel(port, r) == row {
                sum += val * v[col];
            }
        });
        -sum
    }

    /// Partial derivative of the force on the driver at `port`, `axis` with respect to input
    /// `component` (positions, then velocities) of port `input_port`, at the committed state:
    /// `−K_int ∂p/∂input` with `∂p/∂input` 1 for a position and `τ = t − t_ref` [s] for a
    /// velocity (0 if the position carries its own derivatives). Runs
    /// [`Ports::update_interface`] first.
    pub fn force_input_derivative<H: PortHost>(
        &mut self,
        host: &mut H,
        port: usize,
        axis: usize,
        input_port: usize,
        component: usize,
    ) -> f64 {
        let off = self.offsets[input_port];
        let d = self.offsets[input_port + 1] - off;
        let (coord, dp) = if component < d {
            (component, 1.0)
        } else {
            let pos = &self.signals[2 * off + component - d];
            if pos.interpolated {
                return 0.0;
            }
            (component - d, self.t - pos.t_ref)
        };
        self.update_interface(host);
        let n = self.reference.len();
        let k = self.interface.matrix.as_deref().expect("just computed");
        -dp * k[(self.offsets[port] + axis) * n + off + coord]
    }

    /// Appends the input signals and the condensation step size to a snapshot.
    pub fn save(&self, w: &mut StateWriter) {
        for sig in &self.signals {
            sig.save(w);
        }
        w.f64(self.interface.h);
    }

    /// Reads what [`Ports::save`] wrote; the model then calls [`Ports::commit`] with its
    /// restored state and [`Ports::update_interface`].
    pub fn restore(&mut self, r: &mut StateReader) -> Result<(), SnapshotError> {
        for sig in &mut self.signals {
            *sig = InputSignal::restore(r)?;
        }
        self.interface.h = r.f64()?;
        self.interface.matrix = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    //! A port on a two-spring chain: port coordinate 0 —k1— free mass m (coordinate 1) —k2—
    //! ground, where the condensation has the closed form
    //! `K_int = k1 − k1² / (k1 + k2 + 4 m / h²)`.
    use super::*;
    use crate::linalg::CscPattern;
    use crate::model::{JacobianCoeffs, ModelError};

    const K1: f64 = 3.0e4;
    const K2: f64 = 5.0e4;
    const M: f64 = 2.0;
    const H: f64 = 1e-2;

    struct Chain {
        q: [f64; 2],
        pattern: CscPattern,
        scales: Vec<f64>,
    }

    impl MechanicalSystem for Chain {
        fn n_free(&self) -> usize {
            1
        }
        fn pattern(&self) -> &CscPattern {
            &self.pattern
        }
        fn scales(&self) -> &[f64] {
            &self.scales
        }
        fn residual(
            &mut self,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: f64,
            _: &mut [f64],
            _: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            unimplemented!("the ports do not call the residual")
        }
        fn midpoint_residual(
            &mut self,
            _: f64,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: &mut [f64],
            _: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            unimplemented!("the ports do not call the midpoint residual")
        }
    }

    impl PortHost for Chain {
        fn free_index(&self, full: usize) -> Option<usize> {
            (full == 1).then_some(0)
        }
        fn port_residual(&self, coords: &[usize], out: &mut [f64]) {
            assert_eq!(coords, [0]);
            out[0] = K1 * (self.q[0] - self.q[1]);
        }
        fn port_rows(&self, coords: &[usize], _c_m: f64, add: &mut dyn FnMut(usize, usize, f64)) {
            assert_eq!(coords, [0]);
            add(0, 0, K1);
            add(0, 1, -K1);
        }
        fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]) {
            vals[0] = K1 + K2 + c_m * M;
        }
    }

    fn chain() -> (Chain, Ports) {
        let host = Chain {
            q: [0.1, 0.04],
            pattern: CscPattern::from_entries(1, [(0, 0)]),
            scales: vec![1.0],
        };
        let ports = Ports::new(&[vec![0]], &[0.1, 0.04], H);
        (host, ports)
    }

    #[test]
    fn condensation_matches_the_closed_form() {
        let (mut host, mut ports) = chain();
        ports.update_interface(&mut host);
        let want = K1 - K1 * K1 / (K1 + K2 + 4.0 * M / (H * H));
        let got = -ports.force_input_derivative(&mut host, 0, 0, 0, 0);
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    }

    #[test]
    fn force_is_the_reaction_extrapolated_with_the_interface_matrix() {
        let (mut host, mut ports) = chain();
        let r0 = K1 * (0.1 - 0.04);
        assert_eq!(ports.force(&host, 0, 0), -r0);
        ports.signal_mut(0, 0).set(0.1 + 1e-3, 0.0);
        ports.update_interface(&mut host);
        let k = -ports.force_input_derivative(&mut host, 0, 0, 0, 0);
        let f = ports.force(&host, 0, 0);
        assert!((f + r0 + k * 1e-3).abs() <= 1e-12 * r0, "{f}");
        // a velocity input set at the committed time does not move the port yet (τ = 0)
        assert_eq!(ports.force_input_derivative(&mut host, 0, 0, 0, 1), 0.0);
    }

    #[test]
    fn apply_ramps_statics_and_holds_the_committed_state() {
        let (_, mut ports) = chain();
        ports.signal_mut(0, 0).set(0.3, 0.0);
        ports.signal_mut(0, 1).set(2.0, 0.0);
        let (mut q, mut v, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        ports.apply(0.5, 1.0, Some(&mut q), Some(&mut v), Some(&mut a));
        assert_eq!((q[0], v[0], a[0]), (0.3 + 0.5 * 2.0, 2.0, 0.0));
        assert_eq!(q[1], 0.0, "free coordinates untouched");
        ports.apply(0.0, 0.25, Some(&mut q), None, None);
        assert!((q[0] - (0.1 + 0.25 * (0.3 - 0.1))).abs() < 1e-15);
        ports.hold(true);
        ports.apply(0.0, 1.0, Some(&mut q), Some(&mut v), None);
        assert_eq!((q[0], v[0]), (0.1, 0.0), "held at the committed state");
        ports.commit(0.0, &[0.7, 0.0], &[0.2, 0.0]);
        ports.apply(0.0, 1.0, Some(&mut q), Some(&mut v), None);
        assert_eq!((q[0], v[0]), (0.7, 0.2));
    }

    /// A group channel: coordinates 0 and 2 translate together, spring k1 from 0 and k2 from 2
    /// to the free mass (coordinate 1), so `B = [1, 0, 1]ᵀ` and
    /// `K_int = (k1 + k2) − (k1 + k2)² / (k1 + k2 + 4 m / h²)`.
    struct Pair {
        q: [f64; 3],
        pattern: CscPattern,
        scales: Vec<f64>,
    }

    impl MechanicalSystem for Pair {
        fn n_free(&self) -> usize {
            1
        }
        fn pattern(&self) -> &CscPattern {
            &self.pattern
        }
        fn scales(&self) -> &[f64] {
            &self.scales
        }
        fn residual(
            &mut self,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: f64,
            _: &mut [f64],
            _: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            unimplemented!("the ports do not call the residual")
        }
        fn midpoint_residual(
            &mut self,
            _: f64,
            _: f64,
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: &[f64],
            _: &mut [f64],
            _: Option<(JacobianCoeffs, &mut [f64])>,
        ) -> Result<(), ModelError> {
            unimplemented!("the ports do not call the midpoint residual")
        }
    }

    impl PortHost for Pair {
        fn free_index(&self, full: usize) -> Option<usize> {
            (full == 1).then_some(0)
        }
        fn port_residual(&self, coords: &[usize], out: &mut [f64]) {
            assert_eq!(coords, [0, 2]);
            out[0] = K1 * (self.q[0] - self.q[1]);
            out[1] = K2 * (self.q[2] - self.q[1]);
        }
        fn port_rows(&self, coords: &[usize], _c_m: f64, add: &mut dyn FnMut(usize, usize, f64)) {
            assert_eq!(coords, [0, 2]);
            add(0, 0, K1);
            add(0, 1, -K1);
            add(1, 2, K2);
            add(1, 1, -K2);
        }
        fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]) {
            vals[0] = K1 + K2 + c_m * M;
        }
    }

    #[test]
    fn a_group_channel_sums_rows_columns_and_reactions() {
        let q0 = [0.1, 0.04, 0.3];
        let mut host = Pair {
            q: q0,
            pattern: CscPattern::from_entries(1, [(0, 0)]),
            scales: vec![1.0],
        };
        let reference = 0.2;
        let mut ports = Ports::grouped(
            &[vec![Channel {
                members: vec![0, 2],
                reference,
            }]],
            &q0,
            H,
        );
        assert_eq!(ports.coords(0), [0, 2]);
        ports.update_interface(&mut host);
        let ks = K1 + K2;
        let want = ks - ks * ks / (ks + 4.0 * M / (H * H));
        let got = -ports.force_input_derivative(&mut host, 0, 0, 0, 0);
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
        // the reaction is the sum over the members
        let r = K1 * (0.1 - 0.04) + K2 * (0.3 - 0.04);
        assert_eq!(ports.force(&host, 0, 0), -r);
        // members move rigidly with the channel: x_i = X_i + (u - u_ref)
        ports.signal_mut(0, 0).set(reference + 0.05, 0.0);
        let mut q = [0.0; 3];
        ports.apply(0.0, 1.0, Some(&mut q), None, None);
        assert!(
            (q[0] - 0.15).abs() < 1e-15 && (q[2] - 0.35).abs() < 1e-15,
            "{q:?}"
        );
        assert_eq!(q[1], 0.0, "free coordinate untouched");
        ports.apply(0.0, 0.5, Some(&mut q), None, None);
        assert!(
            (q[0] - 0.125).abs() < 1e-15 && (q[2] - 0.325).abs() < 1e-15,
            "{q:?}"
        );
        // committing the applied state: the channel is at the prescribed position exactly
        ports.apply(0.0, 1.0, Some(&mut q), None, None);
        ports.commit(0.0, &q, &[0.0; 3]);
        assert_eq!(ports.position(0, 0), reference + 0.05);
        host.q = [q[0], 0.04, q[2]];
        let r = K1 * (q[0] - 0.04) + K2 * (q[2] - 0.04);
        assert_eq!(
            ports.force(&host, 0, 0),
            -r,
            "no extrapolation once committed"
        );
    }
}
