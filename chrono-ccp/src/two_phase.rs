//! The two-phase strategy of the seed's mud scene: solve the bilateral rows first (a linear
//! problem, by a Krylov method), then the full CCP warm-started from that answer.
//!
//! Phase 1 solves the sub-problem of the bilateral rows with the other rows' impulses held
//! at their warm start, `N_BB g_B = -(r_B + N_BO g_O)`
//! ([`CcpProblem::subproblem`](chrono_core::descriptor::CcpProblem::subproblem)); phase 2
//! runs the CCP solver on the whole problem from `(g_B, g_O)`. When density constraints
//! dominate the problem (constraint fluids) phase 1 does most of the work at Krylov speed
//! and phase 2 only corrects the coupling with the contacts.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, IterationRecord, SolveStats, SolverSettings,
};

use crate::util::{check_gamma_len, empty_stats, sanitize_and_project};
use crate::{Apgd, Cg};

/// Two-phase solver: a bilateral phase ([`Cg`] by default), then a full CCP phase
/// ([`Apgd`] by default). See the [module documentation](self).
///
/// A warm start that already meets the tolerance skips phase 1 (one gradient to check).
///
/// Statistics: `iterations` and the history are those of both phases (phase 2 continues the
/// numbering and the clock of phase 1); `apply_n` counts phase-1 products scaled by the
/// sub-problem's share of the Jacobian (`nnz(D_B) / nnz(D)`, rounded up), so it stays in
/// units of full products. The settings apply to phase 2; phase 1 keeps its own.
pub struct TwoPhase {
    bilateral: Box<dyn CcpSolver>,
    full: Box<dyn CcpSolver>,
    sub: CcpProblem,
    sub_gamma: Vec<f64>,
    grad: Vec<f64>,
    work: CcpWork,
}

impl TwoPhase {
    /// CG (tolerance `settings.tolerance / 10`, same cap) then APGD with `settings`.
    pub fn new(settings: SolverSettings) -> Self {
        let mut s1 = settings.clone();
        s1.tolerance = settings.tolerance / 10.0;
        Self::with_solvers(Box::new(Cg::new(s1)), Box::new(Apgd::new(settings)))
    }

    /// Any bilateral-phase and full-phase solvers.
    pub fn with_solvers(bilateral: Box<dyn CcpSolver>, full: Box<dyn CcpSolver>) -> Self {
        Self {
            bilateral,
            full,
            sub: CcpProblem::new(),
            sub_gamma: Vec::new(),
            grad: Vec::new(),
            work: CcpWork::default(),
        }
    }
}

impl CcpSolver for TwoPhase {
    fn name(&self) -> &'static str {
        "two-phase"
    }

    fn settings(&self) -> &SolverSettings {
        self.full.settings()
    }

    fn settings_mut(&mut self) -> &mut SolverSettings {
        self.full.settings_mut()
    }

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let nb = problem.sections().bilateral.len();
        if nb == m {
            return self.bilateral.solve(problem, gamma);
        }
        if nb == 0 {
            return self.full.solve(problem, gamma);
        }
        sanitize_and_project(problem, gamma);
        // A warm start that already solves the problem needs no phase 1.
        self.grad.resize(m, 0.0);
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        let warm_res = problem.residual(gamma, &self.grad, &mut self.work);
        let mut first = SolveStats {
            apply_n: 1,
            ..SolveStats::default()
        };
        if warm_res > self.full.settings().tolerance && self.sub_problem(problem, gamma) {
            self.sub_gamma.clear();
            self.sub_gamma.extend_from_slice(&gamma[..nb]);
            first = self.bilateral.solve(&self.sub, &mut self.sub_gamma);
            if self.sub_gamma.iter().all(|g| g.is_finite()) {
                gamma[..nb].copy_from_slice(&self.sub_gamma);
            }
            let share = self.sub.n_coefs() as f64 / problem.n_coefs().max(1) as f64;
            first.apply_n = 1 + (first.apply_n as f64 * share).ceil() as usize;
        }
        let mut second = self.full.solve(problem, gamma);
        let t_offset = first.history.last().map_or(0.0, |r| r.time_s);
        let mut history: Vec<IterationRecord> = std::mem::take(&mut first.history);
        history.extend(second.history.iter().map(|r| IterationRecord {
            iteration: r.iteration + first.iterations,
            time_s: r.time_s + t_offset,
            apply_n: r.apply_n + first.apply_n,
            ..*r
        }));
        second.history = history;
        second.iterations += first.iterations;
        second.apply_n += first.apply_n;
        second
    }
}

impl TwoPhase {
    /// Assemble the bilateral sub-problem into `self.sub`; false if that failed (it cannot
    /// for a problem that assembled, but a failure only skips phase 1).
    fn sub_problem(&mut self, problem: &CcpProblem, gamma: &[f64]) -> bool {
        let nb = problem.sections().bilateral.len();
        problem.subproblem(0..nb, gamma, &mut self.sub).is_ok()
    }
}
