//! The support fraction of a particle near a free surface: how much of a full kernel
//! support its neighbourhood would fill at the rest spacing, from the planar-surface
//! model of the lattice ([`SupportModel`]).
//!
//! A density row holds the kernel sum `rho_i = m_k sum_j W_ij` at `rho_0`. A particle
//! within `2 h_k` of a free surface misses the neighbours above it, so at the rest spacing
//! its sum is `phi_i rho_0` with `phi_i < 1`; with the reference `rho_0` its row is slack
//! and gravity packs the surface layers until their truncated sums reach `rho_0` (the top
//! layer of still water held 1.38 particles per `dp^2`, `docs/validation-cfluid.md`).
//! One sum cannot tell a compressed neighbourhood from a truncated one; its first moment
//! can: with `V = m_k / rho_0` (so that the full lattice has `sum_j V W_ij = 1`),
//!
//! ```text
//! g_i = sum_j V W_ij = rho_i / rho_0,      M_i = | sum_j V W_ij (x_j - x_i) |
//! ```
//!
//! (`j` over all neighbours, self, walls and body markers included; a full support has
//! `M_i ~ 0`). For a particle at depth `d` under a plane surface of lattice fluid at
//! number density `n` (relative to the lattice's), `g = n Gamma(d)` and `M = n P(d)`:
//! `Gamma` the filled fraction of the support and `P` the missing first moment, so the
//! ratio `M / g = P(d) / Gamma(d)` does not depend on `n` and gives `d`, and then
//! `phi_i = Gamma(d)`. The density constraint becomes `C_i = rho_i / rho_0 - phi_i`: a
//! surface particle at the lattice spacing sits at `C_i = 0`, and one that sinks into the
//! layer below is compressed (`C_i > 0`) and pushed back. `Gamma` and `P` are tabulated
//! on the lattice itself (layers of spacing `dp` parallel to the surface, each summed
//! exactly over its square in-plane lattice), at the depths `d = (k + 1/2) dp` where the
//! surface lies half a spacing above the top layer, and interpolated linearly between
//! them, after raising the ratio (over the top layer's) to the power
//! [`NOISE_EXPONENT`] so that the moment of a disordered bulk does not read as a
//! surface: on the lattice the top layer and the bulk get their exact fractions
//! (`C_i = 0`), the layers between read a full support within their own small deficit
//! (`1 - Gamma` = 9e-4 for the second layer at `h_k = 1.2 dp`, 0.016 at 1.5 dp). Off the lattice (a disordered packing, a curved surface) it is an
//! estimate; `phi_i` is frozen over a step (the row's Jacobian is that of `rho_i`).
//!
//! A kernel of dimension 2 (a plane-strain slab, chrono-mpm's split) has its surface
//! layers as lines of the square lattice in its plane, summed over one axis; dimension 3
//! sums each layer over its square plane. Moved here from chrono-cfluid (its
//! `surface_reference`) so that chrono-mpm's split uses the same model (issue 25).

use super::DensityField;
use crate::particles::Kernel;
use rayon::prelude::*;

/// The power of the ratio `M / g` over the top layer's that enters the table: 1 would
/// read the ratio as it is; at 1 the moment of a disordered bulk (ratio 0.05-0.2 of
/// the top layer's) gave bulk particles `phi` 0.95-0.99 and the column swelled by 0.24 %
/// (`cfluid-still-water --quick`, `docs/validation-cfluid.md`).
const NOISE_EXPONENT: i32 = 3;

/// The planar-surface model of a lattice of spacing `dp` under a kernel: filled fraction
/// `Gamma` and missing first moment `P` (m) at the depths `(k + 1/2) dp`, `k = 0..`, down
/// to the first depth with a full support (see the module documentation).
#[derive(Debug, Clone)]
pub struct SupportModel {
    gamma: Vec<f64>,
    moment: Vec<f64>,
}

impl SupportModel {
    /// The tables of `kernel` on the lattice of spacing `dp` (cubic; square in the
    /// kernel's plane for a kernel of dimension 2).
    pub fn new(kernel: &Kernel, dp: f64) -> Self {
        let reach = (kernel.support() / dp).ceil() as i64;
        // the in-plane axes of a layer: two (3-D), one (2-D)
        let js = if kernel.dim() >= 3 {
            -reach..=reach
        } else {
            0..=0
        };
        // layer sums A(l) = sum_plane W(dp |(i, j, l)|), normalized by the full sum
        let layer: Vec<f64> = (-reach..=reach)
            .map(|l| {
                let mut s = 0.0;
                for j in js.clone() {
                    for i in -reach..=reach {
                        s += kernel.w(dp * ((i * i + j * j + l * l) as f64).sqrt());
                    }
                }
                s
            })
            .collect();
        let full: f64 = layer.iter().sum();
        let a = |l: i64| layer[(l + reach) as usize] / full;
        let mut gamma = Vec::new();
        let mut moment = Vec::new();
        for k in 0..=reach {
            gamma.push((-reach..=k).map(a).sum());
            moment.push((k + 1..=reach).map(|l| l as f64 * dp * a(l)).sum());
        }
        Self { gamma, moment }
    }

    /// The support fraction `phi` of a particle whose filled fraction is `g` and whose
    /// first moment has the magnitude `m` (m): `Gamma(d)` at the depth `d` where
    /// `P(d) / Gamma(d) = m / g`, clamped to the table (`Gamma` of the top layer for a
    /// larger ratio, 1 for a full support). `phi` is 1 where `g` is not positive.
    pub fn fraction(&self, g: f64, m: f64) -> f64 {
        if g <= 0.0 || m <= 0.0 {
            return 1.0;
        }
        let ratio = |k: usize| self.moment[k] / self.gamma[k];
        // the disorder of a packing gives a full support a moment too (~0.05-0.2 of the
        // top layer's, still water); compressing small ratios keeps it from reading as
        // a surface, while the top layer's ratio maps to itself
        let r0 = ratio(0);
        let r = r0 * (m / g / r0).powi(NOISE_EXPONENT);
        if r >= ratio(0) {
            return self.gamma[0];
        }
        for k in 0..self.gamma.len() - 1 {
            if r >= ratio(k + 1) {
                // P and Gamma linear in d on [k, k + 1]: P(t) = r Gamma(t)
                let (g0, g1) = (self.gamma[k], self.gamma[k + 1]);
                let (p0, p1) = (self.moment[k], self.moment[k + 1]);
                let t = ((r * g0 - p0) / ((p1 - p0) - r * (g1 - g0))).clamp(0.0, 1.0);
                return g0 + t * (g1 - g0);
            }
        }
        1.0
    }

    /// The tabulated `(Gamma, P)` at the depths `(k + 1/2) dp`, -, m.
    pub fn table(&self) -> Vec<(f64, f64)> {
        self.gamma
            .iter()
            .copied()
            .zip(self.moment.iter().copied())
            .collect()
    }
}

impl DensityField<'_> {
    /// The support fractions `phi_i` of the free particles `0..n_free` by `model` (see
    /// [`SupportModel`]), in parallel: the filled fraction `g_i = rho_i / rho_0` and the
    /// first moment `M_i = |sum_j (m_k / rho_0) W_ij (x_j - x_i)|` over every neighbour
    /// (free, fixed and body markers). The density row of a surface particle is then
    /// `C_i = rho_i / rho_0 - phi_i`.
    pub fn support_fractions(&self, model: &SupportModel, phi: &mut [f64]) {
        let v = self.mass / self.rho_0;
        phi[..self.n_free]
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::KernelKind;

    fn model(h_over_dp: f64) -> (SupportModel, Kernel, f64) {
        let dp = 0.02;
        let k = Kernel::new(KernelKind::WendlandC2, h_over_dp * dp, 3).unwrap();
        (SupportModel::new(&k, dp), k, dp)
    }

    /// `g` and `M` of the particle at the origin in the half-lattice whose top layer is
    /// `top_rows_above` spacings above it, by brute force: a cubic lattice (`dim` 3) or the
    /// square lattice of a 2-D kernel (`dim` 2, the layers are lines).
    fn half_lattice(k: &Kernel, dp: f64, top_rows_above: i64, dim: u32) -> (f64, f64) {
        let reach = (k.support() / dp).ceil() as i64;
        let across = if dim == 3 { reach } else { 0 };
        let mut full = 0.0;
        let (mut g, mut m) = (0.0, 0.0);
        for l in -reach..=reach {
            for j in -across..=across {
                for i in -reach..=reach {
                    let w = k.w(dp * ((i * i + j * j + l * l) as f64).sqrt());
                    full += w;
                    if l <= top_rows_above {
                        g += w;
                        m += w * l as f64 * dp;
                    }
                }
            }
        }
        (g / full, m.abs() / full)
    }

    #[test]
    fn every_lattice_layer_gets_its_own_fraction() {
        for h in [1.2, 1.5] {
            let (sm, k, dp) = model(h);
            assert_layer_fractions(&sm, |above| half_lattice(&k, dp, above, 3), h);
        }
    }

    /// The top layer misses part of its support (0.81 at 1.2 dp in 3-D) and a full support
    /// has phi = 1; the top layer and a full support read exactly, the layers between a
    /// full support within their own small deficit (the noise exponent).
    fn assert_layer_fractions(sm: &SupportModel, lattice: impl Fn(i64) -> (f64, f64), h: f64) {
        let table = sm.table();
        assert!((0.4..0.9).contains(&table[0].0), "{table:?}");
        assert_eq!(table.last().unwrap().0, 1.0);
        for above in 0..4 {
            let (g, m) = lattice(above);
            let phi = sm.fraction(g, m);
            let tol = if above == 0 {
                1e-12
            } else {
                1.0 - table[1].0 + 1e-12
            };
            assert!((phi - g).abs() <= tol, "h {h}, layer {above}: {phi} vs {g}");
            assert!(phi >= g - 1e-12, "h {h}, layer {above}: {phi} vs {g}");
        }
    }

    #[test]
    fn a_2d_lattice_layer_gets_its_own_fraction() {
        // the plane-strain slab's kernel (chrono-mpm's split): layers are lines of the
        // square lattice; the top line and a full support exactly, the lines between
        // within their own small deficit
        for h in [1.2, 1.5] {
            let dp = 0.02;
            let k = Kernel::new(KernelKind::WendlandC2, h * dp, 2).unwrap();
            let sm = SupportModel::new(&k, dp);
            assert_layer_fractions(&sm, |above| half_lattice(&k, dp, above, 2), h);
        }
    }

    #[test]
    fn a_compressed_surface_layer_is_seen_compressed() {
        // the same truncated neighbourhood at 1 % more particles per volume: g and M both
        // scale by 1.01 (the ratio, and so the depth, is kept), so g / phi = 1.01
        let (sm, k, dp) = model(1.2);
        let (g, m) = half_lattice(&k, dp, 0, 3);
        let phi = sm.fraction(1.01 * g, 1.01 * m);
        assert!((1.01 * g / phi - 1.01).abs() < 1e-12);
    }

    #[test]
    fn a_full_or_empty_support_has_fraction_one() {
        let (sm, _, _) = model(1.2);
        assert_eq!(sm.fraction(1.0, 0.0), 1.0);
        assert_eq!(sm.fraction(0.0, 0.0), 1.0);
        // an isolated particle (self only, no moment) and a large ratio
        assert_eq!(sm.fraction(0.2, 1.0), sm.table()[0].0);
    }
}
