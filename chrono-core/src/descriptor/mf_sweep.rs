//! The matrix-free triplets ([`super::frames`]) one contact at a time, for Gauss–Seidel
//! sweeps: a solver keeps the world-frame velocity changes `ws = M^-1 D g` of the pure
//! spheres (6 per sphere, `[dv; dw]`), reads a contact's three rows of `D' ws` from its
//! normal, arms and frame (10 numbers instead of 36 Jacobian coefficients and 36 of
//! `M^-1 D`), and applies an impulse change `dg` as `dv = F / m`, `dw = (r x F) / J` on
//! side B and the opposite on side A, `F = n dg_n + u dg_u + w dg_w`. A pure sphere is
//! touched only by matrix-free triplets, so its `ws` is complete; every other block keeps
//! its explicit velocity. Spheres are numbered in block order, so a range of blocks is a
//! range of spheres (a window of `ws`, as for the explicit velocities).

use super::CcpProblem;
use super::frames::{NONE, frame_from};

impl CcpProblem {
    /// The matrix-free contact of friction triplet `k` (counted from the first triplet),
    /// or `None` if that triplet uses its explicit rows.
    pub fn mf_contact(&self, k: usize) -> Option<u32> {
        self.mf.of_triplet.get(k).copied().filter(|&c| c != NONE)
    }

    /// The number of pure spheres (6 entries each in `ws`).
    pub fn mf_spheres(&self) -> usize {
        self.mf.n_bodies()
    }

    /// The number of pure spheres whose variable block is below `block`.
    pub fn mf_spheres_before(&self, block: usize) -> usize {
        let map = &self.mf.block_sphere;
        map[block.min(map.len())..]
            .iter()
            .find(|&&s| s != NONE)
            .map_or(self.mf.n_bodies(), |&s| s as usize)
    }

    /// `ws = M^-1 D g` on the pure spheres, world frame, 6 per sphere.
    ///
    /// # Panics
    /// If `ws` is shorter than `6 mf_spheres()`.
    pub fn mf_gather(&self, gamma: &[f64], ws: &mut [f64]) {
        if self.mf.n_bodies() > 0 {
            self.mf.gather(gamma, ws);
        }
    }

    /// Contact `c`'s geometry and its spheres' inverse masses as one value
    /// ([`SphereContact`]), for a solver that sweeps the contacts many times.
    pub fn mf_sphere_contact(&self, c: u32) -> SphereContact {
        let mf = &self.mf;
        let c = c as usize;
        let at = |x: &[Vec<f64>; 3]| [x[0][c], x[1][c], x[2][c]];
        let n = at(&mf.c_n);
        let spheres = mf.c_body[c];
        let inv = spheres.map(|s| {
            if s == NONE {
                [0.0; 2]
            } else {
                mf.b_inv[s as usize]
            }
        });
        SphereContact {
            spheres,
            normal: n,
            rc: mf.c_rc[c],
            arms: [at(&mf.c_ra), at(&mf.c_rb)],
            inv,
        }
    }

    /// Contact `c`'s rows of `D' ws` (normal, then the two tangents), `ws` the window of
    /// sphere velocities from sphere `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn mf_dots_in(&self, c: u32, ws: &[f64], base: usize) -> [f64; 3] {
        self.mf_sphere_contact(c).dots_in(ws, base)
    }

    /// `ws += M^-1 D' dg` for contact `c` (its impulse change `dg` along normal and
    /// tangents), `ws` the window from sphere `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn mf_add_in(&self, c: u32, dg: &[f64; 3], ws: &mut [f64], base: usize) {
        self.mf_sphere_contact(c).add_in(dg, ws, base);
    }
}

/// One matrix-free contact as a value: its spheres (or `u32::MAX` for a side without
/// variables), its frame `[n, u, w]` (the tangents of [`crate::math::tangent_frame`]),
/// the arms `r_A`, `r_B` from the spheres' centres to the contact point (world, m), and
/// the spheres' `[1/m, 1/J]`. Its rows are `d . ((v_B + w_B x r_B) - (v_A + w_A x r_A))`
/// for `d` in the frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SphereContact {
    spheres: [u32; 2],
    /// The normal and its frame's division ([`frame_from`]): the tangents are rebuilt
    /// where used (a smaller value for the sweeps to stream; the same bits).
    normal: [f64; 3],
    rc: f64,
    arms: [[f64; 3]; 2],
    inv: [[f64; 2]; 2],
}

impl SphereContact {
    /// The frame `[n, u, w]`.
    #[inline(always)]
    fn dirs(&self) -> [[f64; 3]; 3] {
        let (u, w) = frame_from(&self.normal, self.rc);
        [self.normal, u, w]
    }

    /// The contact's three rows of `D' ws`, `ws` the sphere velocities (world frame, 6
    /// per sphere) from sphere `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn dots_in(&self, ws: &[f64], base: usize) -> [f64; 3] {
        let mut rel = [0.0; 3];
        for (side, sign) in [(0, -1.0), (1, 1.0)] {
            let s = self.spheres[side];
            if s == NONE {
                continue;
            }
            let o = 6 * (s as usize - base);
            let x: &[f64; 6] = ws[o..o + 6].try_into().expect("6");
            let r = &self.arms[side];
            let vp = [
                x[0] + (x[4] * r[2] - x[5] * r[1]),
                x[1] + (x[5] * r[0] - x[3] * r[2]),
                x[2] + (x[3] * r[1] - x[4] * r[0]),
            ];
            for k in 0..3 {
                rel[k] += sign * vp[k];
            }
        }
        let dot = |a: &[f64; 3]| a[0] * rel[0] + a[1] * rel[1] + a[2] * rel[2];
        let [n, u, w] = self.dirs();
        [dot(&n), dot(&u), dot(&w)]
    }

    /// The contact's 3x3 block of `D M^-1 D'` (without compliance) as the upper triangle
    /// `[nn, nu, nw, uu, uw, ww]`: `sum over sides of (1/m) d.e + (1/J) (r x d).(r x e)`.
    pub fn block(&self) -> [f64; 6] {
        let cross = |a: &[f64; 3], b: &[f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let mut out = [0.0; 6];
        for side in 0..2 {
            if self.spheres[side] == NONE {
                continue;
            }
            let [im, ij] = self.inv[side];
            let dirs = self.dirs();
            let rd = dirs.map(|d| cross(&self.arms[side], &d));
            let mut q = 0;
            for a in 0..3 {
                for b in a..3 {
                    out[q] += im * dot(&dirs[a], &dirs[b]) + ij * dot(&rd[a], &rd[b]);
                    q += 1;
                }
            }
        }
        out
    }

    /// The diagonal `[nn, uu, ww]` of [`block`](Self::block), by the same operations
    /// (the same bits).
    pub fn block_diagonal(&self) -> [f64; 3] {
        let dirs = self.dirs();
        let mut out = [0.0; 3];
        for side in 0..2 {
            if self.spheres[side] == NONE {
                continue;
            }
            let [im, ij] = self.inv[side];
            let r = &self.arms[side];
            for (o, d) in out.iter_mut().zip(&dirs) {
                let rd = [
                    r[1] * d[2] - r[2] * d[1],
                    r[2] * d[0] - r[0] * d[2],
                    r[0] * d[1] - r[1] * d[0],
                ];
                let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                let rr = rd[0] * rd[0] + rd[1] * rd[1] + rd[2] * rd[2];
                *o += im * dd + ij * rr;
            }
        }
        out
    }

    /// `ws += M^-1 D' dg` for an impulse change `dg` along the frame, `ws` from sphere
    /// `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn add_in(&self, dg: &[f64; 3], ws: &mut [f64], base: usize) {
        let [n, u, v] = &self.dirs();
        let f: [f64; 3] = std::array::from_fn(|k| n[k] * dg[0] + u[k] * dg[1] + v[k] * dg[2]);
        for (side, sign) in [(0, -1.0), (1, 1.0)] {
            let s = self.spheres[side];
            if s == NONE {
                continue;
            }
            let [im, ij] = self.inv[side];
            let r = &self.arms[side];
            let t = [
                r[1] * f[2] - r[2] * f[1],
                r[2] * f[0] - r[0] * f[2],
                r[0] * f[1] - r[1] * f[0],
            ];
            let o = 6 * (s as usize - base);
            let x: &mut [f64; 6] = (&mut ws[o..o + 6]).try_into().expect("6");
            for k in 0..3 {
                x[k] += sign * im * f[k];
                x[3 + k] += sign * ij * t[k];
            }
        }
    }
}
