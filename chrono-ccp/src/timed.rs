//! A CCP solver wrapper that measures the solves' wall time (for the speed figures of
//! the validation cases and the examples: wall time of the solves over that of the steps).

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use chrono_core::descriptor::{CcpProblem, CcpSolver, SolveStats, SolverSettings};

/// A CCP solver that adds its wall time to a shared counter (ns).
pub struct TimedSolver {
    /// The solver that does the work.
    pub inner: Box<dyn CcpSolver>,
    /// Nanoseconds spent in `inner.solve`, summed.
    pub nanos: Arc<AtomicU64>,
}

impl CcpSolver for TimedSolver {
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn settings(&self) -> &SolverSettings {
        self.inner.settings()
    }
    fn settings_mut(&mut self) -> &mut SolverSettings {
        self.inner.settings_mut()
    }
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        let t = Instant::now();
        let s = self.inner.solve(problem, gamma);
        self.nanos
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        s
    }
}
