//! Shared helpers of the solvers: element-wise vector loops that go parallel (rayon) above a
//! size threshold, warm-start sanitation, the final statistics and a history clock.
//!
//! Element-wise loops are deterministic for any thread count (every element is computed by
//! the same expression whatever thread runs it); reductions are not done here but through
//! [`chrono_core::descriptor::reduce`] or [`CcpProblem::dot`], which sum in a fixed order.

use std::time::Instant;

use chrono_core::descriptor::{CcpProblem, CcpWork, IterationRecord, SolveStats, reduce::sum_by};
use rayon::prelude::*;

/// Vectors shorter than this are processed on the calling thread (rayon's overhead would
/// dominate; the same threshold as the row loops of [`CcpProblem`]).
pub(crate) const PAR_MIN: usize = 4096;

/// `out[i] = f(i)` for every `i`, in parallel for long vectors.
pub(crate) fn fill_with(out: &mut [f64], f: impl Fn(usize) -> f64 + Sync + Send) {
    if out.len() >= PAR_MIN {
        out.par_iter_mut().enumerate().for_each(|(i, o)| *o = f(i));
    } else {
        for (i, o) in out.iter_mut().enumerate() {
            *o = f(i);
        }
    }
}

/// `y += a x`, in parallel for long vectors.
pub(crate) fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    assert_eq!(y.len(), x.len());
    if y.len() >= PAR_MIN {
        y.par_iter_mut()
            .zip(x.par_iter())
            .for_each(|(y, x)| *y += a * x);
    } else {
        y.iter_mut().zip(x).for_each(|(y, x)| *y += a * x);
    }
}

/// `(a[i], b[i]) = f(i)` for every `i` (two outputs of one pass), in parallel for long vectors.
pub(crate) fn fill2_with(
    a: &mut [f64],
    b: &mut [f64],
    f: impl Fn(usize) -> (f64, f64) + Sync + Send,
) {
    assert_eq!(a.len(), b.len());
    if a.len() >= PAR_MIN {
        a.par_iter_mut()
            .zip(b.par_iter_mut())
            .enumerate()
            .for_each(|(i, (x, y))| (*x, *y) = f(i));
    } else {
        for (i, (x, y)) in a.iter_mut().zip(b.iter_mut()).enumerate() {
            (*x, *y) = f(i);
        }
    }
}

/// Replace non-finite warm-start entries by zero, then project onto `Y`.
pub(crate) fn sanitize_and_project(problem: &CcpProblem, gamma: &mut [f64]) {
    for g in gamma.iter_mut() {
        if !g.is_finite() {
            *g = 0.0;
        }
    }
    problem.project(gamma);
}

/// Statistics of a problem with no rows: nothing to do, trivially converged.
pub(crate) fn empty_stats() -> SolveStats {
    SolveStats {
        iterations: 0,
        residual: 0.0,
        objective: 0.0,
        converged: true,
        apply_n: 0,
        history: Vec::new(),
    }
}

/// Statistics of the returned `gamma`, whose gradient `N g + r` is `grad`.
pub(crate) fn final_stats(
    problem: &CcpProblem,
    gamma: &[f64],
    grad: &[f64],
    work: &mut CcpWork,
    iterations: usize,
    apply_n: usize,
    tolerance: f64,
    history: Vec<IterationRecord>,
) -> SolveStats {
    let residual = problem.residual(gamma, grad, work);
    let objective = problem.objective_from_gradient(gamma, grad, work);
    SolveStats {
        iterations,
        residual,
        objective,
        converged: residual.is_finite() && objective.is_finite() && residual <= tolerance,
        apply_n,
        history,
    }
}

/// Power-iteration estimate of `L = lambda_max(S^1/2 N S^1/2)` with `S = diag(s)` (the
/// Lipschitz constant of the gradient in the metric `S^-1`), `iterations >= 1` products.
/// `y`, `q`, `nq` are scratch of length `m`. Returns a positive finite value (1 for a zero
/// operator). A power iteration underestimates `L`; callers guard with backtracking.
pub(crate) fn power_lipschitz(
    problem: &CcpProblem,
    s: &[f64],
    iterations: usize,
    y: &mut [f64],
    q: &mut [f64],
    nq: &mut [f64],
    work: &mut CcpWork,
) -> f64 {
    let m = s.len();
    // A fixed, "random-ish" positive start (golden-ratio sequence), not aligned with any
    // structure of the rows.
    fill_with(y, |i| {
        0.5 + ((i as f64 + 1.0) * 0.618_033_988_749_895).fract()
    });
    let mut lambda = 0.0;
    for _ in 0..iterations {
        let norm = problem.dot(y, y, work).sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        fill_with(q, |i| s[i].sqrt() * y[i] / norm);
        problem.apply_n(q, nq, work);
        fill_with(y, |i| s[i].sqrt() * nq[i]);
        lambda = sum_by(m, &mut work.partials, |i| y[i] * y[i]).sqrt();
    }
    if lambda > 0.0 && lambda.is_finite() {
        lambda
    } else {
        1.0
    }
}

/// Records the convergence history (only when asked: reading the clock is not free).
pub(crate) struct History {
    start: Option<Instant>,
    records: Vec<IterationRecord>,
}

impl History {
    /// A recorder; `enabled = false` makes every call a no-op.
    pub(crate) fn new(enabled: bool, max_iterations: usize) -> Self {
        let records = if enabled {
            Vec::with_capacity(max_iterations.min(1 << 16))
        } else {
            Vec::new()
        };
        Self {
            start: enabled.then(Instant::now),
            records,
        }
    }

    /// Record the residual after `iteration`, with the objective (computed only when
    /// recording) and the `apply_n`-equivalents spent so far.
    pub(crate) fn push(
        &mut self,
        iteration: usize,
        residual: f64,
        apply_n: usize,
        objective: impl FnOnce() -> f64,
    ) {
        if let Some(t0) = self.start {
            let time_s = t0.elapsed().as_secs_f64();
            self.records.push(IterationRecord {
                iteration,
                residual,
                objective: objective(),
                apply_n,
                time_s,
            });
        }
    }

    /// The records.
    pub(crate) fn into_records(self) -> Vec<IterationRecord> {
        self.records
    }
}

/// Panics unless `gamma` has one entry per row of `problem` (a caller's bug, not bad data).
pub(crate) fn check_gamma_len(problem: &CcpProblem, gamma: &[f64]) {
    assert_eq!(
        gamma.len(),
        problem.n_rows(),
        "gamma.len() must equal problem.n_rows()"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fill_is_the_same_sequential_and_parallel() {
        for n in [10, PAR_MIN + 7] {
            let mut a = vec![0.0; n];
            let mut b = vec![0.0; n];
            fill_with(&mut a, |i| i as f64 * 0.5);
            fill2_with(&mut a, &mut b, |i| (i as f64, -(i as f64)));
            assert!(a.iter().enumerate().all(|(i, x)| *x == i as f64));
            assert!(b.iter().enumerate().all(|(i, x)| *x == -(i as f64)));
        }
    }
}
