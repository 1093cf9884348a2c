//! Motion ports: coordinates of a body whose position and velocity the co-simulation master
//! prescribes (inputs), and the force the body exerts on the driver (outputs), with the
//! interface Jacobian that tells the master how that force changes with the prescribed motion.
//!
//! A port owns a list of full-coordinate indices: two for a planar point (x, y), three for a 3D
//! point (x, y, z); a 3D pose adds its three rotation coordinates. Its inputs are, in this
//! order, the position of every coordinate and then the velocity of every coordinate (planar:
//! x, y, vx, vy; 3D point: x, y, z, vx, vy, vz); its outputs are the force on the driver per
//! coordinate (fx, fy[, fz]).
//!
//! **Interface Jacobian** (after Sicklinger, Belsky, Engelmann, Elmqvist, Olsson, Wüchner,
//! Bletzinger: "Interface Jacobian-based Co-Simulation", IJNME 98, 2014): the change of the port
//! reactions after one Newmark step of size `h` when the prescribed port trajectory is shifted
//! by a constant displacement (the port's acceleration is given by the inputs, so it does not
//! change), with the interior responding:
//! `K_int = K_cc − S_cf S_ff⁻¹ K_fc`, `S = K_T + (4/h²) M` (`c` the port coordinates, `f` the
//! free ones). The model supplies its rows and free–free matrix through [`PortHost`]; the
//! condensation runs once per communication point (when a motion input is set, or after a
//! state restore), never per internal step.

use crate::linalg::{LinearSolver, SolverKind};
use crate::model::MechanicalSystem;
use crate::model::inputs::{InputSignal, prescribed};
use crate::snapshot::{SnapshotError, StateReader, StateWriter};

/// Most coordinates of one port: a 3D pose (three positions, three rotations).
pub const MAX_PORT_COORDS: usize = 6;

/// What a model provides to its [`Ports`]: all at its committed state.
pub trait PortHost: MechanicalSystem {
    /// Free index of full coordinate `full`, `None` if it is constrained (ports are).
    fn free_index(&self, full: usize) -> Option<usize>;

    /// Residual `M a + f_int − f_ext` [N] of the committed state at the full coordinates
    /// `coords` of one port, into `out` (same length): the force the driver applies to the
    /// body to enforce the motion.
    fn port_residual(&self, coords: &[usize], out: &mut [f64]);

    /// Rows of `K_T + c_m M` (`c_m` [1/s²]) of the committed state at the full coordinates
    /// `coords` of one port: `add(k, column, value)` for every entry of row `coords[k]` at full
    /// `column` (entries of the same column are summed by the caller, in call order).
    fn port_rows(&self, coords: &[usize], c_m: f64, add: &mut dyn FnMut(usize, usize, f64));

    /// Values of the free–free iteration matrix `K_T + c_m M` of the committed state in the
    /// model's pattern ([`MechanicalSystem::pattern`]), into `vals` (length `nnz`).
    fn free_matrix(&mut self, c_m: f64, vals: &mut [f64]);
}

/// The motion ports of a model.
#[derive(Debug, Default)]
pub struct Ports {
    /// Full coordinate indices of all ports, port after port.
    coords: Vec<usize>,
    /// Port `p` has `coords[offsets[p]..offsets[p + 1]]`.
    offsets: Vec<usize>,
    /// Reference values of the port coordinates (start of the static load ramp) [m].
    reference: Vec<f64>,
    /// Inputs per port: the position of each coordinate, then its velocity (so input signal
    /// `2 offsets[p] + component` is component `component` of port `p`).
    signals: Vec<InputSignal>,
    /// Committed time [s] and port coordinates and velocities.
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
            coords: self.coords.clone(),
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
    /// `K_int` (n × n over all port coordinates, row-major) at the committed state [N/m].
    matrix: Option<Vec<f64>>,
    solver: Option<LinearSolver>,
    /// Values of `S_ff`.
    vals: Vec<f64>,
    /// Rows of `S` at the port coordinates restricted to the free ones (n × n_free).
    s_rows: Vec<f64>,
    /// One column of `K_fc`, then `S_ff⁻¹ K_fc` (n_free).
    x: Vec<f64>,
}

impl Ports {
    /// Ports at the given full coordinates (one list per port), starting at rest at the
    /// reference configuration `q0` (full vector) at time 0; `h` [s] is the first
    /// communication step size.
    /// At most [`MAX_PORT_COORDS`] coordinates per port.
    pub fn new(ports: &[Vec<usize>], q0: &[f64], h: f64) -> Self {
        assert!(
            ports.iter().all(|p| p.len() <= MAX_PORT_COORDS),
            "a port has at most {MAX_PORT_COORDS} coordinates"
        );
        let mut offsets = vec![0];
        let coords: Vec<usize> = ports.iter().flatten().copied().collect();
        for p in ports {
            offsets.push(offsets.last().copied().unwrap_or(0) + p.len());
        }
        let reference: Vec<f64> = coords.iter().map(|&i| q0[i]).collect();
        let mut signals = Vec::with_capacity(2 * coords.len());
        for p in ports {
            signals.extend(p.iter().map(|&i| InputSignal::constant(q0[i])));
            signals.extend(p.iter().map(|_| InputSignal::constant(0.0)));
        }
        Self {
            q: reference.clone(),
            v: vec![0.0; coords.len()],
            coords,
            offsets,
            reference,
            signals,
            t: 0.0,
            hold: false,
            interface: Interface {
                h,
                ..Interface::default()
            },
        }
    }

    /// Number of ports.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there are no ports.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Full coordinate indices of port `port`.
    pub fn coords(&self, port: usize) -> &[usize] {
        &self.coords[self.offsets[port]..self.offsets[port + 1]]
    }

    /// The input signal of `component` (positions, then velocities) of port `port`.
    pub fn signal_mut(&mut self, port: usize, component: usize) -> &mut InputSignal {
        &mut self.signals[2 * self.offsets[port] + component]
    }

    /// Position and velocity signals of port coordinate `k` (over all ports).
    fn signals_of(&self, k: usize) -> (&InputSignal, &InputSignal) {
        let p = self.port_of(k);
        let (off, d) = (self.offsets[p], self.offsets[p + 1] - self.offsets[p]);
        let base = 2 * off + (k - off);
        (&self.signals[base], &self.signals[base + d])
    }

    fn port_of(&self, k: usize) -> usize {
        self.offsets.partition_point(|&o| o <= k) - 1
    }

    /// Keeps ports at their committed positions while set (`Model::hold_prescribed_motion`).
    pub fn hold(&mut self, hold: bool) {
        self.hold = hold;
    }

    /// Records the committed state (full vectors) at time `t` [s]; call after
    /// [`Ports::apply`] in `Model::accept` and after a restore. Clears the interface matrix.
    pub fn commit(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.t = t;
        for (k, &i) in self.coords.iter().enumerate() {
            self.q[k] = q[i];
            self.v[k] = v[i];
        }
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
        for (k, &i) in self.coords.iter().enumerate() {
            let (pos, vel) = self.signals_of(k);
            let (mut p, mut pd, pdd) = prescribed(pos, vel, t);
            if self.hold && t == self.t {
                (p, pd) = (self.q[k], self.v[k]);
            }
            if let Some(q) = q.as_deref_mut() {
                // exactly `p` when fully applied: q0 + (p - q0) can differ from p in the last
                // bit, and `force` relies on q = p at the committed state
                q[i] = if lambda == 1.0 {
                    p
                } else {
                    self.reference[k] + lambda * (p - self.reference[k])
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

    /// `K_int = K_cc − S_cf S_ff⁻¹ K_fc`; if `S_ff` cannot be factorized, `K_cc` (the
    /// frozen-interior stiffness) is returned.
    fn condense<H: PortHost>(&mut self, host: &mut H) -> Vec<f64> {
        let n = self.coords.len();
        let n_free = host.n_free();
        let c_m = 4.0 / (self.interface.h * self.interface.h);
        // K_cc
        let mut k = vec![0.0; n * n];
        for p in 0..self.len() {
            let off = self.offsets[p];
            host.port_rows(self.coords(p), 0.0, &mut |r, col, val| {
                if let Some(j) = self.coords.iter().position(|&c| c == col) {
                    k[(off + r) * n + j] += val;
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
                    let off = self.offsets[p];
                    hr.port_rows(self.coords(p), c_m, &mut |r, col, val| {
                        if let Some(f) = hr.free_index(col) {
                            s_rows[(off + r) * n_free + f] += val;
                        }
                    });
                }
                for j in 0..n {
                    // column j of K_fc = row j of K_cf (K_T is symmetric)
                    x.clear();
                    x.resize(n_free, 0.0);
                    let p = self.port_of(j);
                    let (off, coords) = (self.offsets[p], self.coords(p));
                    hr.port_rows(coords, 0.0, &mut |r, col, val| {
                        if let (true, Some(f)) = (off + r == j, hr.free_index(col)) {
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

    /// Force [N] on the driver at port `port`, coordinate `axis`, with the current inputs: the
    /// committed reaction (from [`PortHost::port_residual`]), extrapolated with the interface
    /// Jacobian if the inputs moved a port since the last commit (then
    /// [`Ports::update_interface`] must have run, which setting a motion input does).
    pub fn force<H: PortHost>(&self, host: &H, port: usize, axis: usize) -> f64 {
        let coords = self.coords(port);
        let mut r = [0.0; MAX_PORT_COORDS];
        let r = &mut r[..coords.len()];
        host.port_residual(coords, r);
        let n = self.coords.len();
        let row = self.offsets[port] + axis;
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
        -(r[axis] + extra)
    }

    /// Time derivative [N/s] of the stiffness part of the force on the driver at `port`,
    /// `axis`: `−K_c v` at the committed state (inertia rates neglected); `v` full velocities.
    pub fn force_rate<H: PortHost>(&self, host: &H, port: usize, axis: usize, v: &[f64]) -> f64 {
        let mut sum = 0.0;
        host.port_rows(self.coords(port), 0.0, &mut |r, col, val| {
            if r == axis {
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
        let n = self.coords.len();
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
}
