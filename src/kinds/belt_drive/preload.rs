//! Pre-load of a closed belt: mounted on the pulleys with its span tension, brought into
//! static equilibrium, and the reference length corrected until the mean span tension is the
//! requested one.

use super::model::BeltDrive;
use crate::model::{MechanicalSystem, Model};

/// What the static pre-load did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PreloadReport {
    /// Static solves (one per reference-length correction).
    pub solves: usize,
    /// Newton iterations in total.
    pub iterations: usize,
    /// Span tensions after the last solve [N].
    pub span_tensions: Vec<f64>,
    /// What the pre-load could not do (the pre-tension not reached within 0.1 % in its
    /// rounds), for the importer's log.
    pub note: Option<String>,
}

impl BeltDrive {
    /// Static pre-load: solve, compare the mean span tension (the mean over the spans of the
    /// axial force at the span middles) with `pretension`, correct the reference length,
    /// repeat (at most 4 times; 9 with gravity). Free pulleys are held at their angles
    /// while the belt is mounted (see [`MechanicalSystem::hold_for_statics`]).
    ///
    /// With gravity the spans sag and the load factor of the static solve scales the belt's
    /// weight (`solver.load_steps`). The correction then keeps the loop length consistent
    /// with the sag: `L_ref (1 + T/EA) = L_eff + S(T)`, `S(T) = sag_coeff / T²` the length
    /// the catenaries take up beyond their chords, `L_eff` calibrated by the last solve (the
    /// elastic correction alone needed 5 solves on a 4 m span sagging 2.5 %, this one 2-3);
    /// a correction whose solve fails is halved (at most 6 times).
    ///
    /// Without a tensioner each solve with friction is followed by one without, from its
    /// equilibrium ([`Self::frictionless_solve`]), and the correction compares that state's
    /// span tension: the state of a belt after running in (as belt makers tension a drive:
    /// turned over a few times, then measured on the spans). With friction the belt sinks
    /// into the rims where it was mounted and the arcs keep the mounting strain (shipped
    /// drive, 144 elements: arcs 10.2 / 6.3 N below the spans at rest), which running
    /// releases: the spans then lost 1.9 N at 10 rad/s without load, by an amount set by the
    /// contact's penalty and bristle stiffness, so that the 3D drive, whose contact differs,
    /// ran 1 N above this one (issue 13 item 4, session 33). In frictionless equilibrium an
    /// arc carries the span's tension less `EI/(2ρ²)` (Eshelby's configurational force of a
    /// bent elastica; measured 3.67 / 1.67 N against 3.72 / 1.68 N), and running changes the
    /// spans by +0.2 N. If the frictionless solve fails, the solve with friction stands
    /// ([`Self::preload_was_frictionless`]).
    ///
    /// With a tensioner the belt keeps the length it was mounted with (at `pretension` on the
    /// design layout) and one solve finds the arm's equilibrium, which sets the tension: the
    /// state of a belt after running in. That solve is frictionless (`mu = 0` on every
    /// pulley): with friction the belt sticks on the arcs, which keep the mounting tension
    /// while the spans take the arm's (measured on the shipped drive with the spring
    /// pre-load 30 % above the design balance: spans 432 N, arcs down to 353 N, the arm
    /// 20 % short of its travel). Without friction the belt sliding round its loop is a
    /// mechanism; the first belt node is held at its mounted position by a spring of `EA/L`
    /// (L the loop length) along the belt's tangent there (only the sliding direction: a
    /// spring holding it against the rim or across a span too kept its force in the
    /// equilibrium, released at t = 0; session 33, qa33). Without torques and friction nothing drives the belt round its
    /// loop, so the spring only fixes that mode (softer springs, 1e-4..1e-2 EA/L, left Newton
    /// wandering along it from the mounted state of the shipped drive), and
    /// the free pulleys by a soft bearing spring (`pulleys.rs`). The commit under `mu = 0`
    /// leaves the friction histories at rest at the equilibrium.
    pub(super) fn preload(&mut self, pretension: f64) -> Result<(), String> {
        let frictionless = self.tensioner.is_some();
        // without a tensioner each solve with friction is followed by one without
        // (`frictionless_solve`); cleared if one fails
        self.frictionless_preload = !frictionless;
        let law = self.spec.contact;
        if frictionless {
            let free = crate::contact::ContactLaw { mu: 0.0, ..law };
            self.contact.set_law(free);
            if let Some(t) = self.tensioner.as_mut() {
                t.contact.set_law(free);
            }
            let length = self.element().length() * self.n_el as f64;
            self.belt_anchor = Some((
                nalgebra::Vector2::new(self.q[0], self.q[1]),
                nalgebra::Vector2::new(self.q[2], self.q[3]).normalize(),
                self.spec.section.ea / length,
            ));
        }
        let result = self.preload_solve(pretension);
        if frictionless {
            self.contact.set_law(law);
            if let Some(t) = self.tensioner.as_mut() {
                t.contact.set_law(law);
            }
            self.belt_anchor = None;
            if result.is_err() {
                // the frictionless solve does not converge on every mesh (the shipped drive
                // at 60 elements: Newton stalls from the mounted state); the pre-load with
                // friction (arcs at the mounting tension) is the fallback
                self.frictionless_preload = false;
                return self.preload_solve(pretension);
            }
        }
        self.frictionless_preload = frictionless || self.frictionless_preload;
        result
    }

    /// The solves of [`Self::preload`].
    fn preload_solve(&mut self, pretension: f64) -> Result<(), String> {
        use crate::solver::newton::Workspace;
        let (settings, kind, load_steps) = self.spec.statics;
        let mut ws = Workspace::new(&*self, kind).map_err(|e| e.to_string())?;
        let n = self.n_free();
        let (mut qf, mut vf) = (vec![0.0; n], vec![0.0; n]);
        // with gravity the correction is nonlinear (the sag takes up length): more rounds,
        // and a correction whose solve fails is halved (at most 6 times) from the last
        // equilibrium, which the failed solve left in place
        let rounds = if self.sag_coeff > 0.0 { 10 } else { 5 };
        let mut converged_length: Option<f64> = None;
        // the last round's reference length and mean span tension (secant correction)
        let mut last: Option<(f64, f64)> = None;
        let mut halvings = 0;
        let mut round = 0;
        while round < rounds {
            self.free_state(&mut qf, &mut vf);
            let solved =
                crate::solver::statics::solve(self, &mut ws, &mut qf, &settings, load_steps);
            if solved.is_err()
                && let Some(l_ok) = converged_length
                && halvings < 6
            {
                halvings += 1;
                let l = 0.5 * (l_ok + self.element().length());
                self.set_reference_length(l)?;
                continue;
            }
            let st = solved
                .map_err(|e| {
                    let s = &self.spec.section;
                    format!(
                        "static pre-load of the belt (belt.EA = {} N, belt.EI = {} N.m2, belt.mass_per_length = {} kg/m, belt.damping_axial = {} N.s, belt.damping_bending = {} N.m2.s, belt.pretension = {pretension} N, belt.thickness = {} m, contact.mu = {}, contact.stiffness = {} N/m2, with the pulleys' radius, center and side{}; solver.newton_tolerance = {}, solver.max_iterations = {}): {e}",
                        s.ea, s.ei, s.mass_per_length, s.damping_axial, s.damping_bending, self.spec.thickness, self.spec.contact.mu, self.spec.contact.k_n,
                        if self.spec.tensioner.is_some() { "; tensioner.pulley, pivot, stiffness, preload, damping, inertia" } else { "" },
                        settings.tolerance, settings.max_iterations
                    )
                })?;
            self.preload.solves += 1;
            self.preload.iterations += st.newton.iterations;
            // without a tensioner: the run-in state (see `preload`), from this equilibrium
            let law = self.spec.contact;
            if self.tensioner.is_none() && self.frictionless_preload {
                match self.frictionless_solve(&mut ws, &mut qf) {
                    Ok(it) => {
                        self.preload.iterations += it;
                        // committed without friction: the histories at rest here
                        self.contact
                            .set_law(crate::contact::ContactLaw { mu: 0.0, ..law });
                    }
                    Err(_) => self.frictionless_preload = false,
                }
            }
            self.asm.dofs.expand(&qf, &mut self.q);
            let t = self.t;
            self.commit(t, false);
            self.contact.set_law(law);
            let mean = self.tensions.iter().sum::<f64>() / self.tensions.len().max(1) as f64;
            self.preload.span_tensions = self.tensions.clone();
            if self.tensioner.is_some() || (mean - pretension).abs() <= 1e-3 * pretension {
                break;
            }
            if round == rounds - 1 {
                self.preload.note = Some(format!(
                    "the static pre-load of the belt stopped after {rounds} corrections of the belt's reference length with a mean span tension of {mean:.6} N against belt.pretension = {pretension} N ({:+.2} %)",
                    100.0 * (mean / pretension - 1.0)
                ));
                break;
            }
            round += 1;
            let ea = self.spec.section.ea;
            let l_now = self.element().length();
            converged_length = Some(l_now);
            let l = if self.sag_coeff > 0.0 {
                // the loop takes up the spans' sag: L_ref (1 + T/EA) = L_eff + S(T) with
                // S(T) = sag_coeff / T², L_eff calibrated by this solve
                let n = self.n_el as f64;
                let sag = |t: f64| self.sag_coeff / (n * t.max(0.1 * pretension).powi(2));
                (l_now * (1.0 + mean / ea) - sag(mean) + sag(pretension)) / (1.0 + pretension / ea)
            } else {
                secant_length(l_now, mean, last, pretension)
                    .unwrap_or(l_now * (1.0 + mean / ea) / (1.0 + pretension / ea))
            };
            last = Some((l_now, mean));
            self.set_reference_length(l)?;
        }
        Ok(())
    }

    /// Static solve without friction from the equilibrium with friction in the free
    /// coordinates `qf` (drives without a tensioner, see [`Self::preload`]): `μ = 0` on every
    /// pulley, the first belt node held where it is by a spring of `EA/L` along the belt's
    /// tangent (the loop sliding round the pulleys is a mechanism without friction). Fails, leaving `qf` as it was, if
    /// Newton does not converge. Returns the Newton iterations.
    fn frictionless_solve(
        &mut self,
        ws: &mut crate::solver::newton::Workspace,
        qf: &mut [f64],
    ) -> Result<usize, String> {
        let (settings, _, _) = self.spec.statics;
        let law = self.spec.contact;
        self.contact
            .set_law(crate::contact::ContactLaw { mu: 0.0, ..law });
        let length = self.element().length() * self.n_el as f64;
        let mut full = self.q.clone();
        self.asm.dofs.expand(qf, &mut full);
        self.belt_anchor = Some((
            nalgebra::Vector2::new(full[0], full[1]),
            nalgebra::Vector2::new(full[2], full[3]).normalize(),
            self.spec.section.ea / length,
        ));
        let start = qf.to_vec();
        let solved = crate::solver::statics::solve(self, ws, qf, &settings, 1);
        self.contact.set_law(law);
        self.belt_anchor = None;
        match solved {
            Ok(st) => Ok(st.newton.iterations),
            Err(e) => {
                qf.copy_from_slice(&start);
                Err(e.to_string())
            }
        }
    }

    /// Report of the static pre-load.
    pub fn preload_report(&self) -> &PreloadReport {
        &self.preload
    }

    /// Whether the static pre-load was solved without friction (see [`Self::preload`]).
    pub fn preload_was_frictionless(&self) -> bool {
        self.frictionless_preload
    }
}

/// Reference length [m] of the next pre-load round by the secant through the last two rounds
/// (`l_now` with mean span tension `mean`, `last` the round before): `None` without a round
/// before or where the secant does not say that a shorter belt is tauter (then the elastic
/// correction `L (1 + T/EA)/(1 + T0/EA)`, which assumes the belt's own stretch takes up all
/// the length change). The elastic correction alone converges slowly where the contact's
/// penalty takes up length too: a stiff belt (EA 5e6 N, the shipped drive otherwise) was
/// still 3 % above its pre-tension after 5 rounds, each closing only 30-50 % of the gap.
pub(crate) fn secant_length(
    l_now: f64,
    mean: f64,
    last: Option<(f64, f64)>,
    target: f64,
) -> Option<f64> {
    let (l_prev, t_prev) = last?;
    let slope = (mean - t_prev) / (l_now - l_prev);
    (slope.is_finite() && slope < 0.0).then(|| l_now + (target - mean) / slope)
}
