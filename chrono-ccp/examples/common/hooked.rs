//! APGD with a hook called on every solve's problem and warm start before the solve (the
//! error studies of `pour_stats` and `ball_study`).

use chrono_ccp::{Apgd, CcpSolver, SolveStats, SolverSettings};
use chrono_core::descriptor::CcpProblem;

/// APGD that first calls `hook(problem, warm start)` on every solve.
pub struct Hooked<F> {
    pub apgd: Apgd,
    pub hook: F,
}

impl<F: FnMut(&CcpProblem, &[f64]) + Send + Sync> CcpSolver for Hooked<F> {
    fn name(&self) -> &'static str {
        "study"
    }
    fn settings(&self) -> &SolverSettings {
        self.apgd.settings()
    }
    fn settings_mut(&mut self) -> &mut SolverSettings {
        self.apgd.settings_mut()
    }
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        (self.hook)(problem, gamma);
        self.apgd.solve(problem, gamma)
    }
}
