//! Preconditioned conjugate gradients for problems whose rows are all bilateral.
//!
//! With only free rows the CCP is the linear system `N g = -r` (`N = D'M^-1 D + E`
//! symmetric positive semi-definite): density constraints of constraint fluids, joints.
//! Hestenes and Stiefel 1952 (J. Res. NBS 49(6)), with the Jacobi preconditioner
//! `S = diag(N)^-1`; Saad, "Iterative Methods for Sparse Linear Systems", 2nd ed., alg. 9.1.
//! CG converges for consistent semi-definite systems too (redundant joints), in the range
//! of `N`.

use chrono_core::descriptor::{CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings};
use serde::{Deserialize, Serialize};

use crate::util::{History, axpy, check_gamma_len, empty_stats, fill_with, final_stats};

/// Times a Krylov solver replaces its recurrence residual by the true one when the two
/// disagree about convergence, before it gives up.
pub const MAX_REPLACEMENTS: usize = 5;

/// Options of the Krylov solvers ([`Cg`], [`crate::Minres`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct KrylovOptions {
    /// Also stop when the relative residual `|N g + r| / |r|` is below this (0: only the
    /// common residual, [`SolverSettings::tolerance`], is used). Default 0.
    pub relative_tolerance: f64,
    /// Use the Jacobi preconditioner `diag(N)^-1`. Default `true`.
    pub preconditioned: bool,
}

impl Default for KrylovOptions {
    fn default() -> Self {
        Self {
            relative_tolerance: 0.0,
            preconditioned: true,
        }
    }
}

/// Why a Krylov solver refused a problem.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NotBilateral {
    /// Rows that are not bilateral (box, unilateral, friction, rolling).
    pub other_rows: usize,
    /// Total rows.
    pub rows: usize,
}

impl std::fmt::Display for NotBilateral {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "problem has {} non-bilateral rows of {}: CG/MINRES solve only problems whose rows \
             are all bilateral (use TwoPhase to combine them with a CCP solver)",
            self.other_rows, self.rows
        )
    }
}

impl std::error::Error for NotBilateral {}

/// Check that every row of `problem` is bilateral.
pub fn check_bilateral(problem: &CcpProblem) -> Result<(), NotBilateral> {
    if problem.is_bilateral_only() {
        Ok(())
    } else {
        Err(NotBilateral {
            other_rows: problem.n_rows() - problem.sections().bilateral.len(),
            rows: problem.n_rows(),
        })
    }
}

/// The true relative residual `|N g + r| / |r|` from a gradient (0 when `r = 0` and the
/// gradient is zero).
pub fn relative_residual(problem: &CcpProblem, grad: &[f64], work: &mut CcpWork) -> f64 {
    let num = problem.dot(grad, grad, work).sqrt();
    let den = problem.dot(problem.r(), problem.r(), work).sqrt();
    if den > 0.0 {
        num / den
    } else if num == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Preconditioned CG on `N g = -r`; see the [module documentation](self).
///
/// One iteration: one `apply_n` and three fixed-order reductions; parallel and
/// bit-identical for any thread count. The residual vector is updated by recurrence; the
/// returned statistics use the true gradient.
///
/// On a problem with non-bilateral rows [`solve`](CcpSolver::solve) does nothing (0
/// iterations, `converged = false`, `gamma` only sanitized and projected); check first with
/// [`check_bilateral`], or use [`crate::TwoPhase`].
#[derive(Debug, Clone, Default)]
pub struct Cg {
    settings: SolverSettings,
    options: KrylovOptions,
    work: CcpWork,
    res: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    ap: Vec<f64>,
    grad: Vec<f64>,
}

impl Cg {
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

impl CcpSolver for Cg {
    solver_accessors!("cg");

    /// Solve `N g = -r` by PCG from the warm start `gamma`.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        crate::util::sanitize_and_project(problem, gamma);
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.res,
            &mut self.z,
            &mut self.p,
            &mut self.ap,
            &mut self.grad,
        ] {
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
        let rel_tol = self.options.relative_tolerance;
        let r_norm = problem.dot(problem.r(), problem.r(), &mut self.work).sqrt();
        let grad = &self.grad;
        fill_with(&mut self.res, |i| -grad[i]);
        let res = &self.res;
        fill_with(&mut self.z, |i| if pre { s[i] * res[i] } else { res[i] });
        self.p.copy_from_slice(&self.z);
        let mut rz = problem.dot(&self.res, &self.z, &mut self.work);
        let mut rr = problem.dot(&self.res, &self.res, &mut self.work);
        let done = |rr: f64| {
            let rms = (rr / m as f64).sqrt();
            rms <= tol || (rel_tol > 0.0 && rr.sqrt() <= rel_tol * r_norm)
        };
        let mut iterations = 0;
        let mut replacements = 0;
        if !done(rr) && rr.is_finite() {
            for it in 1..=max_it {
                iterations = it;
                problem.apply_n(&self.p, &mut self.ap, &mut self.work);
                n_apply += 1;
                let pap = problem.dot(&self.p, &self.ap, &mut self.work);
                if !(pap > 0.0 && pap.is_finite()) {
                    break; // converged in the range of N, or breakdown
                }
                let alpha = rz / pap;
                axpy(gamma, alpha, &self.p);
                axpy(&mut self.res, -alpha, &self.ap);
                rr = problem.dot(&self.res, &self.res, &mut self.work);
                let rms = (rr / m as f64).sqrt();
                history.push(it, rms, n_apply, || {
                    // f = 1/2 g'(N g + r) + 1/2 r'g with N g + r = -res.
                    let (res, r) = (&self.res, problem.r());
                    chrono_core::descriptor::reduce::sum_by(m, &mut self.work.partials, |i| {
                        0.5 * gamma[i] * (r[i] - res[i])
                    })
                });
                if !rr.is_finite() {
                    break;
                }
                if done(rr) {
                    // The recurrence says converged: check the true residual. If rounding
                    // has made the two drift apart, replace the residual by the true one
                    // and restart (residual replacement, van der Vorst and Ye 2000).
                    problem.gradient(gamma, &mut self.grad, &mut self.work);
                    n_apply += 1;
                    let grad = &self.grad;
                    fill_with(&mut self.res, |i| -grad[i]);
                    rr = problem.dot(&self.res, &self.res, &mut self.work);
                    if done(rr) || replacements == MAX_REPLACEMENTS {
                        break;
                    }
                    replacements += 1;
                    let res = &self.res;
                    fill_with(&mut self.z, |i| if pre { s[i] * res[i] } else { res[i] });
                    self.p.copy_from_slice(&self.z);
                    rz = problem.dot(&self.res, &self.z, &mut self.work);
                    continue;
                }
                let res = &self.res;
                fill_with(&mut self.z, |i| if pre { s[i] * res[i] } else { res[i] });
                let rz_new = problem.dot(&self.res, &self.z, &mut self.work);
                let beta = rz_new / rz;
                rz = rz_new;
                let z = &self.z;
                let p = &mut self.p;
                if p.len() >= crate::util::PAR_MIN {
                    use rayon::prelude::*;
                    p.par_iter_mut()
                        .zip(z.par_iter())
                        .for_each(|(p, z)| *p = z + beta * *p);
                } else {
                    p.iter_mut().zip(z).for_each(|(p, z)| *p = z + beta * *p);
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
