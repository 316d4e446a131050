//! Hub bodies of the joint block: a body that many joint rows touch (a vehicle's chassis,
//! which every suspension arm, sprocket and idler is jointed to) makes those rows a dense
//! clique of `N_BB`, and its Cholesky factor as dense there. The hub's share of `N_BB` is
//! of low rank, so it is taken out of the sparse factor and put back by the
//! Sherman–Morrison–Woodbury identity.
//!
//! With `U` the rows' Jacobian on the hub blocks (`n_B x k`, `k = 6` per hub) and `V` the
//! matching columns of `M^-1 D_B'` (`V = U M_h^-1`),
//!
//! ```text
//! N_BB = N' + U V',     N_BB^-1 r = y - W (I + V'W)^-1 V'y,     y = N'^-1 r,  W = N'^-1 U,
//! ```
//!
//! where `N'` is `N_BB` without the hubs' products: as sparse as the joint graph with the
//! hubs held fixed. Per factorization: `k` extra solves for `W` and a `k x k` LU of the
//! capacitance `I + V'W` (its eigenvalues are those of `I + M_h^-1 U'N'^-1 U`, all at
//! least 1); per solve: `V'y` over the hub rows, a `k x k` solve and `W t` (`k n_B`
//! multiply-adds, against the clique's `m^2/2` factor entries that each cost more than one
//! multiply-add in the sparse triangular solves).
//!
//! Used by the Schur solver's joint block (at most [`MAX_HUBS`] hubs, the busiest), not
//! by ADMM's blocks of joints and contacts.
//!
//! For the M113 (771 joint rows, 82 of them on the chassis) the factor shrinks from 10,149
//! to 7,028 entries. Reference: W. W. Hager, "Updating the inverse of a matrix", SIAM
//! Review 31(2), 1989 (the identity and its use with sparse factors).

use chrono_core::descriptor::CcpProblem;

/// A block is a hub when at least this many joint rows touch it.
pub(crate) const HUB_MIN_ROWS: usize = 32;

/// At most this many hubs (the busiest).
pub(crate) const MAX_HUBS: usize = 4;

/// The hubs of one joint block (see the [module documentation](self)).
#[derive(Default)]
pub(crate) struct Hubs {
    /// The hub blocks.
    blocks: Vec<u32>,
    /// Per slot (a hub row): its local row and its hub's index.
    slot_row: Vec<(u32, u32)>,
    /// Per slot: `D_i` on the hub (6 values), refreshed each factorization.
    u: Vec<[f64; 6]>,
    /// Per slot: `M^-1 D_i'` on the hub (6 values).
    v: Vec<[f64; 6]>,
    /// Stored values of `N'`'s pattern that still hold a hub product: (value index, slot
    /// of the row, slot of the column).
    corrections: Vec<(u32, u32, u32)>,
    /// `W = N'^-1 U`, `n_B x k` column-major.
    w: Vec<f64>,
    /// The capacitance `I + V'W`, LU-factored in place (row-major), and its pivots.
    lu: Vec<f64>,
    pivots: Vec<usize>,
    /// Scratch of length `k`.
    z: Vec<f64>,
    /// Scratch for the check of `W`: a copy of `U` and one column of `N' W`.
    u_copy: Vec<f64>,
    column: Vec<f64>,
    nb: usize,
}

impl Hubs {
    /// Forget the hubs (the pattern is factored whole).
    pub(crate) fn clear(&mut self) {
        self.blocks.clear();
        self.slot_row.clear();
        self.corrections.clear();
    }

    /// True if there is no hub.
    pub(crate) fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Find the hubs among the blocks (`by_block[b]`: the local rows touching block `b`):
    /// blocks that at least [`HUB_MIN_ROWS`] rows touch, each with 6 coefficients there (a
    /// rigid body), as long as every row keeps another block (a row on the hub alone would
    /// leave `N'` without it). Returns the mask of hub blocks.
    pub(crate) fn find(
        &mut self,
        problem: &CcpProblem,
        b_rows: &[usize],
        by_block: &[Vec<usize>],
    ) -> Vec<bool> {
        self.blocks.clear();
        self.slot_row.clear();
        self.corrections.clear();
        self.nb = b_rows.len();
        let mut mask = vec![false; by_block.len()];
        // The busiest blocks first, at most `MAX_HUBS` (each adds 6 dense columns to every
        // solve and 6 solves to every factorization).
        let mut order: Vec<usize> = (0..by_block.len())
            .filter(|&b| by_block[b].len() >= HUB_MIN_ROWS)
            .collect();
        order.sort_by_key(|&b| (std::cmp::Reverse(by_block[b].len()), b));
        for b in order {
            let rows = &by_block[b];
            if self.blocks.len() == MAX_HUBS {
                break;
            }
            let rigid = rows.iter().all(|&a| {
                let entries: Vec<_> = problem.row_entries(b_rows[a]).collect();
                entries.len() >= 2
                    && entries
                        .iter()
                        .all(|(blk, _, c, _)| blk.0 as usize != b || c.len() == 6)
            });
            if rigid {
                mask[b] = true;
                let h = self.blocks.len() as u32;
                self.blocks.push(b as u32);
                self.slot_row.extend(rows.iter().map(|&a| (a as u32, h)));
            }
        }
        mask
    }

    /// Record which stored values (`entries[k] = (i, j)` local rows) hold a product on a
    /// hub that both their rows touch: those are subtracted after each fill.
    pub(crate) fn plan_corrections(&mut self, entries: &[(usize, usize)]) {
        self.corrections.clear();
        if self.is_empty() {
            return;
        }
        let nb = self.nb;
        let mut slot_of = vec![u32::MAX; nb * self.blocks.len()];
        for (s, &(a, h)) in self.slot_row.iter().enumerate() {
            slot_of[h as usize * nb + a as usize] = s as u32;
        }
        for (k, &(i, j)) in entries.iter().enumerate() {
            for h in 0..self.blocks.len() {
                let (si, sj) = (slot_of[h * nb + i], slot_of[h * nb + j]);
                if si != u32::MAX && sj != u32::MAX {
                    self.corrections.push((k as u32, si, sj));
                }
            }
        }
    }

    /// Read the hub rows' coefficients from `problem` and subtract the hub products from the
    /// filled values of `N_BB` (leaving those of `N'`).
    pub(crate) fn refresh(&mut self, problem: &CcpProblem, b_rows: &[usize], vals: &mut [f64]) {
        self.u.clear();
        self.v.clear();
        for &(a, h) in &self.slot_row {
            let hub = self.blocks[h as usize];
            let (mut u, mut v) = ([0.0; 6], [0.0; 6]);
            for (blk, _, c, m) in problem.row_entries(b_rows[a as usize]) {
                if blk.0 == hub && c.len() == 6 {
                    u.copy_from_slice(c);
                    v.copy_from_slice(m);
                }
            }
            self.u.push(u);
            self.v.push(v);
        }
        for &(k, si, sj) in &self.corrections {
            let (u, v) = (&self.u[si as usize], &self.v[sj as usize]);
            vals[k as usize] -= (0..6).map(|t| u[t] * v[t]).sum::<f64>();
        }
    }

    /// The number of low-rank columns `k` (6 per hub).
    pub(crate) fn rank(&self) -> usize {
        6 * self.blocks.len()
    }

    /// `U` as `n_B x k` column-major, in `self.w`'s buffer, for the caller to solve in place
    /// into `W = N'^-1 U` and hand back by [`set_w`](Self::set_w).
    pub(crate) fn take_u(&mut self) -> Vec<f64> {
        let (nb, k) = (self.nb, self.rank());
        let mut w = std::mem::take(&mut self.w);
        w.clear();
        w.resize(nb * k, 0.0);
        for (s, &(a, h)) in self.slot_row.iter().enumerate() {
            for c in 0..6 {
                w[(6 * h as usize + c) * nb + a as usize] = self.u[s][c];
            }
        }
        self.u_copy.clear();
        self.u_copy.extend_from_slice(&w);
        w
    }

    /// True if `w` solves `N' W = U` to round-off (`mul(x, out)`: `out += N' x`), i.e. the
    /// factor of `N'` was not regularized (`U` as last handed out by
    /// [`take_u`](Self::take_u)).
    pub(crate) fn solves_u(&mut self, w: &[f64], mul: impl Fn(&[f64], &mut [f64])) -> bool {
        let nb = self.nb;
        let mut exact = true;
        for (wc, uc) in w.chunks(nb).zip(self.u_copy.chunks(nb)) {
            self.column.clear();
            self.column.resize(nb, 0.0);
            mul(wc, &mut self.column);
            let scale = uc.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let err = (self.column.iter().zip(uc)).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            exact &= err <= 1e-9 * scale;
        }
        exact
    }

    /// Keep `W = N'^-1 U` and factor the capacitance `I + V'W`.
    pub(crate) fn set_w(&mut self, w: Vec<f64>) {
        let (nb, k) = (self.nb, self.rank());
        self.w = w;
        self.lu.clear();
        self.lu.resize(k * k, 0.0);
        for r in 0..k {
            self.lu[r * k + r] = 1.0;
        }
        for (s, &(a, h)) in self.slot_row.iter().enumerate() {
            for t in 0..6 {
                let r = 6 * h as usize + t;
                let vs = self.v[s][t];
                for c in 0..k {
                    self.lu[r * k + c] += vs * self.w[c * nb + a as usize];
                }
            }
        }
        lu_factor(&mut self.lu, k, &mut self.pivots);
        self.z.clear();
        self.z.resize(k, 0.0);
    }

    /// `z = V'x` over the hub rows.
    fn v_t(&mut self, x: &[f64]) {
        self.z.iter_mut().for_each(|z| *z = 0.0);
        for (s, &(a, h)) in self.slot_row.iter().enumerate() {
            let xa = x[a as usize];
            for t in 0..6 {
                self.z[6 * h as usize + t] += self.v[s][t] * xa;
            }
        }
    }

    /// `x <- x - W (I + V'W)^-1 V'x`: turns `y = N'^-1 r` into `N_BB^-1 r` (one column).
    pub(crate) fn apply(&mut self, x: &mut [f64]) {
        let (nb, k) = (self.nb, self.rank());
        self.v_t(x);
        lu_solve(&self.lu, k, &self.pivots, &mut self.z);
        for c in 0..k {
            let t = self.z[c];
            if t != 0.0 {
                for (xi, wi) in x.iter_mut().zip(&self.w[c * nb..(c + 1) * nb]) {
                    *xi -= wi * t;
                }
            }
        }
    }

    /// `out += U V'x`: the hubs' share of `N_BB x` (one column).
    pub(crate) fn mul_add(&mut self, x: &[f64], out: &mut [f64]) {
        self.v_t(x);
        for (s, &(a, h)) in self.slot_row.iter().enumerate() {
            let z = &self.z[6 * h as usize..6 * h as usize + 6];
            out[a as usize] += (0..6).map(|t| self.u[s][t] * z[t]).sum::<f64>();
        }
    }
}

/// LU factorization with partial pivoting of the row-major `n x n` matrix `a`, in place.
fn lu_factor(a: &mut [f64], n: usize, piv: &mut Vec<usize>) {
    piv.clear();
    for col in 0..n {
        let p = (col..n)
            .max_by(|&i, &j| a[i * n + col].abs().total_cmp(&a[j * n + col].abs()))
            .unwrap_or(col);
        piv.push(p);
        if p != col {
            for c in 0..n {
                a.swap(col * n + c, p * n + c);
            }
        }
        let d = a[col * n + col];
        if d == 0.0 {
            continue;
        }
        for r in col + 1..n {
            let f = a[r * n + col] / d;
            a[r * n + col] = f;
            for c in col + 1..n {
                a[r * n + c] -= f * a[col * n + c];
            }
        }
    }
}

/// Solve with the factor of [`lu_factor`], in place.
fn lu_solve(a: &[f64], n: usize, piv: &[usize], x: &mut [f64]) {
    for (col, &p) in piv.iter().enumerate() {
        x.swap(col, p);
    }
    for r in 0..n {
        let s: f64 = (0..r).map(|c| a[r * n + c] * x[c]).sum();
        x[r] -= s;
    }
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|c| a[r * n + c] * x[c]).sum();
        x[r] = (x[r] - s) / a[r * n + r];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_a_pivoting_system() {
        // Needs a row swap (zero leading pivot).
        let a0 = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 2.0, 0.0, 3.0];
        let mut a = a0;
        let mut piv = Vec::new();
        lu_factor(&mut a, 3, &mut piv);
        let x_true = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|r| (0..3).map(|c| a0[r * 3 + c] * x_true[c]).sum())
            .collect();
        lu_solve(&a, 3, &piv, &mut b);
        for (x, t) in b.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-12, "{b:?}");
        }
    }
}
