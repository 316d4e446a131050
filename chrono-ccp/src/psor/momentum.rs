//! The momentum step of [`Psor`] ([`PsorOptions::momentum`](super::PsorOptions::momentum)).

use chrono_core::descriptor::CcpProblem;
use chrono_core::descriptor::reduce::sum_by;
use rayon::prelude::*;

use super::Psor;
use crate::util::sanitize_and_project;

impl Psor {
    /// The momentum step of [`PsorOptions::momentum`]: `gamma` holds `T(y_k)`; it
    /// becomes `y_{k+1}` (projected onto `Y`), `w` its `M^-1 D g`.
    pub(super) fn extrapolate(&mut self, problem: &CcpProblem, gamma: &mut [f64], k: &mut f64) {
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
        // y_{k+1} before the projection (kept in `y`), and its velocities by linearity
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
        for (w, p) in [
            (&mut self.w, &mut self.w_prev),
            (&mut self.ws, &mut self.ws_prev),
        ] {
            w.par_iter_mut()
                .zip(p.par_iter_mut())
                .with_min_len(4096)
                .for_each(|(w, p)| {
                    let t = *w;
                    *w = t + beta * (t - *p);
                    *p = t;
                });
        }
        // the projection's changes, row by row (few: the extrapolation mostly stays in Y)
        sanitize_and_project(problem, gamma);
        let fs = problem.sections().friction.clone();
        for (i, (g, y)) in gamma.iter().zip(y.iter_mut()).enumerate() {
            if *g != *y {
                let c = if fs.contains(&i) {
                    self.mf_of.get((i - fs.start) / 3).copied()
                } else {
                    None
                };
                match c.filter(|&c| c != u32::MAX) {
                    Some(c) => {
                        let mut dg = [0.0; 3];
                        dg[(i - fs.start) % 3] = *g - *y;
                        problem.mf_add_in(c, &dg, &mut self.ws, 0);
                    }
                    None => problem.row_add_minv(i, *g - *y, &mut self.w),
                }
                *y = *g;
            }
        }
    }
}
