//! Coulomb friction without the lift of the relaxed cone: the de Saxcé fixed point on top of
//! the convex CCP of the NSC step.
//!
//! The CCP `K ∋ g ⊥ u ∈ K*` (with `u = N g + r` the constraint velocity) is the optimality
//! condition of a convex QP, but for a sliding contact it gives `u_n = mu |u_t|`: the bodies
//! separate at `mu |u_t|` while they slide (Anitescu 2006, "Optimization-based simulation
//! of nonsmooth rigid multibody dynamics", Math. Program. 105; the "relaxed" or associated
//! friction law). Coulomb's law proper (no normal velocity while sliding) is the CCP in the
//! modified velocity `û = u + s e_n`, `s = mu |u_t|` (De Saxcé and Feng 1998, "The
//! bipotential method", Math. Comput. Model. 28): with `s` frozen it is again a convex CCP
//! (the normal bias shifted by `s`), so Coulomb's law is a fixed point of convex solves,
//! `s_{k+1} = mu |u_t(g(s_k))|` (Acary, Cadoux, Lemaréchal and Malick 2011, "A formulation
//! of the linear discrete Coulomb friction problem via convex optimization", ZAMM 91).
//! [`FrictionLaw::Coulomb`] runs that iteration after the step's first (relaxed) solve,
//! each re-solve warm-started from the last.

use serde::{Deserialize, Serialize};

use super::System;
use crate::descriptor::{PER_BODY_ROWS, SolveStats};
use crate::error::{ChronoError, Result};

/// The friction law of the NSC step's contacts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionLaw {
    /// The convex (relaxed) cone of Anitescu and Tasora: one CCP solve per step; a contact
    /// sliding at `|u_t|` separates at `u_n = mu |u_t|` (a lift of `h mu |u_t|` per step,
    /// small when `h |u_t|` is small against the contact's scale). Chrono's NSC law.
    #[default]
    Relaxed,
    /// Coulomb's law: after the relaxed solve, up to `passes` re-solves with the normal
    /// bias of each contact shifted by `s = mu |u_t|` of the last solution (spinning and
    /// rolling parts add `mu_spin |u_s| + mu_roll |u_r|`, per body for the per-body model),
    /// stopping early when no shift changes by more than the solver's tolerance. Each pass
    /// costs one solve. The passes converge linearly: for one sliding contact the shift's
    /// error shrinks by `k mu^2 / (1 + k mu^2)` per pass, with `k` the tangential over the
    /// normal inverse effective mass (3.5 for a sphere on a plate): 0.1 at `mu = 0.18`, 0.78
    /// at `mu = 1`.
    Coulomb {
        /// Maximum number of re-solves per step (>= 1).
        passes: usize,
    },
}

impl FrictionLaw {
    /// Check the fields.
    pub fn validate(&self) -> Result<()> {
        match *self {
            FrictionLaw::Relaxed => Ok(()),
            FrictionLaw::Coulomb { passes } if passes == 0 => Err(ChronoError::invalid(
                "settings.friction_law.passes",
                passes,
                "must be >= 1 (use `relaxed` for no re-solve)",
            )),
            FrictionLaw::Coulomb { .. } => Ok(()),
        }
    }
}

impl System {
    /// The de Saxcé passes of [`FrictionLaw::Coulomb`] after the first solve `first`
    /// (`self.gamma` holds its solution). Leaves `self.problem`'s normal biases shifted by
    /// the last `s` and returns the statistics summed over all solves (iterations, work)
    /// with the residual and convergence of the last, and the number of re-solves done.
    pub(crate) fn coulomb_passes(
        &mut self,
        passes: usize,
        first: SolveStats,
    ) -> (SolveStats, usize) {
        let mut stats = first;
        let mut done = 0;
        let tol = self.solver.settings().tolerance;
        let sections = self.problem.sections().clone();
        let nf = sections.friction.len() / 3;
        let nr = sections.rolling.len() / 6 + sections.rolling_per_body.len() / PER_BODY_ROWS;
        self.coulomb_shift.clear();
        self.coulomb_shift.resize(nf + nr, 0.0);
        self.coulomb_next.resize(nf + nr, 0.0);
        if nf + nr == 0 {
            return (stats, 0);
        }
        let ndof = self.problem.ndof();
        for _ in 0..passes {
            self.v.clear();
            self.v.resize(ndof, 0.0);
            self.problem.velocities(&self.gamma, &mut self.v);
            let (p, v, g) = (&self.problem, &self.v, &self.gamma);
            // Constraint velocity u_i = D_i'v + b_i + eps_i g_i (the row of N g + r).
            let u = |i: usize| p.row_dot(i, v) + p.b()[i] + p.eps()[i] * g[i];
            let mu = p.friction_mu();
            for (c, t) in sections.friction.clone().step_by(3).enumerate() {
                self.coulomb_next[c] = mu[c] * u(t + 1).hypot(u(t + 2));
            }
            let mu_r = p.rolling_mu();
            for (c, t) in sections.rolling.clone().step_by(6).enumerate() {
                let m = mu_r[c];
                self.coulomb_next[nf + c] = m[0] * u(t + 1).hypot(u(t + 2))
                    + m[1] * u(t + 3).abs()
                    + m[2] * u(t + 4).hypot(u(t + 5));
            }
            // Per-body: both bodies' own rolling parts (3 rows each) add to the shift.
            let n6 = sections.rolling.len() / 6;
            let mu_pb = p.rolling_per_body_mu();
            let norm3 = |t: usize| (u(t).powi(2) + u(t + 1).powi(2) + u(t + 2).powi(2)).sqrt();
            for (c, t) in sections
                .rolling_per_body
                .clone()
                .step_by(PER_BODY_ROWS)
                .enumerate()
            {
                let m = mu_pb[c];
                self.coulomb_next[nf + n6 + c] = m[0] * u(t + 1).hypot(u(t + 2))
                    + m[1] * u(t + 3).abs()
                    + m[2] * (norm3(t + 4) + norm3(t + 7));
            }
            let change = self
                .coulomb_shift
                .iter()
                .zip(&self.coulomb_next)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if change <= tol {
                break;
            }
            let rows = sections
                .friction
                .clone()
                .step_by(3)
                .chain(sections.rolling.clone().step_by(6))
                .chain(sections.rolling_per_body.clone().step_by(PER_BODY_ROWS));
            for (c, t) in rows.enumerate() {
                let d = self.coulomb_next[c] - self.coulomb_shift[c];
                self.problem.add_to_bias(t, d);
            }
            std::mem::swap(&mut self.coulomb_shift, &mut self.coulomb_next);
            let s = self.solver.solve(&self.problem, &mut self.gamma);
            stats.iterations += s.iterations;
            stats.apply_n += s.apply_n;
            stats.residual = s.residual;
            stats.objective = s.objective;
            stats.converged = s.converged;
            done += 1;
        }
        (stats, done)
    }
}
