//! SPH density summation and the Jacobian of the density constraint.
//!
//! With fluid particles `0..n_fluid` followed by wall markers (same kernel mass `m`, no
//! variables), `x_ij = x_i - x_j` (minimum image on periodic axes) and
//! `grad_i W_ij = F(r_ij) x_ij` ([`Kernel::grad_factor`]):
//!
//! ```text
//! rho_i = m W(0) + sum_j m W(r_ij)                       (fluid and wall neighbours)
//! C_i   = rho_i / rho_0 - 1
//! dC_i/dx_j = -(m / rho_0) F(r_ij) x_ij                  (j != i, fluid only)
//! dC_i/dx_i =  (m / rho_0) sum_j F(r_ij) x_ij            (all neighbours, walls too)
//! ```
//!
//! The wall markers enter the density sum and the self term, so a particle pressed
//! against a wall sees its density rise and its row pushes it back, although the markers
//! carry no variables. The row stored is `D_i = -grad C_i` (see [`crate::fluid`]).
//!
//! Body markers (after the wall markers) move with a rigid body `b`:
//! `x_k = x_b + R r_k`, so `dx_k/dt = v_b + w x (x_k - x_b)` and the row gets, besides
//! the self term, one 6-entry block on the body, `sum_k [c_k; (x_k - x_b) x c_k]` (world
//! linear and angular parts, `c_k = -dC_i/dx_k = (m/rho_0) F(r_ik) x_ik`), turned into the
//! body's coordinates (angular velocity in the body frame) by the caller.

use chrono_core::particles::{CellGrid, Kernel, NeighborList, Positions};
use rayon::prelude::*;

use crate::surface::SupportModel;

/// The coefficients of one density row: the particles it touches (itself first) and
/// three coefficients per particle, `D_i = -dC_i/dx_j`, 1/m. Kept per particle across
/// steps so that refilling it allocates nothing once warm.
#[derive(Debug, Clone, Default)]
pub(crate) struct RowBuf {
    pub particles: Vec<u32>,
    pub coefs: Vec<f64>,
    /// `(body slot, [linear; angular])` of the attached bodies among the neighbours
    /// (world frame as filled here; the item rotates the angular part into the body frame).
    pub bodies: Vec<(u32, [f64; 6])>,
}

/// The kernel data every computation needs.
#[derive(Clone, Copy)]
pub(crate) struct Field<'a> {
    pub kernel: &'a Kernel,
    pub mass: f64,
    pub rho_0: f64,
    pub grid: &'a CellGrid,
    pub pos: Positions<'a>,
    pub nbrs: &'a NeighborList,
    pub n_fluid: usize,
    /// First body marker (fluid, then wall markers, then body markers).
    pub n_static: usize,
    /// Body slot of each body marker.
    pub marker_owner: &'a [u32],
    /// Reference point `x_b` of each body slot (its position at the step), m.
    pub body_origin: &'a [[f64; 3]],
}

impl Field<'_> {
    #[inline]
    pub fn x(&self, i: usize) -> [f64; 3] {
        [self.pos[0][i], self.pos[1][i], self.pos[2][i]]
    }

    #[inline]
    pub fn displacement(&self, i: usize, j: usize) -> [f64; 3] {
        self.grid.displacement(self.x(i), self.x(j))
    }

    /// `rho_i` by summation, kg/m^3.
    pub fn density(&self, i: usize) -> f64 {
        let mut rho = self.mass * self.kernel.w(0.0);
        for &j in self.nbrs.neighbors(i) {
            let d = self.displacement(i, j as usize);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            rho += self.mass * self.kernel.w(r);
        }
        rho
    }

    /// The support fractions `phi_i` of all fluid particles by `model` (see
    /// [`crate::surface`]), in parallel: the filled fraction `g_i = rho_i / rho_0` and the
    /// first moment `M_i = |sum_j (m / rho_0) W_ij (x_j - x_i)|` over every neighbour.
    pub fn support_fractions(&self, model: &SupportModel, phi: &mut [f64]) {
        let v = self.mass / self.rho_0;
        phi[..self.n_fluid]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, p)| {
                let mut g = v * self.kernel.w(0.0);
                let mut m = [0.0; 3];
                for &j in self.nbrs.neighbors(i) {
                    let d = self.displacement(i, j as usize);
                    let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let w = v * self.kernel.w(r);
                    g += w;
                    // x_j - x_i = -d
                    for a in 0..3 {
                        m[a] -= w * d[a];
                    }
                }
                *p = model.fraction(g, (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt());
            });
    }

    /// The densities of all fluid particles, in parallel.
    pub fn densities(&self, rho: &mut [f64]) {
        rho[..self.n_fluid]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, r)| *r = self.density(i));
    }

    /// Fills `row` with `D_i = -grad C_i`.
    pub fn row(&self, i: usize, row: &mut RowBuf) {
        row.particles.clear();
        row.coefs.clear();
        row.bodies.clear();
        row.particles.push(i as u32);
        row.coefs.extend_from_slice(&[0.0; 3]);
        let s = self.mass / self.rho_0;
        let mut self_term = [0.0; 3];
        for &j in self.nbrs.neighbors(i) {
            let j = j as usize;
            let d = self.displacement(i, j);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = s * self.kernel.grad_factor(r);
            for a in 0..3 {
                self_term[a] += f * d[a];
            }
            // -dC_i/dx_j = +(m/rho_0) F x_ij
            let c = [f * d[0], f * d[1], f * d[2]];
            if j < self.n_fluid {
                row.particles.push(j as u32);
                row.coefs.extend_from_slice(&c);
            } else if j >= self.n_static {
                self.add_body(row, j, c);
            }
        }
        for a in 0..3 {
            row.coefs[a] = -self_term[a];
        }
    }

    /// Adds `c` (the coefficients on the velocity of body marker `j`) to the block of
    /// `j`'s body in `row`: `[c; (x_j - x_b) x c]` (world frame).
    fn add_body(&self, row: &mut RowBuf, j: usize, c: [f64; 3]) {
        let slot = self.marker_owner[j - self.n_static];
        let arm = self
            .grid
            .displacement(self.x(j), self.body_origin[slot as usize]);
        let m = [
            arm[1] * c[2] - arm[2] * c[1],
            arm[2] * c[0] - arm[0] * c[2],
            arm[0] * c[1] - arm[1] * c[0],
        ];
        let k = match row.bodies.iter().position(|b| b.0 == slot) {
            Some(k) => k,
            None => {
                row.bodies.push((slot, [0.0; 6]));
                row.bodies.len() - 1
            }
        };
        let acc = &mut row.bodies[k].1;
        for a in 0..3 {
            acc[a] += c[a];
            acc[3 + a] += m[a];
        }
    }

    /// Fills `row` with `D_k = -grad C_k` of body marker `k` (`k >= n_static`), the
    /// marker's own density constraint: its fluid neighbours get `(m/rho_0) F x_kj`, the
    /// marker's own motion (minus the sum over all neighbours but its body's markers) goes
    /// to its body's block, other bodies' markers to theirs, walls are fixed. Markers of
    /// the same body are skipped: a rigid motion does not change their distance, and their
    /// two contributions to the body block cancel. Leaves the row empty when the marker
    /// has no fluid neighbour (no row is needed).
    pub fn marker_row(&self, k: usize, row: &mut RowBuf) {
        row.particles.clear();
        row.coefs.clear();
        row.bodies.clear();
        let s = self.mass / self.rho_0;
        let own = self.marker_owner[k - self.n_static];
        let mut self_term = [0.0; 3];
        let mut fluid = false;
        for &j in self.nbrs.neighbors(k) {
            let j = j as usize;
            if j >= self.n_static && self.marker_owner[j - self.n_static] == own {
                continue;
            }
            let d = self.displacement(k, j);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = s * self.kernel.grad_factor(r);
            let c = [f * d[0], f * d[1], f * d[2]];
            for a in 0..3 {
                self_term[a] += c[a];
            }
            if j < self.n_fluid {
                fluid = true;
                row.particles.push(j as u32);
                row.coefs.extend_from_slice(&c);
            } else if j >= self.n_static {
                self.add_body(row, j, c);
            }
        }
        if !fluid {
            row.particles.clear();
            row.coefs.clear();
            row.bodies.clear();
            return;
        }
        self.add_body(row, k, self_term.map(|x| -x));
    }

    /// Fills `row` with `D_k = -grad C_k` of wall marker `k` (`n_fluid <= k < n_static`):
    /// the marker is fixed, so the row has entries on its fluid neighbours
    /// (`(m/rho_0) F x_kj`) and on the bodies of its body-marker neighbours only; other
    /// wall markers do not move. Left empty when the marker has no fluid neighbour.
    pub fn wall_row(&self, k: usize, row: &mut RowBuf) {
        row.particles.clear();
        row.coefs.clear();
        row.bodies.clear();
        let s = self.mass / self.rho_0;
        for &j in self.nbrs.neighbors(k) {
            let j = j as usize;
            if (self.n_fluid..self.n_static).contains(&j) {
                continue;
            }
            let d = self.displacement(k, j);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = s * self.kernel.grad_factor(r);
            let c = [f * d[0], f * d[1], f * d[2]];
            if j < self.n_fluid {
                row.particles.push(j as u32);
                row.coefs.extend_from_slice(&c);
            } else {
                self.add_body(row, j, c);
            }
        }
        if row.particles.is_empty() {
            row.bodies.clear();
        }
    }

    /// The rows and densities of all wall markers, in parallel.
    pub fn wall_rows(&self, rows: &mut [RowBuf], rho: &mut [f64]) {
        rows.par_iter_mut()
            .zip(rho.par_iter_mut())
            .enumerate()
            .for_each(|(m, (row, r))| {
                let k = self.n_fluid + m;
                self.wall_row(k, row);
                *r = self.density(k);
            });
    }

    /// The rows and densities of all body markers, in parallel.
    pub fn marker_rows(&self, rows: &mut [RowBuf], rho: &mut [f64]) {
        rows.par_iter_mut()
            .zip(rho.par_iter_mut())
            .enumerate()
            .for_each(|(m, (row, r))| {
                let k = self.n_static + m;
                self.marker_row(k, row);
                *r = self.density(k);
            });
    }

    /// All fluid rows, in parallel.
    pub fn rows(&self, rows: &mut [RowBuf]) {
        rows[..self.n_fluid]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, row)| self.row(i, row));
    }

    /// The multipliers of one Jacobi sweep of the position projection (see
    /// [`CfluidSettings::position_iterations`](crate::CfluidSettings::position_iterations)):
    /// `lambda_i = -C_i / (sum_k |dC_i/dx_k|^2)` for a compressed particle (`C_i > 0`,
    /// `k` over `i` and its fluid neighbours), 0 otherwise (a deficit is never pulled
    /// back). Fills `rho` with the densities; returns the largest `C_i`.
    pub fn projection(&self, rho: &mut [f64], lambda: &mut [f64]) -> f64 {
        let s = self.mass / self.rho_0;
        rho[..self.n_fluid]
            .par_iter_mut()
            .zip(lambda[..self.n_fluid].par_iter_mut())
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
                    if j < self.n_fluid {
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
    pub fn projection_step(&self, lambda: &[f64], relax: f64, out: &mut [[f64; 3]]) {
        let s = self.mass / self.rho_0;
        out[..self.n_fluid]
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, o)| {
                let mut acc = [0.0; 3];
                for &j in self.nbrs.neighbors(k) {
                    let j = j as usize;
                    let lj = if j < self.n_fluid { lambda[j] } else { 0.0 };
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
    pub fn xsph_corrected(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out[..self.n_fluid]
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
            .filter(|&j| j < self.n_fluid)
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
    pub fn xsph(&self, eps: f64, rho: &[f64], vel: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out[..self.n_fluid]
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
