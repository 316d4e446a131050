//! A friction triplet's three rows read and updated together: where the rows of a
//! triplet touch the same one or two rigid-body blocks (6 coefficients each, stored one
//! row after the other), the block velocities are loaded once for the three dot products
//! and the three `M^-1 D` updates, instead of decoding each row's entries on their own
//! ([`CcpProblem::row_dot`], [`CcpProblem::row_add_minv`]). The sums and updates are the
//! same operations in the same order as those row by row, so the results are the same
//! bits (test `fused_triplets_match_the_row_by_row_path`). Used by the Gauss–Seidel sweeps
//! of chrono-ccp's PSOR, where the per-row decoding was most of a granular sweep.

use super::CcpProblem;

/// Where a triplet's rows live when they can be fused: the first coefficient of its first
/// row, the dof offsets of its blocks, and the number of blocks (1 or 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FusedTriplet {
    coef: u32,
    off: [u32; 2],
    blocks: u8,
}

impl CcpProblem {
    /// The fused layout of the triplet whose first row is `t`, if its three rows have the
    /// same one or two blocks in the same order, each entry with 6 coefficients stored
    /// contiguously row after row; `None` otherwise (use the row-by-row methods).
    pub fn fused_triplet(&self, t: usize) -> Option<FusedTriplet> {
        let e0 = self.row_ptr[t] as usize;
        let n = self.row_ptr[t + 1] as usize - e0;
        if !(1..=2).contains(&n) {
            return None;
        }
        let coef = self.ent_coef[e0];
        for r in 0..3 {
            if self.row_ptr[t + r + 1] as usize - self.row_ptr[t + r] as usize != n {
                return None;
            }
            for k in 0..n {
                let e = self.row_ptr[t + r] as usize + k;
                let expect = coef as usize + 6 * (n * r + k);
                if self.ent_coef[e] as usize != expect
                    || self.ent_coef[e + 1] as usize != expect + 6
                    || self.ent_off[e] != self.ent_off[e0 + k]
                {
                    return None;
                }
            }
        }
        let off = [self.ent_off[e0], self.ent_off[e0 + n - 1]];
        Some(FusedTriplet {
            coef,
            off,
            blocks: n as u8,
        })
    }

    /// `[D_t' v, D_{t+1}' v, D_{t+2}' v]` of a fused triplet, `v` the window of the dof
    /// vector from dof `base` (the same bits as [`CcpProblem::row_dot_in`] row by row).
    ///
    /// # Panics
    /// If a block lies outside the window.
    #[inline]
    pub fn fused_dots_in(&self, f: &FusedTriplet, v: &[f64], base: usize) -> [f64; 3] {
        let n = f.blocks as usize;
        let c = &self.coefs()[f.coef as usize..f.coef as usize + 18 * n];
        let mut out = [0.0; 3];
        for (r, o) in out.iter_mut().enumerate() {
            let mut s = 0.0;
            for k in 0..n {
                let off = f.off[k] as usize - base;
                let x: &[f64; 6] = v[off..off + 6].try_into().expect("6");
                let a: &[f64; 6] = c[6 * (n * r + k)..6 * (n * r + k) + 6]
                    .try_into()
                    .expect("6");
                for j in 0..6 {
                    s += a[j] * x[j];
                }
            }
            *o = s;
        }
        out
    }

    /// `v += dg_r M^-1 D_{t+r}` for the rows `r` of a fused triplet with `dg_r != 0`, `v`
    /// the window from dof `base` (the same bits as [`CcpProblem::row_add_minv_in`] row
    /// by row).
    ///
    /// # Panics
    /// If a block lies outside the window.
    #[inline]
    pub fn fused_add_minv_in(&self, f: &FusedTriplet, dg: &[f64; 3], v: &mut [f64], base: usize) {
        let n = f.blocks as usize;
        let m = &self.minv()[f.coef as usize..f.coef as usize + 18 * n];
        for (r, &s) in dg.iter().enumerate() {
            if s == 0.0 {
                continue;
            }
            for k in 0..n {
                let off = f.off[k] as usize - base;
                let x: &mut [f64; 6] = (&mut v[off..off + 6]).try_into().expect("6");
                let a: &[f64; 6] = m[6 * (n * r + k)..6 * (n * r + k) + 6]
                    .try_into()
                    .expect("6");
                for j in 0..6 {
                    x[j] += s * a[j];
                }
            }
        }
    }
}
