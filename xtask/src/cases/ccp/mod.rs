//! CCP solver benchmarks: every solver of `chrono-ccp` on problems captured from scenes
//! (`ccp-solvers`), and the throughput of the basic operation `N g` (`ccp-apply-n`). The
//! problems come from `chrono_ccp::testing`.

pub mod apply_n;
pub mod solvers;

use chrono_ccp::{CcpSolver, SolveStats};
use chrono_core::descriptor::CcpProblem;

/// Residual levels the reports read off the histories (m/s).
pub const LEVELS: [(f64, &str); 2] = [(1e-4, "1e-4"), (1e-6, "1e-6")];

/// One solve with history, cold start, timed.
pub struct Run {
    /// Solver name.
    pub solver: String,
    /// Its statistics (with history).
    pub stats: SolveStats,
    /// Wall time of the whole solve, s.
    pub wall_s: f64,
    /// The answer.
    pub gamma: Vec<f64>,
}

impl Run {
    /// Solve `problem` from zero with `solver` (history on).
    pub fn solve(solver: &mut dyn CcpSolver, problem: &CcpProblem) -> Self {
        solver.settings_mut().record_history = true;
        let mut gamma = vec![0.0; problem.n_rows()];
        let t0 = std::time::Instant::now();
        let stats = solver.solve(problem, &mut gamma);
        let wall_s = t0.elapsed().as_secs_f64();
        Self {
            solver: solver.name().to_string(),
            stats,
            wall_s,
            gamma,
        }
    }

    /// The first history record at or below `level`: (iterations, `apply_n`-equivalents,
    /// seconds); NaN when the level was not reached.
    pub fn reached(&self, level: f64) -> (f64, f64, f64) {
        self.stats
            .history
            .iter()
            .find(|r| r.residual <= level)
            .map_or((f64::NAN, f64::NAN, f64::NAN), |r| {
                (r.iteration as f64, r.apply_n as f64, r.time_s)
            })
    }
}
