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

    /// Contact `c`'s rows of `D' ws` (normal, then the two tangents), `ws` the window of
    /// sphere velocities from sphere `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn mf_dots_in(&self, c: u32, ws: &[f64], base: usize) -> [f64; 3] {
        let mf = &self.mf;
        let c = c as usize;
        let at = |x: &[Vec<f64>; 3]| [x[0][c], x[1][c], x[2][c]];
        let mut rel = [0.0; 3];
        let [sa, sb] = mf.c_body[c];
        for (s, r, sign) in [(sa, &mf.c_ra, -1.0), (sb, &mf.c_rb, 1.0)] {
            if s == NONE {
                continue;
            }
            let o = 6 * (s as usize - base);
            let x: &[f64; 6] = ws[o..o + 6].try_into().expect("6");
            let r = at(r);
            let vp = [
                x[0] + (x[4] * r[2] - x[5] * r[1]),
                x[1] + (x[5] * r[0] - x[3] * r[2]),
                x[2] + (x[3] * r[1] - x[4] * r[0]),
            ];
            for k in 0..3 {
                rel[k] += sign * vp[k];
            }
        }
        let n = at(&mf.c_n);
        let (u, v) = frame_from(&n, mf.c_rc[c]);
        let dot = |a: &[f64; 3]| a[0] * rel[0] + a[1] * rel[1] + a[2] * rel[2];
        [dot(&n), dot(&u), dot(&v)]
    }

    /// `ws += M^-1 D' dg` for contact `c` (its impulse change `dg` along normal and
    /// tangents), `ws` the window from sphere `base`.
    ///
    /// # Panics
    /// If a sphere of the contact lies outside the window.
    #[inline]
    pub fn mf_add_in(&self, c: u32, dg: &[f64; 3], ws: &mut [f64], base: usize) {
        let mf = &self.mf;
        let c = c as usize;
        let at = |x: &[Vec<f64>; 3]| [x[0][c], x[1][c], x[2][c]];
        let n = at(&mf.c_n);
        let (u, v) = frame_from(&n, mf.c_rc[c]);
        let f: [f64; 3] = std::array::from_fn(|k| n[k] * dg[0] + u[k] * dg[1] + v[k] * dg[2]);
        let [sa, sb] = mf.c_body[c];
        for (s, r, sign) in [(sa, &mf.c_ra, -1.0), (sb, &mf.c_rb, 1.0)] {
            if s == NONE {
                continue;
            }
            let [im, ij] = mf.b_inv[s as usize];
            let r = at(r);
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
