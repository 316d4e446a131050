//! The fluid's own computations on the density field: the position projection, XSPH
//! (the support fractions of a truncated support are chrono-core's,
//! `DensityField::support_fractions`). The density sums and the rows
//! themselves are [`chrono_core::density_rows`] (shared with chrono-mpm's split).

use chrono_core::density_rows::DensityField;
use rayon::prelude::*;

/// The fluid's operations on a [`DensityField`] (fluid particles are its free particles
/// `0..n_free`, wall markers its fixed markers).
pub(crate) trait FluidField {
    fn projection(&self, rho: &mut [f64], lambda: &mut [f64]) -> f64;
    fn projection_step(&self, lambda: &[f64], relax: f64, out: &mut [[f64; 3]]);
    fn xsph_corrected(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]);
    fn fluid_neighbours(&self, i: usize) -> impl Iterator<Item = (usize, [f64; 3], f64)> + '_;
    fn xsph_at(
        &self,
        i: usize,
        eps: f64,
        rho: &[f64],
        vel: &[[f64; 3]],
        grad: Option<&[[f64; 3]; 3]>,
    ) -> [f64; 3];
    fn xsph(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]);
}

impl FluidField for DensityField<'_> {
    /// The multipliers of one Jacobi sweep of the position projection (see
    /// [`CfluidSettings::position_iterations`](crate::CfluidSettings::position_iterations)):
    /// `lambda_i = -C_i / (sum_k |dC_i/dx_k|^2)` for a compressed particle (`C_i > 0`,
    /// `k` over `i` and its fluid neighbours), 0 otherwise (a deficit is never pulled
    /// back). Fills `rho` with the densities; returns the largest `C_i`.
    fn projection(&self, rho: &mut [f64], lambda: &mut [f64]) -> f64 {
        let s = self.mass / self.rho_0;
        rho[..self.n_free]
            .par_iter_mut()
            .zip(lambda[..self.n_free].par_iter_mut())
            .enumerate()
            .map(|(i, (r, l))| {
                *r = self.density(i);
                let c = *r / self.rho_0 - 1.0;
                *l = 0.0;
                if c <= 0.0 {
                    return c;
                }
                let mut self_term = [0.0; 3];
                let mut sum2 = 0.0;
                for &j in self.nbrs.neighbors(i) {
                    let j = j as usize;
                    let d = self.displacement(i, j);
                    let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let f = s * self.kernel.grad_factor(r);
                    let g = [f * d[0], f * d[1], f * d[2]];
                    for a in 0..3 {
                        self_term[a] += g[a];
                    }
                    if j < self.n_free {
                        sum2 += g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
                    }
                }
                sum2 += self_term[0] * self_term[0]
                    + self_term[1] * self_term[1]
                    + self_term[2] * self_term[2];
                if sum2 > 0.0 {
                    *l = -c / sum2;
                }
                c
            })
            .reduce(|| f64::NEG_INFINITY, f64::max)
    }

    /// The position corrections of a projection sweep,
    /// `dx_k = sum_i lambda_i dC_i/dx_k = (m / rho_0) sum_j F(r_kj) x_kj (lambda_k + lambda_j)`
    /// (`lambda_j = 0` for markers), times `relax`. Symmetric in each pair, so the fluid's
    /// centre of mass does not move except by the walls' pushes.
    fn projection_step(&self, lambda: &[f64], relax: f64, out: &mut [[f64; 3]]) {
        let s = self.mass / self.rho_0;
        out[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, o)| {
                let mut acc = [0.0; 3];
                for &j in self.nbrs.neighbors(k) {
                    let j = j as usize;
                    let lj = if j < self.n_free { lambda[j] } else { 0.0 };
                    let l = lambda[k] + lj;
                    if l == 0.0 {
                        continue;
                    }
                    let d = self.displacement(k, j);
                    let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let f = s * self.kernel.grad_factor(r) * l;
                    for a in 0..3 {
                        acc[a] += f * d[a];
                    }
                }
                *o = [relax * acc[0], relax * acc[1], relax * acc[2]];
            });
    }

    /// Linearly corrected XSPH, fluid neighbours only: the smoothing of
    /// [`xsph`](Self::xsph) applied to the velocity minus its linear part,
    ///
    /// ```text
    /// v_i <- v_i + eps sum_j (2 m / (rho_i + rho_j)) (v_j - v_i - G_i (x_j - x_i)) W_ij
    /// G_i = [sum_j V_j (v_j - v_i) (grad_i W_ij)'] L_i^-1,
    /// L_i = sum_j V_j (x_j - x_i) (grad_i W_ij)',   V_j = m / rho_j
    /// ```
    ///
    /// (`G_i` the renormalized velocity gradient of Randles and Libersky 1996 / Bonet and
    /// Lok 1999, exact for a linear field on any neighbourhood with an invertible `L_i`).
    /// A linear velocity field is left unchanged everywhere, also where the support is cut
    /// by a free surface or a wall (plain XSPH there relaxes `v_i` toward the one-sided mean
    /// of its neighbours, an `O(h_k |grad v|)` drag on any smooth flow, e.g. a sloshing
    /// mode); the particle noise (the part of `v` that is not linear over the support) is
    /// smoothed as by plain XSPH. Where `det L_i` is below `1e-2` (a nearly isolated
    /// particle) `G_i = 0`: plain XSPH.
    fn xsph_corrected(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, o)| {
                let vi = vel[i];
                let mut l = [[0.0; 3]; 3];
                let mut g = [[0.0; 3]; 3];
                // d = x_i - x_j; grad_i W_ij = F d; x_j - x_i = -d
                for (j, d, r) in self.fluid_neighbours(i) {
                    let f = self.mass / rho[j] * self.kernel.grad_factor(r);
                    for a in 0..3 {
                        for b in 0..3 {
                            l[a][b] -= f * d[a] * d[b];
                            g[a][b] += f * (vel[j][a] - vi[a]) * d[b];
                        }
                    }
                }
                let grad = inverse3(&l).map_or([[0.0; 3]; 3], |li| mul3(&g, &li));
                *o = self.xsph_at(i, eps, rho, vel, Some(&grad));
            });
    }

    /// The fluid neighbours `j` of particle `i` (walls and markers skipped) with
    /// `d = x_i - x_j` and `r = |d|`.
    fn fluid_neighbours(&self, i: usize) -> impl Iterator<Item = (usize, [f64; 3], f64)> + '_ {
        (self.nbrs.neighbors(i).iter())
            .map(|&j| j as usize)
            .filter(|&j| j < self.n_free)
            .map(move |j| {
                let d = self.displacement(i, j);
                (j, d, (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
            })
    }

    /// `v_i + eps sum_j (2 m / (rho_i + rho_j)) (v_j - v_i - G (x_j - x_i)) W_ij` over the
    /// fluid neighbours (`G = 0` when `grad` is `None`: plain XSPH).
    fn xsph_at(
        &self,
        i: usize,
        eps: f64,
        rho: &[f64],
        vel: &[[f64; 3]],
        grad: Option<&[[f64; 3]; 3]>,
    ) -> [f64; 3] {
        let vi = vel[i];
        let mut acc = [0.0; 3];
        for (j, d, r) in self.fluid_neighbours(i) {
            let w = 2.0 * self.mass / (rho[i] + rho[j]) * self.kernel.w(r);
            for a in 0..3 {
                let dv = vel[j][a] - vi[a];
                acc[a] += w * match grad {
                    // x_j - x_i = -d
                    Some(g) => dv + (g[a][0] * d[0] + g[a][1] * d[1] + g[a][2] * d[2]),
                    None => dv,
                };
            }
        }
        [
            vi[0] + eps * acc[0],
            vi[1] + eps * acc[1],
            vi[2] + eps * acc[2],
        ]
    }

    /// XSPH smoothing (Monaghan 1989), fluid neighbours only:
    /// `v_i <- v_i + eps sum_j (2 m / (rho_i + rho_j)) (v_j - v_i) W_ij`.
    fn xsph(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, o)| *o = self.xsph_at(i, eps, rho, vel, None));
    }
}

/// `a b` for 3x3 matrices.
fn mul3(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}

/// The inverse of a 3x3 matrix, `None` when `|det| < 1e-2` (the renormalization matrix
/// of a full support is close to the identity).
fn inverse3(m: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c =
        |r0: usize, r1: usize, c0: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    let cof = [
        [c(1, 2, 1, 2), -c(1, 2, 0, 2), c(1, 2, 0, 1)],
        [-c(0, 2, 1, 2), c(0, 2, 0, 2), -c(0, 2, 0, 1)],
        [c(0, 1, 1, 2), -c(0, 1, 0, 2), c(0, 1, 0, 1)],
    ];
    let det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
    if det.is_nan() || det.abs() < 1e-2 {
        return None;
    }
    // inverse = adjugate / det, adjugate = cofactor transposed
    Some(std::array::from_fn(|r| {
        std::array::from_fn(|c| cof[c][r] / det)
    }))
}
