//! Density rows: SPH density summation and the Jacobian of the density constraint
//! `C_i = rho_i / rho_0 - 1` of particles that are 3-dof variables of the CCP, shared by the
//! constraint fluid (chrono-cfluid) and the split MPM (chrono-mpm; pressure by these rows
//! on the markers). Moved here from chrono-cfluid (issue 25) so both use one copy.
//!
//! With free particles `0..n_free` (the variables) followed by fixed markers
//! `n_free..n_static` (walls: no variables) and body markers (`n_static..`, moving with a
//! rigid body), one kernel mass `m_k` for all, `x_ij = x_i - x_j` (minimum image on
//! periodic axes) and `grad_i W_ij = F(r_ij) x_ij` ([`Kernel::grad_factor`]):
//!
//! ```text
//! rho_i = m_k W(0) + sum_j m_k W(r_ij)                   (all neighbours)
//! C_i   = rho_i / rho_0 - 1
//! dC_i/dx_j = -(m_k / rho_0) F(r_ij) x_ij                (j != i, free only)
//! dC_i/dx_i =  (m_k / rho_0) sum_j F(r_ij) x_ij          (all neighbours, markers too)
//! ```
//!
//! The fixed markers enter the density sum and the self term, so a particle pressed
//! against a wall sees its density rise and its row pushes it back, although the markers
//! carry no variables. The row stored is `D_i = -grad C_i`, so that its multiplier `g_i`
//! (N m s) is a pressure impulse, positive when it pushes (`g_i / h = p_i m_k / rho_0`).
//!
//! Body markers move with a rigid body `b`: `x_k = x_b + R r_k`, so
//! `dx_k/dt = v_b + w x (x_k - x_b)` and the row gets, besides the self term, one 6-entry
//! block on the body, `sum_k [c_k; (x_k - x_b) x c_k]` (world linear and angular parts,
//! `c_k = -dC_i/dx_k = (m_k/rho_0) F(r_ik) x_ik`); turning it into a body's own
//! coordinates is the caller's.
//!
//! The right-hand side, the compliance and the free-surface treatment are in
//! [`push_density_row`], [`compliance`] and [`SurfaceMode`]. Reference: H. Mazhar,
//! "Parallel multi-body dynamics with frictional contact and constraint fluids", PhD
//! thesis, UW-Madison 2016 (the density constraint as a CCP row); Monaghan, Rep. Prog.
//! Phys. 68 (2005) (the SPH summation).

use rayon::prelude::*;

use crate::particles::{CellGrid, Kernel, NeighborList, Positions};

mod rhs;
mod surface;
#[cfg(test)]
mod tests;

pub use rhs::{SurfaceMode, compliance, push_density_row};
pub use surface::SupportModel;

/// The coefficients of one density row: the particles it touches (itself first) and
/// three coefficients per particle, `D_i = -dC_i/dx_j`, 1/m. Kept per particle across
/// steps so that refilling it allocates nothing once warm.
#[derive(Debug, Clone, Default)]
pub struct RowBuf {
    /// Free particles of the row (the row's own first, except for marker rows).
    pub particles: Vec<u32>,
    /// Three coefficients per entry of `particles`, 1/m.
    pub coefs: Vec<f64>,
    /// `(body slot, [linear; angular])` of the attached bodies among the neighbours
    /// (world frame as filled here; the caller rotates the angular part into the body frame).
    pub bodies: Vec<(u32, [f64; 6])>,
}

/// The kernel data every density computation needs (borrowed from the caller).
#[derive(Clone, Copy)]
pub struct DensityField<'a> {
    /// The smoothing kernel.
    pub kernel: &'a Kernel,
    /// Kernel mass `m_k` in the sums, kg ([`lattice_mass`] makes a lattice sum to `rho_0`).
    pub mass: f64,
    /// Rest density `rho_0`, kg/m^3.
    pub rho_0: f64,
    /// The neighbour grid (its periodic axes give the minimum image).
    pub grid: &'a CellGrid,
    /// Positions of all particles and markers, m.
    pub pos: Positions<'a>,
    /// Neighbours within the kernel support, of every particle and marker.
    pub nbrs: &'a NeighborList,
    /// Number of free particles (the variables).
    pub n_free: usize,
    /// First body marker (free particles, then fixed markers, then body markers).
    pub n_static: usize,
    /// Body slot of each body marker.
    pub marker_owner: &'a [u32],
    /// Reference point `x_b` of each body slot (its position at the step), m.
    pub body_origin: &'a [[f64; 3]],
}

/// The kernel mass `m_k = rho_0 / sum_lattice W` of the cubic lattice of spacing `dp`
/// (self term included), kg: with it the density sum of a particle inside the lattice is
/// exactly `rho_0`, so the lattice starts at `C_i = 0` (with `m = rho_0 dp^3` a truncated
/// kernel is off by a few percent). It is the mass of the density sums only; the particles'
/// inertial mass may differ (chrono-cfluid's "Two masses") (the sum
/// runs over the lattice points of all three axes; a kernel of dimension 2 (1) sums
/// over one plane (line) of the lattice).
pub fn lattice_mass(kernel: &Kernel, dp: f64, rho_0: f64) -> f64 {
    let reach = (kernel.support() / dp).ceil() as i64;
    let (js, ks) = match kernel.dim() {
        1 => (0..=0, 0..=0),
        2 => (-reach..=reach, 0..=0),
        _ => (-reach..=reach, -reach..=reach),
    };
    let mut sum = 0.0;
    for k in ks {
        for j in js.clone() {
            for i in -reach..=reach {
                let r = dp * ((i * i + j * j + k * k) as f64).sqrt();
                sum += kernel.w(r);
            }
        }
    }
    rho_0 / sum
}

impl DensityField<'_> {
    /// Position of particle `i`, m.
    #[inline]
    pub fn x(&self, i: usize) -> [f64; 3] {
        [self.pos[0][i], self.pos[1][i], self.pos[2][i]]
    }

    /// `x_i - x_j` (minimum image on periodic axes), m.
    #[inline]
    pub fn displacement(&self, i: usize, j: usize) -> [f64; 3] {
        self.grid.displacement(self.x(i), self.x(j))
    }

    /// `rho_i = m_k W(0) + sum_j m_k W(r_ij)` by summation over all neighbours (free,
    /// fixed and body markers), kg/m^3.
    pub fn density(&self, i: usize) -> f64 {
        let mut rho = self.mass * self.kernel.w(0.0);
        for &j in self.nbrs.neighbors(i) {
            let d = self.displacement(i, j as usize);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            rho += self.mass * self.kernel.w(r);
        }
        rho
    }

    /// The densities of all free particles (`rho[..n_free]`), in parallel.
    pub fn densities(&self, rho: &mut [f64]) {
        rho[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, r)| *r = self.density(i));
    }

    /// Fills `row` with `D_i = -grad C_i` of free particle `i`.
    pub fn row(&self, i: usize, row: &mut RowBuf) {
        self.row_mapped(i, row, |c| c);
    }

    /// [`row`](Self::row) with every pair coefficient `c_ij` replaced by `map(c_ij)`
    /// (the self term the negated sum of the mapped ones).
    #[inline(always)]
    fn row_mapped(&self, i: usize, row: &mut RowBuf, map: impl Fn([f64; 3]) -> [f64; 3]) {
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
            // -dC_i/dx_j = +(m/rho_0) F x_ij
            let c = map([f * d[0], f * d[1], f * d[2]]);
            for a in 0..3 {
                self_term[a] += c[a];
            }
            if j < self.n_free {
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

    /// The moment matrix `M_i = -sum_j V_k F(r_ij) x_ij x_ij^T` of particle `i` over all
    /// its neighbours (free particles and markers; `V_k = m_k / rho_0`; dimensionless,
    /// the identity for a full support on the lattice the kernel mass is made for):
    /// `sum_j V_k (f_j - f_i) grad_i W_ij = M_i grad f` for a linear field `f`, so the
    /// SPH gradient is exact only where `M_i = I`.
    pub fn moment(&self, i: usize) -> [[f64; 3]; 3] {
        let s = self.mass / self.rho_0;
        let mut m = [[0.0; 3]; 3];
        for &j in self.nbrs.neighbors(i) {
            let d = self.displacement(i, j as usize);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = s * self.kernel.grad_factor(r);
            for (a, row) in m.iter_mut().enumerate() {
                for (b, e) in row.iter_mut().enumerate() {
                    *e -= f * d[a] * d[b];
                }
            }
        }
        m
    }

    /// `M_i^-1` ([`moment`](Self::moment)) when the smallest eigenvalue of `M_i` is at
    /// least `min_eigen`, else `None` (a truncated support: the free surface).
    pub fn correction(&self, i: usize, min_eigen: f64) -> Option<nalgebra::Matrix3<f64>> {
        let m = self.moment(i);
        let m = nalgebra::Matrix3::from_fn(|a, b| m[a][b]);
        if m.symmetric_eigenvalues().min() < min_eigen {
            return None;
        }
        m.try_inverse()
    }

    /// [`row`](Self::row) with the kernel gradient corrected (Bonet and Lok 1999,
    /// Comput. Methods Appl. Mech. Engrg. 180:97-115): every pair coefficient
    /// `c_ij = (m_k/rho_0) F(r_ij) x_ij` becomes `M_i^-1 c_ij`
    /// ([`correction`](Self::correction)), so for a linear velocity field `v = A x` the
    /// row gives `D_i . v = tr A` (the divergence, `dC_i/dt = -div v`) on any packing: a
    /// shear of a disordered packing no longer reads as a compression (the plain row
    /// gives `M_i : A`, nonzero for a shear where `M_i` is not isotropic). The row is then not the exact gradient of `C_i`: the drift of
    /// the density sums is left to the stabilization. Where the smallest eigenvalue of
    /// `M_i` is below `min_eigen` (the free surface) the plain row is kept.
    pub fn row_corrected(&self, i: usize, row: &mut RowBuf, min_eigen: f64) {
        match self.correction(i, min_eigen) {
            Some(l) => self.row_mapped(i, row, |c| {
                let v = l * nalgebra::Vector3::new(c[0], c[1], c[2]);
                [v.x, v.y, v.z]
            }),
            None => self.row(i, row),
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
    /// marker's own density constraint: its free neighbours get `(m/rho_0) F x_kj`, the
    /// marker's own motion (minus the sum over all neighbours but its body's markers) goes
    /// to its body's block, other bodies' markers to theirs, walls are fixed. Markers of
    /// the same body are skipped: a rigid motion does not change their distance, and their
    /// two contributions to the body block cancel. Leaves the row empty when the marker
    /// has no free neighbour (no row is needed).
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
            if j < self.n_free {
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
    /// the marker is fixed, so the row has entries on its free neighbours
    /// (`(m/rho_0) F x_kj`) and on the bodies of its body-marker neighbours only; other
    /// wall markers do not move. Left empty when the marker has no free neighbour.
    pub fn wall_row(&self, k: usize, row: &mut RowBuf) {
        row.particles.clear();
        row.coefs.clear();
        row.bodies.clear();
        let s = self.mass / self.rho_0;
        for &j in self.nbrs.neighbors(k) {
            let j = j as usize;
            if (self.n_free..self.n_static).contains(&j) {
                continue;
            }
            let d = self.displacement(k, j);
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let f = s * self.kernel.grad_factor(r);
            let c = [f * d[0], f * d[1], f * d[2]];
            if j < self.n_free {
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
                let k = self.n_free + m;
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

    /// The rows of all free particles (`rows[..n_free]`), in parallel.
    pub fn rows(&self, rows: &mut [RowBuf]) {
        rows[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, row)| self.row(i, row));
    }

    /// The rows of all free particles by [`row_corrected`](Self::row_corrected), in
    /// parallel.
    pub fn rows_corrected(&self, rows: &mut [RowBuf], min_eigen: f64) {
        rows[..self.n_free]
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, row)| self.row_corrected(i, row, min_eigen));
    }
}
