//! A few rows of a [`CcpProblem`] gathered into a packed form, for a solver that applies the
//! same rows many times in one solve: the Schur solver's joint rows (`D_B v` and `v += M^-1
//! D_B' g_B` once per completed step, about 64 times a step for the M113's 760 joint
//! rows). A row on one or two rigid bodies keeps its 6 or 12 coefficients and `M^-1`
//! columns side by side with the bodies' dof offsets, so each use is 6 or 12 multiply-adds
//! without the per-entry index lookups of [`CcpProblem::row_dot`]; any other row (a shaft's
//! 1-dof entry, a particle's 3) is used through the problem. The same sums in the same
//! order as the problem's own row operations, so the same bits.

use super::problem::CcpProblem;

/// Marks a packed row on one body (no second offset).
const ONE_BODY: u32 = u32::MAX;
/// Marks a row used through the problem (not packed).
const UNPACKED: u32 = u32::MAX - 1;

/// Rows of one problem in packed form, for a solver that applies the same rows many times
/// in one solve (the Schur solver's joint rows): a row on one or two rigid bodies keeps its
/// 6 or 12 coefficients and `M^-1` columns side by side with the bodies' dof offsets; any
/// other row is used through the problem. The same sums in the same order as
/// [`CcpProblem::row_dot`] and [`CcpProblem::row_add_minv`], so the same bits. Valid for the
/// problem they were [`pack`](PackedRows::pack)ed from until it is assembled again.
#[derive(Debug, Clone, Default)]
pub struct PackedRows {
    /// The problem's row of each packed row.
    rows: Vec<usize>,
    /// The dof offsets of the row's one or two rigid bodies (`[UNPACKED, _]`: not packed;
    /// `[a, ONE_BODY]`: one body).
    off: Vec<[u32; 2]>,
    /// `D_i` on the bodies, 6 values each, in the row's entry order.
    coef: Vec<[f64; 12]>,
    /// `M^-1 D_i'` on the bodies, likewise.
    minv: Vec<[f64; 12]>,
}

impl PackedRows {
    /// Pack the rows `rows` of `problem` (any order; `k`-th here is `rows[k]` there).
    ///
    /// # Panics
    /// If a row index is out of range.
    pub fn pack(&mut self, problem: &CcpProblem, rows: &[usize]) {
        self.rows.clear();
        self.off.clear();
        self.coef.clear();
        self.minv.clear();
        for &i in rows {
            let entries = problem.row_ptr[i] as usize..problem.row_ptr[i + 1] as usize;
            let six = entries
                .clone()
                .all(|e| problem.ent_coef[e + 1] as usize - problem.ent_coef[e] as usize == 6);
            let (mut off, mut coef, mut minv) = ([UNPACKED, ONE_BODY], [0.0; 12], [0.0; 12]);
            if six && (1..=2).contains(&entries.len()) {
                for (k, e) in entries.enumerate() {
                    let c0 = problem.ent_coef[e] as usize;
                    off[k] = problem.ent_off[e];
                    coef[6 * k..6 * k + 6].copy_from_slice(&problem.coefs()[c0..c0 + 6]);
                    minv[6 * k..6 * k + 6].copy_from_slice(&problem.minv()[c0..c0 + 6]);
                }
            }
            self.rows.push(i);
            self.off.push(off);
            self.coef.push(coef);
            self.minv.push(minv);
        }
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True if there are no rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// `D_i' v` for the `k`-th packed row `i` (the bits of [`CcpProblem::row_dot`]).
    #[inline]
    pub fn dot(&self, problem: &CcpProblem, k: usize, v: &[f64]) -> f64 {
        let [a, b] = self.off[k];
        if a == UNPACKED {
            return problem.row_dot(self.rows[k], v);
        }
        let c = &self.coef[k];
        let va: &[f64; 6] = v[a as usize..a as usize + 6].try_into().expect("6");
        let mut s = 0.0;
        for j in 0..6 {
            s += c[j] * va[j];
        }
        if b != ONE_BODY {
            let vb: &[f64; 6] = v[b as usize..b as usize + 6].try_into().expect("6");
            for j in 0..6 {
                s += c[6 + j] * vb[j];
            }
        }
        s
    }

    /// `v += s M^-1 D_i'` for the `k`-th packed row `i` (the bits of
    /// [`CcpProblem::add_row_velocity`] on `work.v`).
    #[inline]
    pub fn add_minv(&self, problem: &CcpProblem, k: usize, s: f64, v: &mut [f64]) {
        let [a, b] = self.off[k];
        if a == UNPACKED {
            problem.row_add_minv(self.rows[k], s, v);
            return;
        }
        let c = &self.minv[k];
        let va: &mut [f64; 6] = (&mut v[a as usize..a as usize + 6]).try_into().expect("6");
        for j in 0..6 {
            va[j] += s * c[j];
        }
        if b != ONE_BODY {
            let vb: &mut [f64; 6] = (&mut v[b as usize..b as usize + 6]).try_into().expect("6");
            for j in 0..6 {
                vb[j] += s * c[6 + j];
            }
        }
    }
}
