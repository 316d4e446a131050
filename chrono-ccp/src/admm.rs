//! ADMM with a direct solve of the proximal system: a CCP solver whose convergence does not
//! degrade with mass ratios (heavy bodies on light ones, tall stacks of growing mass).
//!
//! The CCP `min 1/2 g'N g + r'g, g ∈ Y` is split as `g = z`, `z ∈ Y` (Boyd et al.,
//! "Distributed optimization and statistical learning via the alternating direction method
//! of multipliers", Found. Trends Mach. Learn. 3(1), 2011, sec. 5; for cone complementarity
//! problems of nonsmooth dynamics: A. Tasora, D. Mangoni, S. Benatti, R. Garziera, "Solving
//! variational inequalities and cone complementarity problems in nonsmooth dynamics using
//! the alternating direction method of multipliers", Int. J. Numer. Methods Eng. 122(16),
//! 2021). With the penalty `R = diag(rho_i)` and the scaled multiplier `u`, one iteration is
//!
//! ```text
//! (N + R) g = R (z - u) - r          (a direct solve: the factor is kept while R is)
//! g^ = alpha g + (1 - alpha) z        (over-relaxation, alpha = AdmmOptions::relaxation)
//! z+ = P_Y(g^ + u),   u+ = u + g^ - z+
//! ```
//!
//! Over-relaxation with `alpha` in (0, 2) keeps the method's convergence (Eckstein and
//! Bertsekas, "On the Douglas–Rachford splitting method and the proximal point algorithm for
//! maximal monotone operators", Math. Prog. 55, 1992; Boyd et al. sec. 3.4.3); `alpha` =
//! 1.6 is OSQP's default (Stellato et al. 2020, sec. 5). Measured 2026-12-07: on the
//! heavy-on-light local blocks of `hmmwv-granular --set method=nsc` 1.6 cut the ADMM
//! iterations by 39 % (docs/validation-vehicle.md), so [`crate::LocalDirect`] uses it; on
//! the box stacks it does not help (41 against 40 iterations on the test stack with a mass
//! ratio of 10 per level, 13.8 against 11.0 per step in `rigid-stack-heavy`), so plain
//! ADMM (1) stays this solver's default.
//!
//! Why it suits heavy-on-light contact: a projected gradient method (APGD, PSOR) needs
//! `O(sqrt(kappa))` (or `O(kappa)`) iterations where `kappa` grows with the mass ratio (the
//! soft mode of a heavy body pressing a light one into the ground has an eigenvalue of
//! order `1/M` against `1/m` for the light body's own modes). Here `N` enters only through
//! the exact solve, so in every eigendirection the error of the linear part contracts by
//! `rho / (lambda + rho)` per iteration: with `rho` at or below the soft modes' `lambda`
//! the ill-conditioned directions converge as fast as the well-conditioned ones, and the
//! iterations count only the identification of the active set and of the sliding contacts.
//!
//! The penalty is `rho_i = rho diag(N)_i` with `diag(N)` averaged over each cone's rows
//! ([`CcpProblem::residual_scale`]: ADMM on the Jacobi-scaled problem, and the projection in
//! that metric stays the Euclidean one on each cone), bilateral rows get the tiny
//! [`AdmmOptions::rho_bilateral`] (they are enforced by the solve itself). `rho` is adapted
//! every [`AdmmOptions::adapt_every`] iterations by residual balancing (Boyd et al. sec.
//! 3.4.1, in the normalized form of Stellato et al., "OSQP: an operator splitting solver for
//! quadratic programs", Math. Prog. Comp. 12, 2020, sec. 5.2): `rho <- rho sqrt(ratio)` with
//! `ratio` the relative primal over the relative dual residual, applied when the factor
//! exceeds [`AdmmOptions::adapt_threshold`] (each change refactors numerically).
//!
//! Stopping: the iterate `z` (always in `Y`) is checked with the common residual
//! ([`CcpProblem::residual`]), one product `N z + r` per iteration; the best iterate is
//! returned. Cost: the sparse `N` (rows sharing a body) factored by faer's sparse Cholesky
//! with the symbolic analysis kept while the rows touch the same bodies; problems with more
//! than [`AdmmOptions::max_rows`] rows go to the fallback solver (APGD).
//! Warm start: `z` from the given impulses, the multiplier from their gradient,
//! `u = -R^-1 (N z + r)` (the multiplier of a solution), so a converged warm start costs no
//! iteration.

use chrono_core::descriptor::{CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings};
use serde::{Deserialize, Serialize};

use crate::Apgd;
use crate::sparse_bilateral::SparseBilateral;
use crate::util::{History, check_gamma_len, empty_stats, final_stats, sanitize_and_project};

/// Options of [`Admm`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct AdmmOptions {
    /// Initial penalty relative to the Jacobi metric, `rho_i = rho diag(N)_i`. Default
    /// `0.1` (Tasora et al. 2021's default step, here in the scaled problem).
    pub rho: f64,
    /// Penalty of bilateral rows relative to their diagonal: tiny, so the solve enforces
    /// them (their projection is the identity). Default `1e-8`.
    pub rho_bilateral: f64,
    /// Adapt `rho` after this many iterations (0: never); the interval doubles after each
    /// change. Default `5`.
    pub adapt_every: usize,
    /// Change `rho` only when the balancing factor is outside `[1/t, t]`. Default `2`.
    pub adapt_threshold: f64,
    /// Largest factor applied to `rho` in one adaptation (and its inverse the smallest).
    /// Default `50`.
    pub adapt_clamp: f64,
    /// Problems with more rows than this go to the fallback solver. Default `20 000`.
    pub max_rows: usize,
    /// Over-relaxation `alpha` of the split variable, in `(0, 2)`; 1 is plain ADMM.
    /// Default `1` (see the module documentation for where 1.6 pays).
    pub relaxation: f64,
}

impl Default for AdmmOptions {
    fn default() -> Self {
        Self {
            rho: 0.1,
            rho_bilateral: 1e-8,
            adapt_every: 5,
            adapt_threshold: 2.0,
            adapt_clamp: 50.0,
            max_rows: 20_000,
            relaxation: 1.0,
        }
    }
}

/// The ADMM solver (see the [module documentation](self)).
pub struct Admm {
    settings: SolverSettings,
    options: AdmmOptions,
    fallback: Box<dyn CcpSolver>,
    rows: Vec<usize>,
    factor: SparseBilateral,
    /// The Jacobi metric `diag(N)` (cone-averaged) of each row.
    d: Vec<f64>,
    /// The penalty of each row.
    rho: Vec<f64>,
    /// The scale of `rho` for non-bilateral rows.
    rho_scale: f64,
    g: Vec<f64>,
    z: Vec<f64>,
    z_old: Vec<f64>,
    u: Vec<f64>,
    rhs: Vec<f64>,
    grad: Vec<f64>,
    best: Vec<f64>,
    best_grad: Vec<f64>,
    work: CcpWork,
    /// Factorizations in the last solve (numeric ones; the symbolic is kept across solves).
    factorizations: usize,
}

impl Admm {
    /// An ADMM solver with `settings` and APGD with the same settings as the fallback.
    pub fn new(settings: SolverSettings) -> Self {
        let fallback = Box::new(Apgd::new(settings.clone()));
        Self {
            settings,
            options: AdmmOptions::default(),
            fallback,
            rows: Vec::new(),
            factor: SparseBilateral::default(),
            d: Vec::new(),
            rho: Vec::new(),
            rho_scale: 0.0,
            g: Vec::new(),
            z: Vec::new(),
            z_old: Vec::new(),
            u: Vec::new(),
            rhs: Vec::new(),
            grad: Vec::new(),
            best: Vec::new(),
            best_grad: Vec::new(),
            work: CcpWork::default(),
            factorizations: 0,
        }
    }

    settings_builders!();

    /// Set the options.
    ///
    /// # Panics
    /// If a value is out of range (`rho`, `rho_bilateral` not positive and finite,
    /// `relaxation` outside `(0, 2)`, `adapt_threshold` or `adapt_clamp` below 1): a
    /// caller's bug.
    pub fn with_options(mut self, options: AdmmOptions) -> Self {
        assert!(
            options.rho.is_finite() && options.rho > 0.0,
            "AdmmOptions::rho must be > 0, got {}",
            options.rho
        );
        assert!(
            options.rho_bilateral.is_finite() && options.rho_bilateral > 0.0,
            "AdmmOptions::rho_bilateral must be > 0, got {}",
            options.rho_bilateral
        );
        assert!(
            options.relaxation > 0.0 && options.relaxation < 2.0,
            "AdmmOptions::relaxation must be in (0, 2), got {}",
            options.relaxation
        );
        assert!(
            options.adapt_threshold >= 1.0 && options.adapt_clamp >= 1.0,
            "AdmmOptions::adapt_threshold and adapt_clamp must be >= 1, got {} and {}",
            options.adapt_threshold,
            options.adapt_clamp
        );
        self.options = options;
        self
    }

    /// The options.
    pub fn options(&self) -> &AdmmOptions {
        &self.options
    }

    /// Numeric factorizations of the proximal matrix in the last solve (1 + the `rho`
    /// changes).
    pub fn factorizations(&self) -> usize {
        self.factorizations
    }

    /// Set the penalties for `rho_scale` and factor `N + R`.
    fn refactor(&mut self, problem: &CcpProblem, rho_scale: f64) -> Result<(), ()> {
        let bil = problem.sections().bilateral.clone();
        self.rho_scale = rho_scale;
        for (i, (r, &d)) in self.rho.iter_mut().zip(&self.d).enumerate() {
            *r = d * if bil.contains(&i) {
                self.options.rho_bilateral
            } else {
                rho_scale
            };
        }
        self.factorizations += 1;
        self.factor
            .factor_shifted(problem, &self.rows, Some(&self.rho))
            .map_err(drop)
    }

    /// Keep `z` (and its gradient) as the best iterate.
    fn keep_best(&mut self) {
        self.best.copy_from_slice(&self.z);
        self.best_grad.copy_from_slice(&self.grad);
    }
}

/// Euclidean norm (the residual balancing's norms; no reduction order matters for the
/// iterates beyond the rho decisions, which are made from these sums on one thread).
fn norm(x: impl Iterator<Item = f64>) -> f64 {
    x.map(|v| v * v).sum::<f64>().sqrt()
}

impl CcpSolver for Admm {
    solver_accessors!("admm");

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        if m > self.options.max_rows {
            *self.fallback.settings_mut() = self.settings.clone();
            return self.fallback.solve(problem, gamma);
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.d,
            &mut self.rho,
            &mut self.g,
            &mut self.z,
            &mut self.z_old,
            &mut self.u,
            &mut self.rhs,
            &mut self.grad,
            &mut self.best,
            &mut self.best_grad,
        ] {
            v.clear();
            v.resize(m, 0.0);
        }
        self.rows.clear();
        self.rows.extend(0..m);
        self.factorizations = 0;
        // The metric: diag(N) averaged over cones; a row with a zero diagonal (it touches no
        // movable dof) gets the mean so its penalty stays positive.
        let scales = problem.scales();
        let (mut sum, mut count) = (0.0, 0usize);
        for (d, &s) in self.d.iter_mut().zip(scales) {
            if s > 0.0 {
                *d = 1.0 / s;
                sum += *d;
                count += 1;
            }
        }
        let mean = if count > 0 { sum / count as f64 } else { 1.0 };
        for d in &mut self.d {
            if *d == 0.0 {
                *d = mean;
            }
        }

        sanitize_and_project(problem, gamma);
        self.z.copy_from_slice(gamma);
        problem.gradient(&self.z, &mut self.grad, &mut self.work);
        let mut n_apply = 1;
        let mut best_res = problem.residual(&self.z, &self.grad, &mut self.work);
        self.keep_best();
        let mut iterations = 0;
        if best_res.is_finite() && best_res > tol {
            if self.refactor(problem, self.options.rho).is_err() {
                *self.fallback.settings_mut() = self.settings.clone();
                return self.fallback.solve(problem, gamma);
            }
            let bil = problem.sections().bilateral.clone();
            // The multiplier of the warm start (zero on bilateral rows, whose projection is
            // the identity and whose multiplier is therefore always zero after a step).
            for i in 0..m {
                self.u[i] = if bil.contains(&i) {
                    0.0
                } else {
                    -self.grad[i] / self.rho[i]
                };
            }
            // Adaptation points: every `adapt_every` iterations, the interval doubling after
            // each change of `rho` so that balancing cannot cycle (each change also costs a
            // factorization).
            let mut every = self.options.adapt_every;
            let mut next_adapt = every;
            for it in 1..=max_it {
                iterations = it;
                for i in 0..m {
                    self.rhs[i] = self.rho[i] * (self.z[i] - self.u[i]) - problem.r()[i];
                }
                self.g.copy_from_slice(&self.rhs);
                // No residual check per iteration once the factor's first solve needed no
                // refinement: the iteration corrects a round-off error in `g` itself.
                self.factor.solve_corrected_later(&mut self.g);
                std::mem::swap(&mut self.z, &mut self.z_old);
                let alpha = self.options.relaxation;
                if alpha != 1.0 {
                    for (g, &z) in self.g.iter_mut().zip(&self.z_old) {
                        *g = alpha * *g + (1.0 - alpha) * z;
                    }
                }
                for i in 0..m {
                    self.z[i] = self.g[i] + self.u[i];
                }
                problem.project(&mut self.z);
                for i in 0..m {
                    self.u[i] += self.g[i] - self.z[i];
                }
                problem.gradient(&self.z, &mut self.grad, &mut self.work);
                n_apply += 1;
                let res = problem.residual(&self.z, &self.grad, &mut self.work);
                history.push(it, res, n_apply, || {
                    problem.objective_from_gradient(&self.z, &self.grad, &mut self.work)
                });
                if !res.is_finite() {
                    break;
                }
                if res < best_res {
                    best_res = res;
                    self.keep_best();
                }
                if res <= tol {
                    break;
                }
                if every > 0 && it >= next_adapt {
                    next_adapt = it + every;
                    // Residual balancing in the Jacobi-scaled variables `sqrt(d) g`.
                    let sd = |i: usize| self.d[i].sqrt();
                    let rp = norm((0..m).map(|i| sd(i) * (self.g[i] - self.z[i])));
                    let rd =
                        self.rho_scale * norm((0..m).map(|i| sd(i) * (self.z[i] - self.z_old[i])));
                    let gz = norm((0..m).map(|i| sd(i) * self.g[i]))
                        .max(norm((0..m).map(|i| sd(i) * self.z[i])));
                    let yu = self.rho_scale * norm((0..m).map(|i| sd(i) * self.u[i]));
                    let tiny = f64::MIN_POSITIVE.sqrt();
                    let ratio = (rp / gz.max(tiny)) / (rd / yu.max(tiny)).max(tiny);
                    let clamp = self.options.adapt_clamp;
                    let f = ratio.sqrt().clamp(1.0 / clamp, clamp);
                    let t = self.options.adapt_threshold;
                    if f.is_finite() && !(1.0 / t..=t).contains(&f) {
                        // The scaled multiplier is y / rho: rescale with rho.
                        for i in 0..m {
                            if !bil.contains(&i) {
                                self.u[i] /= f;
                            }
                        }
                        if self.refactor(problem, self.rho_scale * f).is_err() {
                            break;
                        }
                        every *= 2;
                        next_adapt = it + every;
                    }
                }
            }
        }
        gamma.copy_from_slice(&self.best);
        final_stats(
            problem,
            gamma,
            &self.best_grad,
            &mut self.work,
            iterations,
            n_apply,
            tol,
            history.into_records(),
        )
    }
}
