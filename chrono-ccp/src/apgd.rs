//! Accelerated projected gradient descent (Nesterov's method with adaptive step and restart).
//!
//! H. Mazhar, T. Heyn, D. Negrut, A. Tasora, "Using Nesterov's method to accelerate multibody
//! dynamics with friction and contact", ACM Trans. Graph. 34(3), 2015 — the clean variant of
//! Chrono::Multicore's `ChSolverMulticoreAPGD` — on `min f(g) = 1/2 g'N g + r'g, g ∈ Y`
//! (gradient `N g + r`), with an optional diagonal (Jacobi) metric.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings,
    reduce::{sum_by, sum2_by},
};
use serde::{Deserialize, Serialize};

mod units;

use crate::util::{
    History, check_gamma_len, empty_stats, fill_with, fill2_with, final_stats, power_lipschitz,
    sanitize_and_project,
};

/// After every iteration the Lipschitz estimate is relaxed, `L <- LIPSCHITZ_DECAY L`, so the
/// step can grow again where the problem is locally flatter (Mazhar et al. 2015).
pub const LIPSCHITZ_DECAY: f64 = 0.9;

/// The backtracking line search gives up (and the solve stops, not converged) after this many
/// doublings of `L` in one iteration; `2^60` is far beyond any reachable mismatch between the
/// estimate and the true constant, so hitting it means non-finite or garbage data.
pub const MAX_BACKTRACKS: usize = 60;

/// The buffer holding the best iterate during a solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Best {
    /// In `g` (the current iterate).
    G,
    /// In `g_new` (the trial buffer).
    GNew,
    /// Copied into `best`.
    Kept,
}

/// Options of [`Apgd`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ApgdOptions {
    /// Use the diagonal metric `P = diag(N)^-1` (averaged over the three rows of a friction
    /// triplet, [`CcpProblem::residual_scale`], so cones stay cones): the step is
    /// `g <- P_Y(y - P (N y + r) / L)`, i.e. APGD on the Jacobi-scaled problem
    /// `P^1/2 N P^1/2`. It equalizes rows of very different effective mass (stacks, mass
    /// ratios) and is exactly the scaling of the common residual. Default `true`.
    pub preconditioned: bool,
    /// Power iterations for the initial Lipschitz estimate `L ≈ lambda_max(P^1/2 N P^1/2)`
    /// (each costs one `apply_n`; `>= 1`). Backtracking corrects an underestimate, the decay
    /// an overestimate. Default `2`.
    pub power_iterations: usize,
    /// Adaptive restart (O'Donoghue and Candès 2015, as in Mazhar et al.): when
    /// `(N y + r)'(g_new - g) > 0` the momentum is dropped (`y = g_new`, `theta = 1`).
    /// Default `true`.
    pub adaptive_restart: bool,
    /// On problems whose rows are all friction triplets
    /// ([`CcpProblem::is_friction_only`]: granular material), run an iteration in three
    /// passes over the rows instead of about nine (the reductions fused into the product,
    /// the extrapolation into the step). The iterates are the same bits either way; `false`
    /// is for comparison. Default `true`.
    pub fused: bool,
}

impl Default for ApgdOptions {
    fn default() -> Self {
        Self {
            preconditioned: true,
            power_iterations: 2,
            adaptive_restart: true,
            fused: true,
        }
    }
}

impl ApgdOptions {
    fn validate(&self) {
        assert!(
            self.power_iterations >= 1,
            "ApgdOptions.power_iterations must be >= 1"
        );
    }
}

/// Nesterov accelerated projected gradient solver of the CCP `Y ∋ g ⊥ -(N g + r) ∈ Y°`.
///
/// With `P` the metric ([`ApgdOptions::preconditioned`]: `diag(N)^-1`, else `I`), starting
/// from `g_0 = P_Y(warm start)`, `y = g_0`, `theta = 1`, `L` from a few power iterations:
///
/// ```text
/// repeat
///     g+ = P_Y(y - P (N y + r) / L)
///     while d'N d > L d'P^-1 d   (d = g+ - y):  L <- 2L, recompute g+      (backtracking)
///     theta+ = (-theta^2 + theta sqrt(theta^2 + 4)) / 2
///     beta   = theta (1 - theta) / (theta^2 + theta+)
///     if (N y + r)'(g+ - g) > 0:  theta+ = 1, beta = 0                       (restart)
///     y = g+ + beta (g+ - g);  g = g+;  theta = theta+;  L <- 0.9 L
/// until residual(g) <= tolerance
/// ```
///
/// and the iterate with the lowest common residual ([`CcpProblem::residual`], m/s) is
/// returned (the method is not monotone).
///
/// Implementation choices (vs Chrono's `ChSolverAPGD`):
/// - the sufficient-decrease test `f(g+) <= f(y) + grad'd + L/2 |d|^2` is evaluated in its
///   exact form for a quadratic, `d'N d <= L |d|^2`, from the gradients at `g+` and `y`: no
///   difference of two nearly equal objective values, so no spurious backtracking near the
///   solution (Chrono's form fails there in floating point);
/// - one `apply_n` per iteration (plus one per backtrack): the gradient at `y` is the same
///   linear combination of the gradients at `g+` and `g` as `y` is of the iterates;
/// - the residual of `g+` reuses the gradient already computed for the line search.
///
/// All vector operations are rayon-parallel above a size threshold and every reduction is
/// done in a fixed order, so the result is bit-identical for any thread count. The solver
/// owns its buffers and allocates only when a problem is larger than any seen before.
#[derive(Debug, Clone, Default)]
pub struct Apgd {
    settings: SolverSettings,
    options: ApgdOptions,
    work: CcpWork,
    /// Metric `P` (step scale per row).
    s: Vec<f64>,
    /// `1 / P` per row (0 where `P` is 0): the line search's `d'P^-1 d` without a division
    /// per row.
    s_inv: Vec<f64>,
    g: Vec<f64>,
    g_new: Vec<f64>,
    y: Vec<f64>,
    grad: Vec<f64>,
    grad_new: Vec<f64>,
    grad_y: Vec<f64>,
    best: Vec<f64>,
    /// The fused path's per-unit sums ([`units`]).
    units: Vec<units::UnitSums>,
}

impl Apgd {
    /// A solver with the common settings `settings` and default [`ApgdOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Use the diagonal (Jacobi) metric or not (see [`ApgdOptions::preconditioned`]).
    pub fn with_preconditioning(mut self, preconditioned: bool) -> Self {
        self.options.preconditioned = preconditioned;
        self
    }

    /// Number of power iterations of the initial Lipschitz estimate.
    ///
    /// # Panics
    /// If `power_iterations == 0`.
    pub fn with_power_iterations(mut self, power_iterations: usize) -> Self {
        self.options.power_iterations = power_iterations;
        self.options.validate();
        self
    }

    /// Enable or disable the adaptive restart.
    pub fn with_adaptive_restart(mut self, adaptive_restart: bool) -> Self {
        self.options.adaptive_restart = adaptive_restart;
        self
    }

    settings_builders!();

    /// Replace all APGD-specific options.
    ///
    /// # Panics
    /// If an option is out of range (see [`ApgdOptions`]).
    pub fn with_options(mut self, options: ApgdOptions) -> Self {
        options.validate();
        self.options = options;
        self
    }

    /// The APGD-specific options.
    pub fn options(&self) -> &ApgdOptions {
        &self.options
    }

    /// The APGD-specific options, mutable (checked at the start of every solve).
    pub fn options_mut(&mut self) -> &mut ApgdOptions {
        &mut self.options
    }

    /// Power-iteration estimate of `lambda_max(P^1/2 N P^1/2)`, using `y`, `grad_y`,
    /// `grad_new` as scratch. Returns a positive finite value (1 for a zero operator).
    fn estimate_lipschitz(&mut self, problem: &CcpProblem) -> f64 {
        power_lipschitz(
            problem,
            &self.s,
            self.options.power_iterations,
            &mut self.y,
            &mut self.grad_y,
            &mut self.grad_new,
            &mut self.work,
        )
    }

    /// Fill `g_new = P_Y(y - P grad_y / l)` and `grad_new = N g_new + r`; return
    /// `(d'N d, d'P^-1 d)` with `d = g_new - y`.
    fn trial(&mut self, problem: &CcpProblem, l: f64) -> (f64, f64) {
        let (y, gy, s, si) = (&self.y, &self.grad_y, &self.s, &self.s_inv);
        let t = 1.0 / l;
        fill_with(&mut self.g_new, |i| y[i] - t * s[i] * gy[i]);
        problem.project(&mut self.g_new);
        problem.gradient(&self.g_new, &mut self.grad_new, &mut self.work);
        let (gn, grn) = (&self.g_new, &self.grad_new);
        // One pass for both (each sum in sum_by's order: the same bits as two passes).
        sum2_by(gn.len(), &mut self.work.partials, |i| {
            let d = gn[i] - y[i];
            let dpd = d * d * si[i];
            (d * (grn[i] - gy[i]), dpd)
        })
    }
}

impl CcpSolver for Apgd {
    solver_accessors!("apgd");

    /// Solve by accelerated projected gradient; see [`Apgd`]. `gamma` is the warm start
    /// (non-finite entries are replaced by 0, then it is projected onto `Y`) and receives the
    /// best iterate.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        self.options.validate();
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        for v in [
            &mut self.s,
            &mut self.s_inv,
            &mut self.g,
            &mut self.g_new,
            &mut self.y,
            &mut self.grad,
            &mut self.grad_new,
            &mut self.grad_y,
            &mut self.best,
        ] {
            v.resize(m, 0.0);
        }
        if self.options.preconditioned {
            fill_with(&mut self.s, |i| problem.residual_scale(i));
        } else {
            self.s.fill(1.0);
        }
        let s = &self.s;
        fill_with(
            &mut self.s_inv,
            |i| if s[i] > 0.0 { 1.0 / s[i] } else { 0.0 },
        );

        sanitize_and_project(problem, gamma);
        self.g.copy_from_slice(gamma);
        // Where the best iterate is: copied into `best` only when its buffer is about to be
        // overwritten (rarely: the residual mostly falls from one iterate to the next).
        let mut best_at = Best::G;
        problem.gradient(&self.g, &mut self.grad, &mut self.work);
        let mut n_apply = 1;
        let mut best_res = problem.residual(&self.g, &self.grad, &mut self.work);
        if !best_res.is_finite() || best_res <= tol {
            return final_stats(
                problem,
                gamma,
                &self.grad,
                &mut self.work,
                0,
                n_apply,
                tol,
                history.into_records(),
            );
        }
        let mut l = self.estimate_lipschitz(problem);
        n_apply += self.options.power_iterations;
        self.y.copy_from_slice(&self.g);
        self.grad_y.copy_from_slice(&self.grad);
        let mut theta: f64 = 1.0;
        let mut iterations = 0;

        // Friction-only problems take the fused passes (same bits, fewer passes).
        let fused = self.options.fused && problem.is_friction_only();
        // The fused path extrapolates `y` at the start of the next iteration's first trial.
        let mut extrapolate: Option<f64> = None;

        for it in 1..=max_it {
            iterations = it;
            // Projected gradient step from y with backtracking on L.
            let mut ok = false;
            let mut sums = units::TrialSums::default();
            // The trials overwrite `g_new`: if it holds the best iterate, its buffer becomes
            // `best` (a swap, not a copy) and the fused extrapolation reads the previous
            // iterate from there.
            let mut prev_in_best = false;
            if best_at == Best::GNew {
                std::mem::swap(&mut self.best, &mut self.g_new);
                best_at = Best::Kept;
                prev_in_best = true;
            }
            for _ in 0..=MAX_BACKTRACKS {
                let (dnd, dpd) = if fused {
                    sums = self.trial_units(problem, l, extrapolate.take(), prev_in_best);
                    (sums.dnd, sums.dpd)
                } else {
                    self.trial(problem, l)
                };
                n_apply += 1;
                if !(dnd.is_finite() && dpd.is_finite()) {
                    break;
                }
                if dnd <= l * dpd {
                    ok = true;
                    break;
                }
                l *= 2.0;
            }
            let res = if !ok {
                f64::NAN
            } else if fused {
                sums.residual
            } else {
                problem.residual(&self.g_new, &self.grad_new, &mut self.work)
            };
            history.push(it, res, n_apply, || {
                problem.objective_from_gradient(&self.g_new, &self.grad_new, &mut self.work)
            });
            if !res.is_finite() {
                break;
            }
            let improved = res < best_res;
            if improved {
                best_res = res;
                best_at = Best::GNew;
            }
            if res <= tol {
                break;
            }

            let theta_new = 0.5 * (-theta * theta + theta * (theta * theta + 4.0).sqrt());
            let mut beta = theta * (1.0 - theta) / (theta * theta + theta_new);
            let mut theta_next = theta_new;
            if self.options.adaptive_restart {
                let slope = if fused {
                    sums.slope
                } else {
                    let (gy, gn, g) = (&self.grad_y, &self.g_new, &self.g);
                    sum_by(m, &mut self.work.partials, |i| gy[i] * (gn[i] - g[i]))
                };
                if slope > 0.0 {
                    theta_next = 1.0;
                    beta = 0.0;
                }
            }
            if fused {
                extrapolate = Some(beta);
            } else {
                // y = g+ + beta (g+ - g), and by linearity N y + r likewise.
                let (gn, g, grn, gr) = (&self.g_new, &self.g, &self.grad_new, &self.grad);
                fill2_with(&mut self.y, &mut self.grad_y, |i| {
                    (
                        gn[i] + beta * (gn[i] - g[i]),
                        grn[i] + beta * (grn[i] - gr[i]),
                    )
                });
            }
            std::mem::swap(&mut self.g, &mut self.g_new);
            std::mem::swap(&mut self.grad, &mut self.grad_new);
            best_at = match best_at {
                Best::G => Best::GNew,
                Best::GNew => Best::G,
                Best::Kept => Best::Kept,
            };
            theta = theta_next;
            l *= LIPSCHITZ_DECAY;
        }

        gamma.copy_from_slice(match best_at {
            Best::G => &self.g,
            Best::GNew => &self.g_new,
            Best::Kept => &self.best,
        });
        // The best iterate's gradient moved with it (`g` with `grad`, `g_new` with
        // `grad_new`: every trial fills both, every swap swaps both); only a copied best has
        // lost its own.
        let grad = match best_at {
            Best::G => &self.grad,
            Best::GNew => &self.grad_new,
            Best::Kept => {
                problem.gradient(gamma, &mut self.grad_new, &mut self.work);
                n_apply += 1;
                &self.grad_new
            }
        };
        final_stats(
            problem,
            gamma,
            grad,
            &mut self.work,
            iterations,
            n_apply,
            tol,
            history.into_records(),
        )
    }
}
