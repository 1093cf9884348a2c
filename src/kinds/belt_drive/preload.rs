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
}

impl BeltDrive {
    /// Static pre-load: solve, compare the mean span tension with `pretension`, correct the
    /// reference length, repeat (at most 4 times). With a tensioner the belt keeps the
    /// length it was mounted with (at `pretension` on the design layout) and one solve finds
    /// the arm's equilibrium, which sets the tension. Free pulleys are then held by a soft
    /// bearing spring only (`pulleys.rs`), so that the belt slides round with the arm and,
    /// without input torques, every span has the same tension, as the hand calculation of a
    /// tensioner assumes. Free pulleys are held at their angles
    /// while the belt is mounted (see [`MechanicalSystem::hold_for_statics`]).
    pub(super) fn preload(&mut self, pretension: f64) -> Result<(), String> {
        use crate::solver::newton::Workspace;
        let (settings, kind, load_steps) = self.spec.statics;
        let mut ws = Workspace::new(&*self, kind).map_err(|e| e.to_string())?;
        let n = self.n_free();
        let (mut qf, mut vf) = (vec![0.0; n], vec![0.0; n]);
        for round in 0..5 {
            self.free_state(&mut qf, &mut vf);
            let st = crate::solver::statics::solve(self, &mut ws, &mut qf, &settings, load_steps)
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
            self.asm.dofs.expand(&qf, &mut self.q);
            let t = self.t;
            self.commit(t, false);
            let mean = self.tensions.iter().sum::<f64>() / self.tensions.len().max(1) as f64;
            self.preload.span_tensions = self.tensions.clone();
            if self.tensioner.is_some()
                || (mean - pretension).abs() <= 1e-3 * pretension
                || round == 4
            {
                break;
            }
            let ea = self.spec.section.ea;
            let l = self.element().length() * (1.0 + mean / ea) / (1.0 + pretension / ea);
            self.set_reference_length(l)?;
        }
        Ok(())
    }

    /// Report of the static pre-load.
    pub fn preload_report(&self) -> &PreloadReport {
        &self.preload
    }
}
