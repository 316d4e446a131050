//! Barzilai–Borwein / spectral projected gradient (SPG).
//!
//! E. G. Birgin, J. M. Martínez, M. Raydan, "Nonmonotone spectral projected gradient
//! methods on convex sets", SIAM J. Optim. 10(4), 2000 (algorithm SPG2), with the diagonal
//! metric `S = diag(N)^-1` (cone-averaged) as in Chrono's `ChSolverBB` (Tasora et al.), on
//! `min f(g) = 1/2 g'N g + r'g, g ∈ Y`:
//!
//! ```text
//! d = P_Y(g - alpha S grad) - g                       (feasible direction, grad'd <= 0)
//! lambda = 1 if f(g + d) <= max(last M values of f) + sigma grad'd  (non-monotone Armijo)
//!          else the exact minimizer -grad'd / d'N d of f along d (it satisfies the test)
//! s = lambda d,  y = lambda N d,  g += s,  grad += y
//! alpha = s'S^-1 s / s'y  (BB1, even iterations)  or  s'y / y'S y  (BB2, odd)
//! ```
//!
//! `f` is quadratic, so the line search is exact and free: one `apply_n` (`N d`) per
//! iteration whatever happens. Fixes Chrono's flaw (its non-monotone reference starts at
//! `1e30` and only grows, so the Armijo test never fails): the reference here is the true
//! maximum of the last `M` objective values.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings, reduce::sum_by,
};

use crate::util::{
    History, axpy, check_gamma_len, empty_stats, fill_with, final_stats, power_lipschitz,
    sanitize_and_project,
};

/// Length of the non-monotone memory (values of `f` kept).
pub const NONMONOTONE_MEMORY: usize = 10;

/// Armijo parameter `sigma` of the non-monotone test.
pub const ARMIJO_SIGMA: f64 = 1e-4;

/// The gradient is recomputed from scratch every this many iterations (it is otherwise
/// updated as `grad += lambda N d`, which accumulates rounding).
pub const REFRESH_EVERY: usize = 50;

/// Barzilai–Borwein spectral projected gradient solver; see the [module documentation](self).
///
/// Parallel (element-wise loops, fixed-order reductions: bit-identical for any thread count),
/// allocation-free after the first solve of a given size, returns the iterate with the
/// lowest common residual ([`CcpProblem::residual`]).
#[derive(Debug, Clone, Default)]
pub struct BarzilaiBorwein {
    settings: SolverSettings,
    work: CcpWork,
    g: Vec<f64>,
    grad: Vec<f64>,
    d: Vec<f64>,
    nd: Vec<f64>,
    best: Vec<f64>,
}

impl BarzilaiBorwein {
    /// A solver with the common settings.
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }
}

impl CcpSolver for BarzilaiBorwein {
    solver_accessors!("bb");

    /// Solve by spectral projected gradient; `gamma` is the warm start and receives the
    /// best iterate.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.g,
            &mut self.grad,
            &mut self.d,
            &mut self.nd,
            &mut self.best,
        ] {
            v.resize(m, 0.0);
        }
        let s = problem.scales();
        sanitize_and_project(problem, gamma);
        self.g.copy_from_slice(gamma);
        self.best.copy_from_slice(gamma);
        problem.gradient(&self.g, &mut self.grad, &mut self.work);
        let mut n_apply = 1;
        let mut best_res = problem.residual(&self.g, &self.grad, &mut self.work);
        let mut best_is_current = true;
        let mut iterations = 0;
        if best_res.is_finite() && best_res > tol {
            // First step 1/L (L = lambda_max of the scaled N): a safe gradient step.
            let l = power_lipschitz(
                problem,
                s,
                2,
                &mut self.d,
                &mut self.nd,
                &mut self.best,
                &mut self.work,
            );
            n_apply += 2;
            self.best.copy_from_slice(&self.g);
            let (alpha_min, alpha_max) = (1e-10 / l, 1e10 / l);
            let mut alpha = 1.0 / l;
            let mut f = problem.objective_from_gradient(&self.g, &self.grad, &mut self.work);
            let mut memory = [f64::NEG_INFINITY; NONMONOTONE_MEMORY];
            memory[0] = f;
            for it in 1..=max_it {
                iterations = it;
                let (g, gr) = (&self.g, &self.grad);
                fill_with(&mut self.d, |i| g[i] - alpha * s[i] * gr[i]);
                problem.project(&mut self.d);
                axpy(&mut self.d, -1.0, g);
                problem.apply_n(&self.d, &mut self.nd, &mut self.work);
                n_apply += 1;
                let (d, nd) = (&self.d, &self.nd);
                let gd = sum_by(m, &mut self.work.partials, |i| gr[i] * d[i]);
                let dnd = sum_by(m, &mut self.work.partials, |i| d[i] * nd[i]);
                if !(gd.is_finite() && dnd.is_finite()) {
                    history.push(it, f64::NAN, n_apply, || f64::NAN);
                    break;
                }
                if dnd == 0.0 && d.iter().all(|x| *x == 0.0) {
                    // The projected step does not move: g is stationary.
                    history.push(it, best_res, n_apply, || f);
                    break;
                }
                let fmax = memory.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                // Near the solution rounding can make grad'd >= 0 for a genuine projected
                // step (the cone projection's round-off dominates a 1e-20 decrease): then
                // the full step is taken, as a projected gradient step.
                let mut lambda = 1.0;
                if gd < 0.0 && f + gd + 0.5 * dnd > fmax + ARMIJO_SIGMA * gd && dnd > 0.0 {
                    lambda = (-gd / dnd).min(1.0);
                }
                f += lambda * gd + 0.5 * lambda * lambda * dnd;
                memory[it % NONMONOTONE_MEMORY] = f;
                let (d, nd) = (&self.d, &self.nd);
                axpy(&mut self.g, lambda, d);
                if it % REFRESH_EVERY == 0 {
                    problem.gradient(&self.g, &mut self.grad, &mut self.work);
                    n_apply += 1;
                    f = problem.objective_from_gradient(&self.g, &self.grad, &mut self.work);
                } else {
                    axpy(&mut self.grad, lambda, nd);
                }
                let res = problem.residual(&self.g, &self.grad, &mut self.work);
                history.push(it, res, n_apply, || f);
                if !res.is_finite() {
                    best_is_current = false;
                    break;
                }
                best_is_current = res < best_res;
                if best_is_current {
                    best_res = res;
                    self.best.copy_from_slice(&self.g);
                }
                if res <= tol {
                    break;
                }
                // Spectral step in the metric S^-1: s = lambda d, y = lambda N d.
                let sty = lambda * lambda * dnd;
                alpha = if sty <= 0.0 {
                    alpha_max
                } else if it % 2 == 0 {
                    let ss = sum_by(m, &mut self.work.partials, |i| {
                        if s[i] > 0.0 { d[i] * d[i] / s[i] } else { 0.0 }
                    });
                    ss / dnd
                } else {
                    let ys = sum_by(m, &mut self.work.partials, |i| nd[i] * nd[i] * s[i]);
                    if ys > 0.0 { dnd / ys } else { alpha_max }
                };
                alpha = alpha.clamp(alpha_min, alpha_max);
            }
        }
        gamma.copy_from_slice(&self.best);
        if !best_is_current {
            problem.gradient(gamma, &mut self.grad, &mut self.work);
            n_apply += 1;
        }
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            n_apply,
            tol,
            history.into_records(),
        )
    }
}
