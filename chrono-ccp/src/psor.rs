//! Projected successive over-relaxation (projected Gauss–Seidel with relaxation).
//!
//! The method of Chrono's `ChSolverPSOR` (Anitescu and Tasora 2010, "An iterative approach
//! for cone complementarity problems for nonsmooth dynamics", Comput. Optim. Appl. 47(2)),
//! i.e. block coordinate descent on `f(g) = 1/2 g'N g + r'g` over `g ∈ Y`, matrix-free: the
//! solver keeps `w = M^-1 D g` up to date, so a row's constraint velocity is
//! `c_i = (N g + r)_i = D_i' w + eps_i g_i + r_i` (equivalently `D_i' v + b_i + eps_i g_i`
//! with `v = M^-1 k + w` the new velocity) at the cost of one sparse row.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings, project_friction_cone,
};
use serde::{Deserialize, Serialize};

use crate::util::{History, empty_stats, final_stats, sanitize_and_project};

/// How the single step size of a friction triplet `(n, u, w)` is chosen.
///
/// A triplet is updated as one block, `g_t <- P_cone(g_t - h c_t)`, with one scalar step `h`
/// for its three rows so that the scaled step keeps the cone's shape (a per-row step would
/// distort the cone and the projection would no longer be the right one).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum TripletStep {
    /// `h = omega / lambda_max(N_tt)`, with `N_tt` the 3x3 diagonal block of `N` of the
    /// triplet (computed once per solve from the rows, eigenvalue in closed form). This is a
    /// projected gradient step on the block with step `<= 1/L_block`, so every triplet update
    /// decreases `f` for `0 < omega < 2` and the sweep is a convergent block coordinate
    /// descent (Tseng 2001). The default.
    #[default]
    MaxEigen,
    /// `h = omega / mean(diag N_tt)`, Chrono's choice (`SchurComplementUpdateConstraints`
    /// averaging). Larger steps, but `lambda_max(N_tt)` can reach `3 mean(diag N_tt)`, so a
    /// triplet update can overshoot and the iteration is not guaranteed to converge.
    Average,
}

/// Options of [`Psor`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PsorOptions {
    /// Relaxation factor `omega` in `(0, 2)`: `g_i <- P(g_i - omega c_i / N_ii)`. `1` is plain
    /// projected Gauss–Seidel (exact minimization along each unilateral/box/bilateral row);
    /// `> 1` over-relaxes. Default `1.0`, as in Chrono.
    pub omega: f64,
    /// Symmetric sweeps: one iteration is a forward sweep followed by a backward sweep (the
    /// symmetric SOR ordering, less biased towards the first rows). Default `false`.
    pub symmetric: bool,
    /// Compute the residual (one `apply_n`, about the cost of one sweep) every this many
    /// iterations; `>= 1`. Default `1`.
    pub check_every: usize,
    /// Step of the friction triplets. Default [`TripletStep::MaxEigen`].
    pub triplet_step: TripletStep,
}

impl Default for PsorOptions {
    fn default() -> Self {
        Self {
            omega: 1.0,
            symmetric: false,
            check_every: 1,
            triplet_step: TripletStep::MaxEigen,
        }
    }
}

impl PsorOptions {
    fn validate(&self) {
        assert!(
            self.omega > 0.0 && self.omega < 2.0,
            "PsorOptions.omega = {} must be in (0, 2)",
            self.omega
        );
        assert!(
            self.check_every >= 1,
            "PsorOptions.check_every must be >= 1"
        );
    }
}

/// Projected SOR solver of the CCP `Y ∋ g ⊥ -(N g + r) ∈ Y°`.
///
/// One iteration sweeps the units in storage order — bilateral rows, box rows, unilateral
/// rows, friction triplets — (then backwards, if [`PsorOptions::symmetric`]). A scalar row
/// `i` does `g_i <- P_i(g_i - omega c_i / N_ii)` with `c_i = (N g + r)_i` (clamped to
/// `[lo, hi]` for box rows, to `>= 0` for unilateral rows, unchanged for bilateral rows); a
/// friction triplet does the same with one step for its three rows ([`TripletStep`]) and
/// the joint Coulomb-cone projection [`project_friction_cone`]. Each change of `g` is applied
/// at once to `w = M^-1 D g` (`row_add_minv`), so later rows see it (Gauss–Seidel).
///
/// Stopping: the common residual [`CcpProblem::residual`] (m/s, RMS of the diagonally scaled
/// projected-gradient step) every [`PsorOptions::check_every`] iterations, against
/// [`SolverSettings::tolerance`]. The iterate with the lowest residual seen is returned.
///
/// Differences from Chrono's `ChSolverPSOR`: no `sharpness` blend; the residual is the common
/// one (Chrono uses the largest violation); friction triplets use a step that guarantees
/// descent ([`TripletStep::MaxEigen`]) unless asked otherwise; a non-finite iterate stops the
/// solve and returns the best finite one.
///
/// Gauss–Seidel is inherently sequential (each row reads the velocity the previous rows just
/// changed), so the sweep runs on one thread; the setup and the residual checks use the
/// parallel problem operations. A graph-coloured parallel PSOR (rows of one colour share no
/// variable block and can be relaxed concurrently) is future work. The result is bit-identical
/// for any rayon thread count.
///
/// Each sweep costs about one `apply_n` (`2 nnz(D)` flops); the solver allocates only when a
/// problem is larger than any it has seen before.
#[derive(Debug, Clone, Default)]
pub struct Psor {
    settings: SolverSettings,
    options: PsorOptions,
    work: CcpWork,
    /// `M^-1 D g`, ndof.
    w: Vec<f64>,
    /// Zero vector of length ndof used to form the triplet blocks of `N`.
    scratch: Vec<f64>,
    /// Step per row (`omega / N_ii`; per triplet, one value on its three rows).
    step: Vec<f64>,
    grad: Vec<f64>,
    best: Vec<f64>,
}

impl Psor {
    /// A solver with the common settings `settings` and default [`PsorOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Set the relaxation factor `omega` (see [`PsorOptions::omega`]).
    ///
    /// # Panics
    /// If `omega` is not in `(0, 2)`.
    pub fn with_omega(mut self, omega: f64) -> Self {
        self.options.omega = omega;
        self.options.validate();
        self
    }

    /// Use symmetric (forward + backward) sweeps.
    pub fn with_symmetric(mut self, symmetric: bool) -> Self {
        self.options.symmetric = symmetric;
        self
    }

    /// Check the residual every `check_every` iterations.
    ///
    /// # Panics
    /// If `check_every == 0`.
    pub fn with_check_every(mut self, check_every: usize) -> Self {
        self.options.check_every = check_every;
        self.options.validate();
        self
    }

    /// Choose the friction-triplet step (see [`TripletStep`]).
    pub fn with_triplet_step(mut self, triplet_step: TripletStep) -> Self {
        self.options.triplet_step = triplet_step;
        self
    }

    /// Set the residual tolerance (m/s).
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.settings.tolerance = tolerance;
        self
    }

    /// Set the iteration cap.
    pub fn with_max_iterations(mut self, max_iterations: usize) -> Self {
        self.settings.max_iterations = max_iterations;
        self
    }

    /// Record the residual history.
    pub fn with_record_history(mut self, record_history: bool) -> Self {
        self.settings.record_history = record_history;
        self
    }

    /// Replace all PSOR-specific options.
    ///
    /// # Panics
    /// If an option is out of range (see [`PsorOptions`]).
    pub fn with_options(mut self, options: PsorOptions) -> Self {
        options.validate();
        self.options = options;
        self
    }

    /// The PSOR-specific options.
    pub fn options(&self) -> &PsorOptions {
        &self.options
    }

    /// The PSOR-specific options, mutable (checked at the start of every solve).
    pub fn options_mut(&mut self) -> &mut PsorOptions {
        &mut self.options
    }

    /// Fill `self.step`: `omega / N_ii` per scalar row, one value per friction triplet.
    fn compute_steps(&mut self, problem: &CcpProblem) {
        let omega = self.options.omega;
        let diag = problem.diag();
        let s = problem.sections();
        let inv = |d: f64| if d > 0.0 { omega / d } else { 0.0 };
        for i in 0..s.friction.start {
            self.step[i] = inv(diag[i]);
        }
        for t in s.friction.clone().step_by(3) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => (diag[t] + diag[t + 1] + diag[t + 2]) / 3.0,
                TripletStep::MaxEigen => triplet_max_eigen(problem, t, &mut self.scratch),
            };
            let h = inv(lambda);
            self.step[t..t + 3].fill(h);
        }
    }

    /// One sweep over all units, forwards or backwards.
    fn sweep(&mut self, problem: &CcpProblem, g: &mut [f64], forward: bool) {
        let s = problem.sections().clone();
        let scalar = 0..s.friction.start;
        let triplets = s.friction.clone().step_by(3);
        if forward {
            for i in scalar {
                self.relax_row(problem, i, g);
            }
            for t in triplets {
                self.relax_triplet(problem, t, g);
            }
        } else {
            for t in triplets.rev() {
                self.relax_triplet(problem, t, g);
            }
            for i in scalar.rev() {
                self.relax_row(problem, i, g);
            }
        }
    }

    /// Relax scalar row `i` (bilateral, box or unilateral).
    #[inline]
    fn relax_row(&mut self, problem: &CcpProblem, i: usize, g: &mut [f64]) {
        let c = problem.row_dot(i, &self.w) + problem.eps()[i] * g[i] + problem.r()[i];
        let z = g[i] - self.step[i] * c;
        let s = problem.sections();
        let new = if i < s.boxed.start {
            z
        } else if i < s.unilateral.start {
            let (lo, hi) = problem.box_bounds();
            let k = i - s.boxed.start;
            z.clamp(lo[k], hi[k])
        } else {
            z.max(0.0)
        };
        let dg = new - g[i];
        if dg != 0.0 {
            problem.row_add_minv(i, dg, &mut self.w);
            g[i] = new;
        }
    }

    /// Relax the friction triplet whose normal row is `t`.
    #[inline]
    fn relax_triplet(&mut self, problem: &CcpProblem, t: usize, g: &mut [f64]) {
        let (eps, r) = (problem.eps(), problem.r());
        let h = self.step[t];
        let mut z = [0.0; 3];
        for j in 0..3 {
            let c = problem.row_dot(t + j, &self.w) + eps[t + j] * g[t + j] + r[t + j];
            z[j] = g[t + j] - h * c;
        }
        let mu = problem.friction_mu()[(t - problem.sections().friction.start) / 3];
        project_friction_cone(mu, &mut z);
        for j in 0..3 {
            let dg = z[j] - g[t + j];
            if dg != 0.0 {
                problem.row_add_minv(t + j, dg, &mut self.w);
                g[t + j] = z[j];
            }
        }
    }
}

/// The largest eigenvalue of the 3x3 block `N_tt = D_t'M^-1 D_t + E_t` of the friction
/// triplet starting at row `t`. `scratch` is a zero vector of length ndof, and is zero again
/// on return.
fn triplet_max_eigen(problem: &CcpProblem, t: usize, scratch: &mut [f64]) -> f64 {
    let diag = problem.diag();
    let mut a = [[0.0; 3]; 3];
    for j in 0..3 {
        a[j][j] = diag[t + j];
    }
    for j in 0..2 {
        problem.row_add_minv(t + j, 1.0, scratch);
        for k in j + 1..3 {
            let njk = problem.row_dot(t + k, scratch);
            a[j][k] = njk;
            a[k][j] = njk;
        }
        problem.row_add_minv(t + j, -1.0, scratch);
    }
    sym3_max_eigen(&a)
}

/// The largest eigenvalue of a symmetric 3x3 matrix, in closed form (trigonometric solution of
/// the characteristic cubic; Smith 1961, "Eigenvalues of a symmetric 3x3 matrix", CACM 4(4)).
pub(crate) fn sym3_max_eigen(a: &[[f64; 3]; 3]) -> f64 {
    let p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if p1 == 0.0 {
        return a[0][0].max(a[1][1]).max(a[2][2]);
    }
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let (b00, b11, b22) = (a[0][0] - q, a[1][1] - q, a[2][2] - q);
    let p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let det = b00 * (b11 * b22 - a[1][2] * a[1][2]) - a[0][1] * (a[0][1] * b22 - a[1][2] * a[0][2])
        + a[0][2] * (a[0][1] * a[1][2] - b11 * a[0][2]);
    let half_det = (det / (p * p * p) / 2.0).clamp(-1.0, 1.0);
    let phi = half_det.acos() / 3.0;
    q + 2.0 * p * phi.cos()
}

impl CcpSolver for Psor {
    fn name(&self) -> &'static str {
        "psor"
    }

    fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    fn settings_mut(&mut self) -> &mut SolverSettings {
        &mut self.settings
    }

    /// Solve by projected SOR; see [`Psor`]. `gamma` is the warm start (non-finite entries
    /// are replaced by 0, then it is projected onto `Y`) and receives the solution.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        assert_eq!(
            gamma.len(),
            problem.n_rows(),
            "gamma.len() must equal problem.n_rows()"
        );
        self.options.validate();
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        self.w.resize(problem.ndof(), 0.0);
        self.scratch.clear();
        self.scratch.resize(problem.ndof(), 0.0);
        for v in [&mut self.step, &mut self.grad, &mut self.best] {
            v.resize(m, 0.0);
        }

        sanitize_and_project(problem, gamma);
        self.compute_steps(problem);
        problem.minv_d(gamma, &mut self.w);
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        let mut best_res = problem.residual(gamma, &self.grad, &mut self.work);
        self.best.copy_from_slice(gamma);
        // Is `grad` the gradient of `best`?
        let mut grad_is_best = true;
        let mut iterations = 0;
        if !best_res.is_finite() || best_res <= tol {
            return final_stats(
                problem,
                gamma,
                &self.grad,
                &mut self.work,
                0,
                tol,
                history.into_records(),
            );
        }

        for it in 1..=max_it {
            iterations = it;
            self.sweep(problem, gamma, true);
            if self.options.symmetric {
                self.sweep(problem, gamma, false);
            }
            if it % self.options.check_every != 0 && it != max_it {
                continue;
            }
            problem.gradient(gamma, &mut self.grad, &mut self.work);
            let res = problem.residual(gamma, &self.grad, &mut self.work);
            history.push(it, res);
            let finite = res.is_finite() && self.w.iter().all(|x| x.is_finite());
            if !finite {
                grad_is_best = false;
                break;
            }
            grad_is_best = res < best_res;
            if grad_is_best {
                best_res = res;
                self.best.copy_from_slice(gamma);
            }
            if res <= tol {
                break;
            }
        }
        gamma.copy_from_slice(&self.best);
        if !grad_is_best {
            problem.gradient(gamma, &mut self.grad, &mut self.work);
        }
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            tol,
            history.into_records(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_eigen_of_known_matrices() {
        let d = [[2.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(sym3_max_eigen(&d), 5.0);
        // all-ones: eigenvalues 3, 0, 0
        let ones = [[1.0; 3]; 3];
        assert!((sym3_max_eigen(&ones) - 3.0).abs() < 1e-12);
        // [[2,1,0],[1,2,0],[0,0,1]]: eigenvalues 3, 1, 1
        let a = [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((sym3_max_eigen(&a) - 3.0).abs() < 1e-12);
        // tridiagonal [[2,-1,0],[-1,2,-1],[0,-1,2]]: max eigenvalue 2 + sqrt(2)
        let t = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]];
        assert!((sym3_max_eigen(&t) - (2.0 + 2f64.sqrt())).abs() < 1e-12);
    }
}
