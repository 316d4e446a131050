//! Projected Jacobi with a safe step.
//!
//! Every row (cone block) is updated at once from the same iterate with its diagonal step,
//! `g <- P_Y(g - omega S (N g + r))`, `S = diag(N)^-1` cone-averaged — Chrono's
//! `ChSolverPJacobi` (Anitescu and Tasora 2010, Comput. Optim. Appl. 47(2)) — which is the
//! projected gradient method in the metric `S^-1`. Chrono leaves `omega` to the user (its
//! docs suggest 0.2) and the method diverges when `omega > 2 / lambda_max(S^1/2 N S^1/2)`
//! (many rows sharing a body). Here `omega = 1 / L` with `L` from a power iteration and
//! enlarged by backtracking until the step satisfies the descent condition
//! `d'N d <= L d'S^-1 d` (`d` the update): the objective then decreases every iteration
//! (Bertsekas, "Nonlinear Programming", 3rd ed., prop. 6.1.2), so the method cannot diverge.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings, reduce::sum_by,
};
use serde::{Deserialize, Serialize};

use crate::apgd::MAX_BACKTRACKS;
use crate::util::{
    History, check_gamma_len, empty_stats, fill_with, final_stats, power_lipschitz,
    sanitize_and_project,
};

/// Options of [`Jacobi`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct JacobiOptions {
    /// A fixed relaxation `omega` (Chrono's PJacobi: no safeguard, may diverge) instead of
    /// the safe step. Default `None` (safe step `1/L` with backtracking).
    pub omega: Option<f64>,
    /// Power iterations for the initial `L` (each one `apply_n`; `>= 1`). Default 10.
    pub power_iterations: usize,
}

impl Default for JacobiOptions {
    fn default() -> Self {
        Self {
            omega: None,
            power_iterations: 10,
        }
    }
}

/// Projected Jacobi solver of the CCP; see the [module documentation](self).
///
/// One iteration costs one `apply_n` (plus one per backtrack, which happens only while `L`
/// is still too small) and is fully parallel (element-wise loops and fixed-order
/// reductions: bit-identical for any thread count). Returns the iterate with the lowest
/// common residual ([`CcpProblem::residual`]).
#[derive(Debug, Clone, Default)]
pub struct Jacobi {
    settings: SolverSettings,
    options: JacobiOptions,
    work: CcpWork,
    g: Vec<f64>,
    g_new: Vec<f64>,
    grad: Vec<f64>,
    grad_new: Vec<f64>,
    best: Vec<f64>,
}

impl Jacobi {
    /// A solver with the common settings and default [`JacobiOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Replace the Jacobi-specific options.
    ///
    /// # Panics
    /// If `power_iterations == 0` or `omega` is not finite and > 0.
    pub fn with_options(mut self, options: JacobiOptions) -> Self {
        validate(&options);
        self.options = options;
        self
    }

    /// The Jacobi-specific options.
    pub fn options(&self) -> &JacobiOptions {
        &self.options
    }
}

fn validate(o: &JacobiOptions) {
    assert!(
        o.power_iterations >= 1,
        "JacobiOptions.power_iterations must be >= 1"
    );
    if let Some(w) = o.omega {
        assert!(
            w.is_finite() && w > 0.0,
            "JacobiOptions.omega = {w} must be finite and > 0"
        );
    }
}

impl CcpSolver for Jacobi {
    solver_accessors!("jacobi");

    /// Solve by projected Jacobi; `gamma` is the warm start and receives the best iterate.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        validate(&self.options);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.g,
            &mut self.g_new,
            &mut self.grad,
            &mut self.grad_new,
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
        let mut iterations = 0;
        let mut best_has_grad = true;
        if best_res.is_finite() && best_res > tol {
            let (mut l, safe) = match self.options.omega {
                Some(w) => (1.0 / w, false),
                None => {
                    n_apply += self.options.power_iterations;
                    let l = power_lipschitz(
                        problem,
                        s,
                        self.options.power_iterations,
                        &mut self.g_new,
                        &mut self.grad_new,
                        &mut self.best,
                        &mut self.work,
                    );
                    self.best.copy_from_slice(&self.g);
                    (l, true)
                }
            };
            for it in 1..=max_it {
                iterations = it;
                let mut ok = false;
                for _ in 0..=MAX_BACKTRACKS {
                    let (g, gr) = (&self.g, &self.grad);
                    let t = 1.0 / l;
                    fill_with(&mut self.g_new, |i| g[i] - t * s[i] * gr[i]);
                    problem.project(&mut self.g_new);
                    problem.gradient(&self.g_new, &mut self.grad_new, &mut self.work);
                    n_apply += 1;
                    if !safe {
                        ok = true;
                        break;
                    }
                    let (gn, grn) = (&self.g_new, &self.grad_new);
                    let dnd = sum_by(m, &mut self.work.partials, |i| {
                        (gn[i] - g[i]) * (grn[i] - gr[i])
                    });
                    let dsd = sum_by(m, &mut self.work.partials, |i| {
                        let d = gn[i] - g[i];
                        if s[i] > 0.0 { d * d / s[i] } else { 0.0 }
                    });
                    if !(dnd.is_finite() && dsd.is_finite()) {
                        break;
                    }
                    if dnd <= l * dsd {
                        ok = true;
                        break;
                    }
                    l *= 2.0;
                }
                let res = if ok {
                    problem.residual(&self.g_new, &self.grad_new, &mut self.work)
                } else {
                    f64::NAN
                };
                history.push(it, res, n_apply, || {
                    problem.objective_from_gradient(&self.g_new, &self.grad_new, &mut self.work)
                });
                if !res.is_finite() {
                    break;
                }
                std::mem::swap(&mut self.g, &mut self.g_new);
                std::mem::swap(&mut self.grad, &mut self.grad_new);
                best_has_grad = res < best_res;
                if best_has_grad {
                    best_res = res;
                    self.best.copy_from_slice(&self.g);
                }
                if res <= tol {
                    break;
                }
            }
        }
        gamma.copy_from_slice(&self.best);
        if !best_has_grad {
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
