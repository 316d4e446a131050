//! The interface of CCP solvers.

use serde::{Deserialize, Serialize};

use super::problem::CcpProblem;

/// Settings common to every iterative CCP solver.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolverSettings {
    /// Stop when the residual ([`CcpProblem::residual`], m/s) is below this.
    pub tolerance: f64,
    /// Hard cap on iterations.
    pub max_iterations: usize,
    /// Record the residual after every iteration in [`SolveStats::history`].
    pub record_history: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_iterations: 200,
            record_history: false,
        }
    }
}

/// One entry of the convergence history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Iteration number (1-based).
    pub iteration: usize,
    /// Residual after that iteration, m/s.
    pub residual: f64,
    /// Objective `1/2 g'N g + r'g` of the iterate the residual is of.
    pub objective: f64,
    /// `apply_n`-equivalents spent so far (see [`SolveStats::apply_n`]).
    pub apply_n: usize,
    /// Wall time since the start of the solve, s.
    pub time_s: f64,
}

/// What a solve did.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SolveStats {
    /// Iterations performed.
    pub iterations: usize,
    /// Residual of the returned solution, m/s.
    pub residual: f64,
    /// Objective `1/2 g'N g + r'g` of the returned solution.
    pub objective: f64,
    /// True if the residual reached the tolerance.
    pub converged: bool,
    /// Work in `apply_n`-equivalents: products `N x` (or gradients `N x + r`) computed, plus
    /// one per Gauss–Seidel sweep (a sweep streams the Jacobian once, like one product).
    /// The machine-independent measure of cost that compares solvers.
    pub apply_n: usize,
    /// Per-iteration residuals, if requested.
    pub history: Vec<IterationRecord>,
}

/// A solver of the cone complementarity problem
/// `Y ∋ g ⊥ -(N g + r) ∈ Y°` (equivalently `min 1/2 g'N g + r'g, g ∈ Y`).
pub trait CcpSolver: Send + Sync {
    /// Short name, e.g. `psor`.
    fn name(&self) -> &'static str;
    /// The settings.
    fn settings(&self) -> &SolverSettings;
    /// The settings, mutable.
    fn settings_mut(&mut self) -> &mut SolverSettings;
    /// Solve `problem`. On entry `gamma` holds the warm start (zeros for a cold start; it is
    /// projected first); on exit the solution. `gamma.len() == problem.n_rows()`.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats;
}
