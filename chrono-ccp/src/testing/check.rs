//! Dense views of a problem and an explicit check of its complementarity conditions.

use chrono_core::descriptor::{CcpProblem, CcpWork, PER_BODY_ROWS};
use nalgebra::DMatrix;

use crate::CcpError;

/// `N` as a dense matrix, column by column through `apply_n` (for small problems).
pub fn dense_n(problem: &CcpProblem) -> DMatrix<f64> {
    let m = problem.n_rows();
    let mut work = CcpWork::for_problem(problem);
    let mut n = DMatrix::zeros(m, m);
    let mut e = vec![0.0; m];
    let mut col = vec![0.0; m];
    for j in 0..m {
        e.fill(0.0);
        e[j] = 1.0;
        problem.apply_n(&e, &mut col, &mut work);
        for i in 0..m {
            n[(i, j)] = col[i];
        }
    }
    n
}

/// `c = N g + r`, the constraint velocities (m/s) of the impulses `gamma` (N s).
pub fn gradient(problem: &CcpProblem, gamma: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; problem.n_rows()];
    problem.gradient(gamma, &mut c, &mut CcpWork::for_problem(problem));
    c
}

/// The objective `f(g) = 1/2 g'N g + r'g`.
pub fn objective(problem: &CcpProblem, gamma: &[f64]) -> f64 {
    let c = gradient(problem, gamma);
    gamma
        .iter()
        .zip(&c)
        .zip(problem.r())
        .map(|((g, c), r)| 0.5 * g * (c + r))
        .sum()
}

/// The common residual of `gamma` ([`CcpProblem::residual`], m/s), the stopping measure of
/// every solver.
pub fn residual(problem: &CcpProblem, gamma: &[f64]) -> f64 {
    let c = gradient(problem, gamma);
    problem.residual(gamma, &c, &mut CcpWork::for_problem(problem))
}

/// Check the complementarity conditions of the CCP explicitly, row by row, with velocity
/// tolerance `tol` (m/s); impulse tolerances are `tol` times the row's step scale
/// `1 / N_ii` (the scaling of the residual, which makes the two comparable).
pub fn check_complementarity(
    problem: &CcpProblem,
    gamma: &[f64],
    tol: f64,
) -> Result<(), CcpError> {
    let fail = |kind, row, detail| Err(CcpError::NotComplementary { kind, row, detail });
    let c = gradient(problem, gamma);
    let s = problem.sections();
    let (lo, hi) = problem.box_bounds();
    for i in 0..problem.n_rows() {
        if !gamma[i].is_finite() || !c[i].is_finite() {
            return fail(
                "any",
                i,
                format!("non-finite g = {} or c = {}", gamma[i], c[i]),
            );
        }
    }
    for i in s.bilateral.clone() {
        if c[i].abs() > tol {
            return fail("bilateral", i, format!("|c| = {:e} > {tol:e}", c[i].abs()));
        }
    }
    for i in s.boxed.clone() {
        let k = i - s.boxed.start;
        let (g, tg) = (gamma[i], tol * problem.residual_scale(i));
        if g < lo[k] || g > hi[k] {
            return fail("box", i, format!("g = {g} outside [{}, {}]", lo[k], hi[k]));
        }
        let (at_lo, at_hi) = (g - lo[k] <= tg, hi[k] - g <= tg);
        let ok = match (at_lo, at_hi) {
            (true, true) => true,
            (true, false) => c[i] >= -tol,
            (false, true) => c[i] <= tol,
            (false, false) => c[i].abs() <= tol,
        };
        if !ok {
            return fail(
                "box",
                i,
                format!("g = {g} in [{}, {}] with c = {:e}", lo[k], hi[k], c[i]),
            );
        }
    }
    for i in s.unilateral.clone() {
        let (g, sc) = (gamma[i], problem.residual_scale(i));
        if g < 0.0 {
            return fail("unilateral", i, format!("g = {g} < 0"));
        }
        if c[i] < -tol {
            return fail("unilateral", i, format!("c = {:e} < -{tol:e}", c[i]));
        }
        if (g * c[i]).abs() > tol * (g + sc * c[i].abs() + sc * tol) {
            return fail(
                "unilateral",
                i,
                format!("g c = {:e} (g = {g:e}, c = {:e})", g * c[i], c[i]),
            );
        }
    }
    for (k, t) in s.friction.clone().step_by(3).enumerate() {
        let mu = problem.friction_mu()[k];
        let (gn, gt) = (gamma[t], gamma[t + 1].hypot(gamma[t + 2]));
        if gn < 0.0 || gt > mu * gn * (1.0 + 1e-12) + 1e-300 {
            return fail(
                "friction",
                t,
                format!("g = {:?} outside the cone mu = {mu}", &gamma[t..t + 3]),
            );
        }
        let (cn, ct) = (c[t], c[t + 1].hypot(c[t + 2]));
        // -c in the polar cone  <=>  mu |c_t| <= c_n
        if mu * ct - cn > tol * (1.0 + mu) {
            return fail(
                "friction",
                t,
                format!("-c = {:?} not in the polar cone (mu = {mu})", &c[t..t + 3]),
            );
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..3).map(|j| gamma[t + j] * c[t + j]).sum();
        let gnorm = (gn * gn + gt * gt).sqrt();
        let cnorm = (cn * cn + ct * ct).sqrt();
        if gc.abs() > 2.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return fail(
                "friction",
                t,
                format!(
                    "g'c = {gc:e} (g = {:?}, c = {:?})",
                    &gamma[t..t + 3],
                    &c[t..t + 3]
                ),
            );
        }
    }
    for (k, t) in s.rolling.clone().step_by(6).enumerate() {
        let mu = problem.rolling_mu()[k];
        let g = &gamma[t..t + 6];
        let norms = [g[1].hypot(g[2]), g[3].abs(), g[4].hypot(g[5])];
        if g[0] < 0.0 || (0..3).any(|j| norms[j] > mu[j] * g[0] * (1.0 + 1e-12) + 1e-300) {
            return fail(
                "rolling",
                t,
                format!("g = {g:?} outside the cone mu = {mu:?}"),
            );
        }
        // -c in the polar cone  <=>  c in the dual cone  <=>  c_n >= sum_j mu_j |c_j|
        let cv = &c[t..t + 6];
        let cn = [cv[1].hypot(cv[2]), cv[3].abs(), cv[4].hypot(cv[5])];
        let dual = cv[0] - (0..3).map(|j| mu[j] * cn[j]).sum::<f64>();
        if dual < -tol * (1.0 + mu.iter().sum::<f64>()) {
            return fail(
                "rolling",
                t,
                format!("c = {cv:?} not in the dual cone (mu = {mu:?})"),
            );
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..6).map(|j| g[j] * cv[j]).sum();
        let gnorm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cnorm = cv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gc.abs() > 3.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return fail(
                "rolling",
                t,
                format!("g'c = {gc:e} (g = {g:?}, c = {cv:?})"),
            );
        }
    }
    let n = PER_BODY_ROWS;
    for (k, t) in s.rolling_per_body.clone().step_by(n).enumerate() {
        let m = problem.rolling_per_body_mu()[k];
        // Parts (first row, length, coefficient): sliding, spin, body A, body B.
        let parts = [(1, 2, m[0]), (3, 1, m[1]), (4, 3, m[2]), (7, 3, m[2])];
        let norm = |x: &[f64], (s, len, _): (usize, usize, f64)| {
            x[s..s + len].iter().map(|v| v * v).sum::<f64>().sqrt()
        };
        let g = &gamma[t..t + n];
        if g[0] < 0.0
            || parts
                .iter()
                .any(|&p| norm(g, p) > p.2 * g[0] * (1.0 + 1e-12) + 1e-300)
        {
            return fail(
                "per-body rolling",
                t,
                format!("g = {g:?} outside the cone mu = {m:?}"),
            );
        }
        // -c in the polar cone  <=>  c_n >= sum_parts mu_p |c_p|
        let cv = &c[t..t + n];
        let dual = cv[0] - parts.iter().map(|&p| p.2 * norm(cv, p)).sum::<f64>();
        if dual < -tol * (1.0 + m[0] + m[1] + 2.0 * m[2]) {
            return fail(
                "per-body rolling",
                t,
                format!("c = {cv:?} not in the dual cone (mu = {m:?})"),
            );
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..n).map(|j| g[j] * cv[j]).sum();
        let gnorm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cnorm = cv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gc.abs() > 4.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return fail(
                "per-body rolling",
                t,
                format!("g'c = {gc:e} (g = {g:?}, c = {cv:?})"),
            );
        }
    }
    Ok(())
}
