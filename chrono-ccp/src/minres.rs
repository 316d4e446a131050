//! Preconditioned MINRES for problems whose rows are all bilateral.
//!
//! C. C. Paige and M. A. Saunders, "Solution of sparse indefinite systems of linear
//! equations", SIAM J. Numer. Anal. 12(4), 1975: Lanczos on the preconditioned operator and
//! Givens rotations that minimize the residual norm `|N g + r|_S` over the Krylov space,
//! here with the Jacobi preconditioner `S = diag(N)^-1`. Unlike CG it minimizes the residual
//! monotonically and also handles symmetric indefinite and singular (consistent) systems.
//! The residual vector itself is carried along by recurrence (`N w` is updated with `w`),
//! so the stopping test is the common residual, not only its preconditioned estimate.

use chrono_core::descriptor::{CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings};

use crate::cg::{KrylovOptions, MAX_REPLACEMENTS, check_bilateral, relative_residual};
use crate::util::{
    History, axpy, check_gamma_len, empty_stats, fill_with, final_stats, sanitize_and_project,
};

/// Preconditioned MINRES on `N g = -r`; see the [module documentation](self).
///
/// One iteration: one `apply_n` and two fixed-order reductions; parallel and bit-identical
/// for any thread count. On a problem with non-bilateral rows `solve` does nothing (0
/// iterations, not converged), like [`crate::Cg`].
#[derive(Debug, Clone, Default)]
pub struct Minres {
    settings: SolverSettings,
    options: KrylovOptions,
    work: CcpWork,
    v: Vec<f64>,
    y: Vec<f64>,
    r1: Vec<f64>,
    r2: Vec<f64>,
    w: Vec<f64>,
    w1: Vec<f64>,
    w2: Vec<f64>,
    av: Vec<f64>,
    aw: Vec<f64>,
    aw1: Vec<f64>,
    aw2: Vec<f64>,
    res: Vec<f64>,
    grad: Vec<f64>,
}

impl Minres {
    /// A solver with the common settings and default [`KrylovOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Replace the Krylov options.
    pub fn with_options(mut self, options: KrylovOptions) -> Self {
        self.options = options;
        self
    }
}

impl CcpSolver for Minres {
    solver_accessors!("minres");

    /// Solve `N g = -r` by preconditioned MINRES from the warm start `gamma`.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        sanitize_and_project(problem, gamma);
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.v,
            &mut self.y,
            &mut self.r1,
            &mut self.r2,
            &mut self.w,
            &mut self.w1,
            &mut self.w2,
            &mut self.av,
            &mut self.aw,
            &mut self.aw1,
            &mut self.aw2,
            &mut self.res,
            &mut self.grad,
        ] {
            v.clear();
            v.resize(m, 0.0);
        }
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        let mut n_apply = 1;
        if check_bilateral(problem).is_err() {
            let mut st = final_stats(
                problem,
                gamma,
                &self.grad,
                &mut self.work,
                0,
                n_apply,
                tol,
                Vec::new(),
            );
            st.converged = false;
            return st;
        }
        let s = problem.scales();
        let pre = self.options.preconditioned;
        let prec = |i: usize, x: f64| if pre { s[i] * x } else { x };
        let rel_tol = self.options.relative_tolerance;
        let r_norm = problem.dot(problem.r(), problem.r(), &mut self.work).sqrt();

        // r1 = b - A x with b = -r: the residual of N g = -r is -grad.
        let grad = &self.grad;
        fill_with(&mut self.r1, |i| -grad[i]);
        self.r2.copy_from_slice(&self.r1);
        self.res.copy_from_slice(&self.r1);
        let r1 = &self.r1;
        fill_with(&mut self.y, |i| prec(i, r1[i]));
        let mut beta1 = problem.dot(&self.r1, &self.y, &mut self.work);
        let mut rr = problem.dot(&self.res, &self.res, &mut self.work);
        let done = |rr: f64| {
            (rr / m as f64).sqrt() <= tol || (rel_tol > 0.0 && rr.sqrt() <= rel_tol * r_norm)
        };
        let mut iterations = 0;
        let mut replacements = 0;
        if beta1 > 0.0 && beta1.is_finite() && !done(rr) {
            beta1 = beta1.sqrt();
            let (mut oldb, mut beta) = (0.0, beta1);
            let (mut dbar, mut epsln, mut phibar) = (0.0, 0.0, beta1);
            let (mut cs, mut sn) = (-1.0f64, 0.0f64);
            for it in 1..=max_it {
                iterations = it;
                let sc = 1.0 / beta;
                let y = &self.y;
                fill_with(&mut self.v, |i| sc * y[i]);
                problem.apply_n(&self.v, &mut self.av, &mut self.work);
                n_apply += 1;
                self.y.copy_from_slice(&self.av);
                if it >= 2 {
                    axpy(&mut self.y, -beta / oldb, &self.r1);
                }
                let alfa = problem.dot(&self.v, &self.y, &mut self.work);
                axpy(&mut self.y, -alfa / beta, &self.r2);
                std::mem::swap(&mut self.r1, &mut self.r2);
                self.r2.copy_from_slice(&self.y);
                let r2 = &self.r2;
                fill_with(&mut self.y, |i| prec(i, r2[i]));
                oldb = beta;
                let b2 = problem.dot(&self.r2, &self.y, &mut self.work);
                beta = b2.max(0.0).sqrt();
                let oldeps = epsln;
                let delta = cs * dbar + sn * alfa;
                let gbar = sn * dbar - cs * alfa;
                epsln = sn * beta;
                dbar = -cs * beta;
                let gamma_k = gbar.hypot(beta).max(f64::MIN_POSITIVE);
                cs = gbar / gamma_k;
                sn = beta / gamma_k;
                let phi = cs * phibar;
                phibar *= sn;
                let denom = 1.0 / gamma_k;
                // w = (v - oldeps w1 - delta w2) / gamma, and N w likewise.
                std::mem::swap(&mut self.w1, &mut self.w2);
                std::mem::swap(&mut self.w2, &mut self.w);
                std::mem::swap(&mut self.aw1, &mut self.aw2);
                std::mem::swap(&mut self.aw2, &mut self.aw);
                let (v, w1, w2) = (&self.v, &self.w1, &self.w2);
                fill_with(&mut self.w, |i| {
                    (v[i] - oldeps * w1[i] - delta * w2[i]) * denom
                });
                let (av, aw1, aw2) = (&self.av, &self.aw1, &self.aw2);
                fill_with(&mut self.aw, |i| {
                    (av[i] - oldeps * aw1[i] - delta * aw2[i]) * denom
                });
                axpy(gamma, phi, &self.w);
                axpy(&mut self.res, -phi, &self.aw);
                rr = problem.dot(&self.res, &self.res, &mut self.work);
                let rms = (rr / m as f64).sqrt();
                history.push(it, rms, n_apply, || {
                    let (res, r) = (&self.res, problem.r());
                    chrono_core::descriptor::reduce::sum_by(m, &mut self.work.partials, |i| {
                        0.5 * gamma[i] * (r[i] - res[i])
                    })
                });
                if !rr.is_finite() || beta == 0.0 {
                    break;
                }
                if done(rr) {
                    // Check the true residual (the recurrence drifts by rounding); if they
                    // disagree, carry on with the true one.
                    problem.gradient(gamma, &mut self.grad, &mut self.work);
                    n_apply += 1;
                    let grad = &self.grad;
                    fill_with(&mut self.res, |i| -grad[i]);
                    rr = problem.dot(&self.res, &self.res, &mut self.work);
                    if done(rr) || replacements == MAX_REPLACEMENTS {
                        break;
                    }
                    replacements += 1;
                }
            }
        }
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        n_apply += 1;
        let mut st = final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            n_apply,
            tol,
            history.into_records(),
        );
        if rel_tol > 0.0 && relative_residual(problem, &self.grad, &mut self.work) <= rel_tol {
            st.converged = true;
        }
        st
    }
}
