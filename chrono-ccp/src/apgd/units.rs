//! APGD's iteration for friction-only problems (granular material) in three passes over
//! the rows instead of about nine: the extrapolation `y = g + beta (g - g_prev)` (and its
//! gradient) and the projected step in one pass, the product `N g+ + r` in the problem's
//! passes, and every reduction the iteration needs (the line-search products, the
//! restart slope, the residual) in the same pass as the product, unit by unit while the
//! rows are in cache ([`CcpProblem::gradient_by_units`]).
//!
//! Each sum keeps the chunk order of [`sum_by`](chrono_core::descriptor::reduce::sum_by)
//! (a unit is three chunks of rows and one chunk of triplets), so the iterates are the same
//! bits as the general path's, for any thread count.

use chrono_core::descriptor::{
    CcpProblem, UNIT_ROWS, friction_residual_terms, project_friction_cones,
    reduce::{CHUNK, lane_sum},
};
use rayon::prelude::*;

use super::Apgd;

/// A triplet's `y`, `N y + r` and `g+` in the step pass.
type StepChunks<'a> = ((&'a mut [f64], &'a mut [f64]), &'a mut [f64]);

/// Below this many rows the step pass runs on the calling thread.
const PAR_MIN_ROWS: usize = 4096;

/// Rows per task of the step pass (whole triplets: element-wise work, so the split does not
/// change any value).
const STEP_ROWS: usize = 3 * 512;

/// The sums of one unit of rows: per chunk of [`CHUNK`] rows `d'(N d)`, `d'P^-1 d` and the
/// restart slope; over the unit's triplets the residual's sum of squares.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct UnitSums {
    dnd: [f64; 3],
    dpd: [f64; 3],
    slope: [f64; 3],
    chunks: usize,
    res2: f64,
}

/// The totals of a trial: `(d'N d, d'P^-1 d)`, the slope `(N y + r)'(g+ - g)` and the
/// residual of `g+` ([`CcpProblem::residual`], m/s).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct TrialSums {
    pub dnd: f64,
    pub dpd: f64,
    pub slope: f64,
    pub residual: f64,
}

impl Apgd {
    /// One trial of the line search on a friction-only problem: with `beta` given, first
    /// `y = g + beta (g - g_prev)` and `N y + r` likewise (`g_prev` and its gradient are in
    /// `g_new`, `grad_new`: the buffers of the last iteration); then
    /// `g_new = P_Y(y - P (N y + r) / l)`, `grad_new = N g_new + r` and the sums. With
    /// `prev_in_best` the previous iterate is in `best` instead of `g_new` (the solve swapped
    /// the buffers to keep the best iterate).
    pub(super) fn trial_units(
        &mut self,
        problem: &CcpProblem,
        l: f64,
        beta: Option<f64>,
        prev_in_best: bool,
    ) -> TrialSums {
        let t = 1.0 / l;
        let mu = problem.friction_mu();
        let (g, gr, grp, s) = (&self.g, &self.grad, &self.grad_new, &self.s);
        let best = prev_in_best.then_some(&self.best[..]);
        // One task per `STEP_ROWS` rows (whole triplets), its slices taken once.
        let step = |(c, ((y, gy), gn)): (usize, StepChunks)| {
            let base = c * STEP_ROWS;
            let n = gn.len();
            let (g, gr, grp, s) = (
                &g[base..base + n],
                &gr[base..base + n],
                &grp[base..base + n],
                &s[base..base + n],
            );
            // Row-wise first (plain loops over slices, which the compiler vectorizes: the same
            // operations per element, so the same bits), then the cone projections.
            if let Some(beta) = beta {
                // The general path's `gn + beta (gn - g)`: here `g` is the new iterate and
                // `gn` (or `best`) still holds the previous one.
                let gp: &[f64] = match best {
                    Some(b) => &b[base..base + n],
                    None => gn,
                };
                for ((((y, gy), &g), &gr), (&gp, &grp)) in (y.iter_mut())
                    .zip(gy.iter_mut())
                    .zip(g)
                    .zip(gr)
                    .zip(gp.iter().zip(grp))
                {
                    *y = g + beta * (g - gp);
                    *gy = gr + beta * (gr - grp);
                }
            }
            for (((gn, &y), &gy), &s) in gn.iter_mut().zip(&*y).zip(&*gy).zip(s) {
                *gn = y - t * s * gy;
            }
            project_friction_cones(&mu[base / 3..(base + n) / 3], gn);
        };
        let m = self.g.len();
        if m >= PAR_MIN_ROWS {
            (self.y.par_chunks_mut(STEP_ROWS))
                .zip(self.grad_y.par_chunks_mut(STEP_ROWS))
                .zip(self.g_new.par_chunks_mut(STEP_ROWS))
                .enumerate()
                .for_each(step);
        } else {
            (self.y.chunks_mut(STEP_ROWS))
                .zip(self.grad_y.chunks_mut(STEP_ROWS))
                .zip(self.g_new.chunks_mut(STEP_ROWS))
                .enumerate()
                .for_each(step);
        }

        let (y, gy, gn, g, si) = (&self.y, &self.grad_y, &self.g_new, &self.g, &self.s_inv);
        let scale = problem.scales();
        let sums = |rows: std::ops::Range<usize>, grn: &[f64]| {
            let mut u = UnitSums::default();
            let base = rows.start;
            for (c, c0) in rows.clone().step_by(CHUNK).enumerate() {
                let c1 = (c0 + CHUNK).min(rows.end);
                // Sliced to the chunk so the loop runs without per-element bounds checks,
                // summed in `lane_sum`'s order (that of `sum_by`, `sum2_by`).
                let n = c1 - c0;
                let (gn, y, grn, gy, si, g) = (
                    &gn[c0..c1],
                    &y[c0..c1],
                    &grn[c0 - base..c1 - base],
                    &gy[c0..c1],
                    &si[c0..c1],
                    &g[c0..c1],
                );
                let [a, b, sl] = lane_sum::<3>(n, |j| {
                    let d = gn[j] - y[j];
                    [d * (grn[j] - gy[j]), d * d * si[j], gy[j] * (gn[j] - g[j])]
                });
                (u.dnd[c], u.dpd[c], u.slope[c]) = (a, b, sl);
                u.chunks = c + 1;
            }
            let r = rows.clone();
            let (gn, sc, mu) = (
                &gn[r.clone()],
                &scale[r.clone()],
                &mu[r.start / 3..r.end / 3],
            );
            let mut terms = [0.0f64; UNIT_ROWS / 3];
            let terms = &mut terms[..mu.len()];
            friction_residual_terms(gn, grn, sc, mu, terms);
            let [res2] = lane_sum::<1>(mu.len(), |k| [terms[k]]);
            u.res2 = res2;
            u
        };
        let mut units = std::mem::take(&mut self.units);
        problem.gradient_by_units(gn, &mut self.grad_new, &mut self.work, &mut units, sums);
        let mut tot = TrialSums::default();
        let mut res2 = 0.0;
        for u in &units {
            for c in 0..u.chunks {
                tot.dnd += u.dnd[c];
                tot.dpd += u.dpd[c];
                tot.slope += u.slope[c];
            }
            res2 += u.res2;
        }
        self.units = units;
        tot.residual = (res2 / m as f64).sqrt();
        tot
    }
}

/// A unit is three chunks of rows and one chunk of triplets (what the sums above assume).
const _: () = assert!(UNIT_ROWS == 3 * CHUNK);
