//! A direct–iterative solver for problems dominated by joints: the bilateral rows are
//! eliminated by a dense `LDL'` factorization and the remaining (contact, box, unilateral)
//! rows are solved on their Schur complement by an accelerated projected gradient.
//!
//! With the rows split into bilateral `B` and the rest `C`,
//!
//! ```text
//! [N_BB N_BC] [g_B]   [r_B]
//! [N_CB N_CC] [g_C] + [r_C]  = grad,   grad_B = 0,   g_C in Y_C complementary to grad_C,
//! ```
//!
//! `g_B = -N_BB^-1 (r_B + N_BC g_C)` exactly, and `g_C` solves the CCP
//!
//! ```text
//! min 1/2 g_C' S g_C + q' g_C  s.t. g_C in Y_C,   S = N_CC - N_CB N_BB^-1 N_BC,
//! q = r_C - N_CB N_BB^-1 r_B.
//! ```
//!
//! `N_BB` is sparse (a joint row couples the rows of the bodies it touches) and is
//! factored by faer's sparse Cholesky with the symbolic analysis kept across steps
//! (the crate-internal `sparse_bilateral` module).
//!
//! `S` is the inverse effective mass seen by the contacts *through* the joints (a wheel
//! feels the chassis behind its suspension), so the iterative part converges as fast as for
//! free bodies, however stiff the chain and however large its mass ratios: a vehicle's
//! suspension links of a few kilograms on a two-tonne chassis, or a long chain of links,
//! which stall the projected iterations on the whole problem. Redundant joints (a singular
//! `N_BB`) get a multiplier of about zero (regularized pivots).
//!
//! Cost: forming `N_BB` and `N_BC` from the problem's sparse rows, the sparse
//! factorization (for a mechanism about linear in `n_B`), `n_C` sparse solves and
//! `O(n_B n_C^2)` for `S`, then `O(n_C^2)` per iteration.
//! It suits mechanisms (hundreds of joint rows, tens of contacts); past
//! [`max_dense_rows`](Schur::with_max_dense_rows) contact rows the complement is applied
//! matrix-free (one product with `N`, the joint rows' share of a second and a sparse solve
//! per iteration), and a problem
//! without bilateral rows goes to the fallback solver (APGD by default) directly.
//!
//! Reference: the Schur-complement (reduced) formulation of the contact problem of a
//! multibody system with bilateral constraints, e.g. M. Anitescu and G. D. Hart, "A
//! constraint-stabilized time-stepping approach for rigid multibody dynamics with joints,
//! contact and friction", Int. J. Numer. Methods Eng. 60 (2004); accelerated projected
//! gradient with restart as in [`crate::Apgd`] (Nesterov; O'Donoghue and Candès 2015).

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, PackedRows, SolveStats, SolverSettings,
};

use crate::Apgd;
use crate::sparse_bilateral::SparseBilateral;
use crate::util::{History, check_gamma_len, empty_stats, final_stats, sanitize_and_project};

/// The Schur-complement solver (see the [module documentation](self)).
pub struct Schur {
    settings: SolverSettings,
    fallback: Box<dyn CcpSolver>,
    max_dense_rows: usize,
    // scratch, reused across solves
    b_rows: Vec<usize>,
    c_rows: Vec<usize>,
    factor: SparseBilateral,
    nbc: Vec<f64>,
    x: Vec<f64>,
    s: Vec<f64>,
    q: Vec<f64>,
    g: Vec<f64>,
    g_prev: Vec<f64>,
    y: Vec<f64>,
    grad_c: Vec<f64>,
    rhs_b: Vec<f64>,
    full: Vec<f64>,
    grad: Vec<f64>,
    zero: Vec<f64>,
    scratch: ImplicitScratch,
    /// The joint rows packed for the matrix-free mode's completed steps.
    packed: PackedRows,
    work: CcpWork,
    /// The matrix-free mode's step-size bound at the end of the last solve (0: none yet).
    last_lip: f64,
}

/// Power iterations for the step size of the matrix-free mode (a lower bound of the
/// largest eigenvalue, raised by the backtracking where it is too low).
const POWER_ITERATIONS: usize = 4;

/// The matrix-free mode's vectors (one entry per row), kept across solves.
#[derive(Default)]
struct ImplicitScratch {
    x: Vec<f64>,
    grad_x: Vec<f64>,
    best: Vec<f64>,
    y: Vec<f64>,
    grad_y: Vec<f64>,
    x_new: Vec<f64>,
    step: Vec<f64>,
    n_step: Vec<f64>,
}

impl ImplicitScratch {
    fn resize(&mut self, m: usize) {
        for v in [
            &mut self.x,
            &mut self.grad_x,
            &mut self.best,
            &mut self.y,
            &mut self.grad_y,
            &mut self.x_new,
            &mut self.step,
            &mut self.n_step,
        ] {
            v.clear();
            v.resize(m, 0.0);
        }
    }
}

impl Schur {
    /// A Schur solver with `settings` (tolerance and iteration cap of the contact part) and
    /// APGD with the same settings as the fallback.
    pub fn new(settings: SolverSettings) -> Self {
        let fallback = Box::new(Apgd::new(settings.clone()));
        Self::with_fallback(settings, fallback)
    }

    /// A Schur solver that hands problems too large for dense blocks to `fallback`.
    pub fn with_fallback(settings: SolverSettings, fallback: Box<dyn CcpSolver>) -> Self {
        Self {
            settings,
            fallback,
            max_dense_rows: 1500,
            b_rows: Vec::new(),
            c_rows: Vec::new(),
            factor: SparseBilateral::with_hubs(),
            nbc: Vec::new(),
            x: Vec::new(),
            s: Vec::new(),
            q: Vec::new(),
            g: Vec::new(),
            g_prev: Vec::new(),
            y: Vec::new(),
            grad_c: Vec::new(),
            rhs_b: Vec::new(),
            full: Vec::new(),
            grad: Vec::new(),
            zero: Vec::new(),
            scratch: ImplicitScratch::default(),
            packed: PackedRows::default(),
            work: CcpWork::default(),
            last_lip: 0.0,
        }
    }

    /// The largest number of non-bilateral rows whose Schur complement is formed densely
    /// (default 1500). Beyond it (a vehicle on granular terrain: thousands of contacts) the
    /// complement is applied matrix-free (the private `implicit` path).
    pub fn with_max_dense_rows(mut self, n: usize) -> Self {
        self.max_dense_rows = n;
        self
    }

    /// Set the joint impulses exactly for the current other impulses: `g_B = -N_BB^-1 (r_B +
    /// N_BC g_C)` (from the gradient of `gamma` with its bilateral part zeroed), then leave
    /// the full gradient `N g + r` of the completed `gamma` in `self.grad` (its bilateral part
    /// is zero to round-off; its other part is the gradient of the reduced problem).
    fn complete(&mut self, problem: &CcpProblem, gamma: &mut [f64]) {
        for &i in &self.b_rows {
            gamma[i] = 0.0;
        }
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        self.rhs_b.clear();
        self.rhs_b.extend(self.b_rows.iter().map(|&i| self.grad[i]));
        self.factor.solve(&mut self.rhs_b, 1);
        for (k, &i) in self.b_rows.iter().enumerate() {
            gamma[i] = -self.rhs_b[k];
        }
        problem.gradient(gamma, &mut self.grad, &mut self.work);
    }

    /// Extend a step `d` (its non-bilateral part given, its bilateral part overwritten) by
    /// the joint impulses that keep the joints exact: `d_B = -N_BB^-1 (base_B + N_BC d_C)`
    /// with `base_B` the bilateral part of the gradient at the point the step starts from,
    /// and leave `N d` in `out`. One product with `N` and one sparse solve: the velocity
    /// change of `d_C` (`M^-1 D_C' d_C`, the first half of a product) gives `N_BC d_C` on
    /// the joint rows alone, the joint impulses' velocity change is added row by row (a
    /// mechanism has few joint rows next to its contacts), and the second half gives `N d`
    /// on the other rows; on the joint rows `N d = -base_B` by construction.
    fn complete_step(
        &mut self,
        problem: &CcpProblem,
        d: &mut [f64],
        base: &[f64],
        out: &mut [f64],
    ) {
        for &i in &self.b_rows {
            d[i] = 0.0;
        }
        problem.velocity_changes_of(d, &mut self.work);
        self.rhs_b.clear();
        let (v, packed) = (&self.work.v, &self.packed);
        self.rhs_b.extend(
            self.b_rows
                .iter()
                .enumerate()
                .map(|(k, &i)| base[i] + packed.dot(problem, k, v)),
        );
        self.factor.solve_corrected_later(&mut self.rhs_b);
        for (k, &i) in self.b_rows.iter().enumerate() {
            d[i] = -self.rhs_b[k];
            self.packed.add_minv(problem, k, d[i], &mut self.work.v);
        }
        // The joint rows of `N d` are `N_BB d_B + N_BC d_C = -base_B` by construction (to the
        // factor's round-off: the solve is refined until a check met that bound): set, not
        // computed, which saves the products of about a third of a vehicle's rows. The
        // completed iterates' joint gradient is then zero, as the exact one is.
        problem.rows_from_velocity_except_bilateral(d, &self.work, out, None);
        for &i in &self.b_rows {
            out[i] = -base[i];
        }
    }

    /// Power-iteration estimate of `lambda_max(D^1/2 S D^1/2)` (`D` the rows' step scales,
    /// `S` the Schur complement) with the operator applied matrix-free: `S x` is the
    /// non-bilateral part of `N [z; x]` with `z = -N_BB^-1 N_BC x`.
    fn reduced_lipschitz(&mut self, problem: &CcpProblem, iterations: usize) -> f64 {
        let m = problem.n_rows();
        let sc = problem.scales();
        let mut x = std::mem::take(&mut self.y);
        let mut nx = std::mem::take(&mut self.g_prev);
        x.clear();
        x.resize(m, 0.0);
        nx.clear();
        nx.resize(m, 0.0);
        for (k, &i) in self.c_rows.iter().enumerate() {
            x[i] = 0.5 + ((k as f64 + 1.0) * 0.618_033_988_749_895).fract();
        }
        let mut lambda = 1.0;
        for _ in 0..iterations {
            let norm = self.c_rows.iter().map(|&i| x[i] * x[i]).sum::<f64>().sqrt();
            if !(norm > 0.0 && norm.is_finite()) {
                break;
            }
            for &i in &self.c_rows {
                x[i] *= sc[i].sqrt() / norm;
            }
            // `S x` is the non-bilateral part of `N [z; x]`, `z` the completion from zero.
            let zero = std::mem::take(&mut self.zero);
            self.complete_step(problem, &mut x, &zero, &mut nx);
            self.zero = zero;
            let mut l2 = 0.0;
            for &i in &self.c_rows {
                x[i] = sc[i].sqrt() * nx[i];
                l2 += x[i] * x[i];
            }
            lambda = l2.sqrt();
        }
        self.y = x;
        self.g_prev = nx;
        if lambda > 0.0 && lambda.is_finite() {
            lambda
        } else {
            1.0
        }
    }

    /// The mode for many non-bilateral rows (granular contacts): accelerated projected
    /// gradient on the reduced problem with the Schur complement applied matrix-free, every
    /// iterate completed by the exact joint impulses (each step by
    /// [`complete_step`](Self::complete_step): one product with `N` and one sparse solve per
    /// trial; the warm start by [`complete`](Self::complete)). The metric is the rows'
    /// diagonal scales (Jacobi preconditioning, cone-averaged); the step `1 / L` with `L`
    /// from a power iteration on the first solve and half the last solve's `L` after it,
    /// doubled while the quadratic model does not bound the step;
    /// momentum with gradient restart; the best iterate is returned. The joints hold to
    /// round-off at every iterate, so however far from convergence the iterations stop, no
    /// joint drifts.
    fn implicit(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        let tol = self.settings.tolerance;
        let m = problem.n_rows();
        let max_it = self.settings.max_iterations.max(1);
        let mut history = History::new(self.settings.record_history, max_it);
        self.zero.clear();
        self.zero.resize(m, 0.0);
        // The joint rows, used twice per completed step, packed once per solve.
        self.packed.pack(problem, &self.b_rows);
        // The bound of the last solve, halved, when there is one (the problems of
        // successive steps are alike; the backtracking doubles a low bound back, one product
        // where the power iteration spent four); else the power iteration.
        let (mut lip, mut apply_n) = if self.last_lip > 0.0 {
            (0.5 * self.last_lip, 1)
        } else {
            (
                self.reduced_lipschitz(problem, POWER_ITERATIONS),
                1 + POWER_ITERATIONS,
            )
        };
        let sc = problem.scales();
        // The non-bilateral rows: the problem's rows before and after its bilateral section.
        let bil = problem.sections().bilateral.clone();
        let c_ranges = [0..bil.start, bil.end..m];
        let mut v = std::mem::take(&mut self.scratch);
        v.resize(m);
        // x: the iterate, y: the extrapolated point; both completed (their joints exact),
        // and since the completion is affine, so is every combination of them.
        v.x.copy_from_slice(gamma);
        self.complete(problem, &mut v.x);
        apply_n += 2;
        v.grad_x.copy_from_slice(&self.grad);
        let mut best_res = problem.residual(&v.x, &v.grad_x, &mut self.work);
        v.best.copy_from_slice(&v.x);
        v.y.copy_from_slice(&v.x);
        v.grad_y.copy_from_slice(&v.grad_x);
        // Stale until the first step writes it; only its non-bilateral rows are read.
        v.x_new.copy_from_slice(&v.x);
        let mut theta = 1.0f64;
        let mut iterations = 0;
        for it in 1..=max_it {
            if best_res <= tol {
                break;
            }
            iterations = it;
            // Projected step from y; backtrack until the quadratic model bounds the step
            // (d'S d <= L |d|^2 in the metric), as in APGD.
            for _ in 0..40 {
                let t = 1.0 / lip;
                for r in &c_ranges {
                    let (xn, y, gy, s) = (
                        &mut v.x_new[r.clone()],
                        &v.y[r.clone()],
                        &v.grad_y[r.clone()],
                        &sc[r.clone()],
                    );
                    for (((xn, &y), &gy), &s) in xn.iter_mut().zip(y).zip(gy).zip(s) {
                        *xn = y - s * gy * t;
                    }
                }
                // The bilateral rows are left alone by the projection.
                problem.project(&mut v.x_new);
                // The step from `y` (completed), completed by its joint impulses: the new
                // gradient is `grad_y + N d`, one product instead of two.
                for r in &c_ranges {
                    let (st, xn, y) =
                        (&mut v.step[r.clone()], &v.x_new[r.clone()], &v.y[r.clone()]);
                    for ((st, &xn), &y) in st.iter_mut().zip(xn).zip(y) {
                        *st = xn - y;
                    }
                }
                self.complete_step(problem, &mut v.step, &v.grad_y, &mut v.n_step);
                for i in bil.clone() {
                    v.x_new[i] = v.y[i] + v.step[i];
                }
                for ((g, &gy), &ns) in self.grad.iter_mut().zip(&v.grad_y).zip(&v.n_step) {
                    *g = gy + ns;
                }
                apply_n += 1;
                let (mut dnd, mut dpd) = (0.0, 0.0);
                for r in &c_ranges {
                    let (st, g, gy, s) = (
                        &v.step[r.clone()],
                        &self.grad[r.clone()],
                        &v.grad_y[r.clone()],
                        &sc[r.clone()],
                    );
                    for (((&d, &g), &gy), &s) in st.iter().zip(g).zip(gy).zip(s) {
                        dnd += d * (g - gy);
                        if s > 0.0 {
                            dpd += d * d / s;
                        }
                    }
                }
                if dnd <= lip * dpd || dpd == 0.0 {
                    break;
                }
                lip *= 2.0;
            }
            let mut res = problem.residual(&v.x_new, &self.grad, &mut self.work);
            if res <= tol {
                // The gradient was updated step by step and carries their round-off:
                // converged only if the exact gradient agrees (else iterate on from it).
                problem.gradient(&v.x_new, &mut self.grad, &mut self.work);
                apply_n += 1;
                res = problem.residual(&v.x_new, &self.grad, &mut self.work);
            }
            history.push(it, res, apply_n, || {
                problem.objective_from_gradient(&v.x_new, &self.grad, &mut self.work)
            });
            if !res.is_finite() {
                break;
            }
            if res < best_res {
                best_res = res;
                v.best.copy_from_slice(&v.x_new);
            }
            // Nesterov momentum with gradient restart (O'Donoghue and Candès).
            let mut slope = 0.0;
            for r in &c_ranges {
                let (gy, xn, x) = (&v.grad_y[r.clone()], &v.x_new[r.clone()], &v.x[r.clone()]);
                for ((&gy, &xn), &x) in gy.iter().zip(xn).zip(x) {
                    slope += gy * (xn - x);
                }
            }
            let beta = momentum(&mut theta, slope);
            for (((y, gy), (&xn, &x)), (&g, &gx)) in (v.y.iter_mut().zip(v.grad_y.iter_mut()))
                .zip(v.x_new.iter().zip(&v.x))
                .zip(self.grad.iter().zip(&v.grad_x))
            {
                *y = xn + beta * (xn - x);
                *gy = g + beta * (g - gx);
            }
            std::mem::swap(&mut v.x, &mut v.x_new);
            std::mem::swap(&mut v.grad_x, &mut self.grad);
        }
        gamma.copy_from_slice(&v.best);
        self.scratch = v;
        self.last_lip = if lip.is_finite() && lip > 0.0 {
            lip
        } else {
            0.0
        };
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        apply_n += 1;
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            apply_n,
            tol,
            history.into_records(),
        )
    }

    /// Scatter the contact part `gc` into the full-length `full` (bilateral rows 0) and
    /// project it onto the cones; read it back.
    fn project_c(problem: &CcpProblem, c_rows: &[usize], full: &mut [f64], gc: &mut [f64]) {
        for (k, &i) in c_rows.iter().enumerate() {
            full[i] = gc[k];
        }
        problem.project(full);
        for (k, &i) in c_rows.iter().enumerate() {
            gc[k] = full[i];
        }
    }

    /// `out = S v + q` (the reduced gradient).
    fn reduced_gradient(s: &[f64], q: &[f64], v: &[f64], out: &mut [f64]) {
        let nc = q.len();
        for c in 0..nc {
            let row = &s[c * nc..(c + 1) * nc];
            out[c] = q[c] + row.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
        }
    }

    /// `g_B = -N_BB^+ (r_B + N_BC g_C)` into `gamma`.
    fn recover_bilateral(&mut self, problem: &CcpProblem, gamma: &mut [f64]) {
        let (nb, nc) = (self.b_rows.len(), self.c_rows.len());
        let r = problem.r();
        let rhs = &mut self.rhs_b;
        rhs.clear();
        rhs.extend(self.b_rows.iter().map(|&i| r[i]));
        for (c, &gc) in self.g.iter().enumerate().take(nc) {
            if gc != 0.0 {
                let col = &self.nbc[c * nb..(c + 1) * nb];
                rhs.iter_mut().zip(col).for_each(|(x, a)| *x += a * gc);
            }
        }
        self.factor.solve(rhs, 1);
        let rhs = &self.rhs_b;
        for (k, &i) in self.b_rows.iter().enumerate() {
            gamma[i] = -rhs[k];
        }
        for (c, &i) in self.c_rows.iter().enumerate() {
            gamma[i] = self.g[c];
        }
    }
}

impl CcpSolver for Schur {
    solver_accessors!("schur");

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let bil = problem.sections().bilateral.clone();
        let nb = bil.len();
        let nc = m - nb;
        if nb == 0 {
            return self.fallback.solve(problem, gamma);
        }
        sanitize_and_project(problem, gamma);
        // A warm start that already solves the problem needs no work.
        self.grad.resize(m, 0.0);
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        if problem.residual(gamma, &self.grad, &mut self.work) <= self.settings.tolerance {
            let tol = self.settings.tolerance;
            return final_stats(
                problem,
                gamma,
                &self.grad,
                &mut self.work,
                0,
                1,
                tol,
                Vec::new(),
            );
        }
        self.b_rows.clear();
        self.b_rows.extend(bil.clone());
        self.c_rows.clear();
        self.c_rows.extend((0..m).filter(|i| !bil.contains(i)));

        // N_BB, factored (sparse).
        if self.factor.factor(problem, &self.b_rows).is_err() {
            return self.fallback.solve(problem, gamma);
        }
        if nc > self.max_dense_rows {
            return self.implicit(problem, gamma);
        }

        // N_BC by columns, X = N_BB^+ N_BC, S = N_CC - N_BC' X, q = r_C - X' r_B.
        self.nbc.resize(nb * nc, 0.0);
        self.x.resize(nb * nc, 0.0);
        for (c, &j) in self.c_rows.iter().enumerate() {
            let col = &mut self.nbc[c * nb..(c + 1) * nb];
            for (b, &i) in self.b_rows.iter().enumerate() {
                col[b] = problem.n_entry(i, j);
            }
            self.x[c * nb..(c + 1) * nb].copy_from_slice(col);
        }
        self.factor.solve(&mut self.x, nc);
        let r = problem.r();
        self.s.resize(nc * nc, 0.0);
        self.q.resize(nc, 0.0);
        for c in 0..nc {
            let xc = &self.x[c * nb..(c + 1) * nb];
            self.q[c] = r[self.c_rows[c]]
                - xc.iter()
                    .zip(&self.b_rows)
                    .map(|(x, &i)| x * r[i])
                    .sum::<f64>();
            for d in c..nc {
                let nd = &self.nbc[d * nb..(d + 1) * nb];
                let v = problem.n_entry(self.c_rows[c], self.c_rows[d])
                    - xc.iter().zip(nd).map(|(a, b)| a * b).sum::<f64>();
                self.s[c * nc + d] = v;
                self.s[d * nc + c] = v;
            }
        }

        // Accelerated projected gradient on (S, q), step 1/L with L a Gershgorin bound.
        let lip = (0..nc)
            .map(|c| {
                self.s[c * nc..(c + 1) * nc]
                    .iter()
                    .map(|v| v.abs())
                    .sum::<f64>()
            })
            .fold(0.0f64, f64::max);
        let step = if lip > 0.0 && lip.is_finite() {
            1.0 / lip
        } else {
            1.0
        };
        self.full.clear();
        self.full.resize(m, 0.0);
        self.g.clear();
        self.g.extend(self.c_rows.iter().map(|&i| gamma[i]));
        self.g_prev.clear();
        self.g_prev.extend_from_slice(&self.g);
        self.y.clear();
        self.y.extend_from_slice(&self.g);
        self.grad_c.resize(nc, 0.0);
        self.grad.resize(m, 0.0);
        let tol = self.settings.tolerance;
        let max_it = self.settings.max_iterations.max(1);
        let mut history = History::new(self.settings.record_history, max_it);
        let mut theta = 1.0f64;
        let mut iterations = 0;
        let mut apply_n = 1;
        let check_every = 10;
        // Cost of one reduced iteration (nc^2 multiply-adds) in products with N (about
        // 2 n_coefs multiply-adds), at least one, so statistics compare with the other solvers.
        let per_iteration = (nc * nc).div_ceil(2 * problem.n_coefs().max(1)).max(1);
        let max_it = if nc == 0 { 0 } else { max_it };
        // True while `gamma` and `self.grad` hold the completed current iterate (a check
        // just ran): the final completion would redo the same sums.
        let mut completed = false;
        for it in 0..max_it {
            completed = false;
            iterations = it + 1;
            apply_n += per_iteration;
            Self::reduced_gradient(&self.s, &self.q, &self.y, &mut self.grad_c);
            self.g_prev.copy_from_slice(&self.g);
            for c in 0..nc {
                self.g[c] = self.y[c] - step * self.grad_c[c];
            }
            Self::project_c(problem, &self.c_rows, &mut self.full, &mut self.g);
            // Gradient restart (O'Donoghue and Candès): momentum only while it descends.
            let descent: f64 = (0..nc)
                .map(|c| self.grad_c[c] * (self.g[c] - self.g_prev[c]))
                .sum();
            let beta = momentum(&mut theta, descent);
            for c in 0..nc {
                self.y[c] = self.g[c] + beta * (self.g[c] - self.g_prev[c]);
            }
            if it % check_every == check_every - 1 || it + 1 == max_it {
                self.recover_bilateral(problem, gamma);
                problem.gradient(gamma, &mut self.grad, &mut self.work);
                apply_n += 1;
                let res = problem.residual(gamma, &self.grad, &mut self.work);
                history.push(iterations, res, apply_n, || {
                    problem.objective_from_gradient(gamma, &self.grad, &mut self.work)
                });
                completed = true;
                if res <= tol {
                    break;
                }
            }
        }
        if !completed {
            self.recover_bilateral(problem, gamma);
            problem.gradient(gamma, &mut self.grad, &mut self.work);
            apply_n += 1;
        }
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            apply_n,
            tol,
            history.into_records(),
        )
    }
}

/// Nesterov's extrapolation weight for the next iterate, with gradient restart
/// (O'Donoghue and Candès, 2015): `slope = grad(y).(x+ - x)`; a positive slope (the step
/// went uphill along the momentum) restarts the sequence (`theta = 1`, no momentum).
fn momentum(theta: &mut f64, slope: f64) -> f64 {
    if slope > 0.0 {
        *theta = 1.0;
        return 0.0;
    }
    let next = 0.5 * (1.0 + (1.0 + 4.0 * *theta * *theta).sqrt());
    let beta = (*theta - 1.0) / next;
    *theta = next;
    beta
}
