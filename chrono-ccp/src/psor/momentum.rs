//! The momentum step of [`Psor`] ([`PsorOptions::momentum`](super::PsorOptions::momentum)).

use chrono_core::descriptor::CcpProblem;
use chrono_core::descriptor::reduce::sum_by;
use rayon::prelude::*;

use super::Psor;

impl Psor {
    /// Back to the best iterate seen: `gamma`, its velocities and the momentum's history
    /// (the next step starts without momentum).
    pub(super) fn restart_from_best(
        &mut self,
        problem: &CcpProblem,
        gamma: &mut [f64],
        matrix_free: bool,
    ) {
        gamma.copy_from_slice(&self.best);
        if matrix_free {
            problem.minv_d_explicit(gamma, &mut self.w);
            problem.mf_gather(gamma, &mut self.ws);
        } else {
            problem.minv_d(gamma, &mut self.w);
        }
        self.g_prev.copy_from_slice(gamma);
        self.y.copy_from_slice(gamma);
        self.w_prev.copy_from_slice(&self.w);
        self.ws_prev.copy_from_slice(&self.ws);
    }

    /// The momentum step of [`PsorOptions::momentum`]: `gamma` holds `T(y_k)`; it
    /// becomes `y_{k+1}` (not projected: each unit of the next sweep projects its own
    /// update, from velocities consistent with `y`), `w` and `ws` its velocities.
    pub(super) fn extrapolate(&mut self, gamma: &mut [f64], k: &mut f64) {
        let (g_prev, y) = (&mut self.g_prev, &mut self.y);
        let agree = {
            let (g, p, y) = (&*gamma, &*g_prev, &*y);
            sum_by(g.len(), &mut self.partials, |i| {
                (g[i] - y[i]) * (g[i] - p[i])
            })
        };
        if agree < 0.0 {
            *k = 1.0;
        }
        let beta = (*k - 1.0) / (*k + 2.0);
        *k += 1.0;
        // y_{k+1}, not projected: the next sweep starts from it (each unit's update
        // projects), and its velocities follow by linearity
        gamma
            .par_iter_mut()
            .zip(g_prev.par_iter_mut())
            .zip(y.par_iter_mut())
            .with_min_len(4096)
            .for_each(|((g, p), y)| {
                let t = *g;
                *g = t + beta * (t - *p);
                *p = t;
                *y = *g;
            });
        // (the explicit velocities stay zero where only matrix-free spheres have rows)
        let explicit = if self.w_zero {
            None
        } else {
            Some((&mut self.w, &mut self.w_prev))
        };
        for (w, p) in explicit
            .into_iter()
            .chain([(&mut self.ws, &mut self.ws_prev)])
        {
            w.par_iter_mut()
                .zip(p.par_iter_mut())
                .with_min_len(4096)
                .for_each(|(w, p)| {
                    let t = *w;
                    *w = t + beta * (t - *p);
                    *p = t;
                });
        }
    }
}
