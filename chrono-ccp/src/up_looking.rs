//! A sparse Cholesky factor `P A P' = L L'` on a fixed pattern, for the small, often
//! refactored bilateral block of a mechanism ([`crate::sparse_bilateral`]).
//!
//! Everything that depends on the pattern alone is found once ([`UpLooking::new`]): the
//! permuted pattern of `A`, the elimination tree, for each column `k` the columns `j < k`
//! with `L_kj != 0` (the reach of `k` in the tree, Davis 2006, "Direct Methods for Sparse
//! Linear Systems", SIAM, sections 4.1-4.4) and where each `L_kj` is stored. A numeric
//! factorization is then the up-looking algorithm (row `k` of `L` by a sparse triangular
//! solve with the rows above it) with no graph work; a solve is a forward and a backward
//! substitution.
//!
//! The operations and their order are those of faer's simplicial `LL'` factorization and
//! solve (the pattern is checked against the symbolic factor faer computed, the same
//! regularization of small pivots), so the results are bit-identical to faer's: the
//! solver's results do not depend on which of the two ran. What this saves is faer's
//! per-call work on the pattern (the permutation of `A`, the reach of every column).

/// The factor on a fixed pattern (see the [module documentation](self)).
#[derive(Debug, Clone, Default)]
pub(crate) struct UpLooking {
    n: usize,
    /// `fwd[new] = old`, `inv[old] = new`.
    fwd: Vec<usize>,
    inv: Vec<usize>,
    /// Permuted upper triangle of `A` by columns: rows and the index of each value in the
    /// caller's storage order of `A`'s upper triangle.
    a_ptr: Vec<usize>,
    a_row: Vec<usize>,
    a_src: Vec<usize>,
    /// Columns `j` of row `k` of `L` (`reach_col[reach_ptr[k]..reach_ptr[k + 1]]`) in
    /// elimination order, and where each `L_kj` is stored.
    reach_ptr: Vec<usize>,
    reach_col: Vec<usize>,
    reach_pos: Vec<usize>,
    /// `L` by columns, the diagonal first, then rows in increasing order.
    l_ptr: Vec<usize>,
    l_row: Vec<usize>,
    l_val: Vec<f64>,
    /// `1 / L_jj`.
    inv_diag: Vec<f64>,
    /// Dense scratch of length `n`, zero between uses.
    x: Vec<f64>,
}

/// A pivot that stayed non-positive after regularization (1-based column, as faer).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NonPositivePivot(pub usize);

const NONE: usize = usize::MAX;

impl UpLooking {
    /// The pattern of `A` (upper triangle by columns: `col_ptr`, `row_idx`, in the storage
    /// order the values will come in), the fill-reducing permutation (`fwd[new] = old`,
    /// `inv[old] = new`) and the expected pattern of `L` (`l_col_ptr`, `l_row_idx`: the
    /// diagonal first in each column, then increasing rows). `None` if that pattern is not
    /// the one this factorization produces (the caller then keeps another factorization).
    pub(crate) fn new(
        col_ptr: &[usize],
        row_idx: &[usize],
        fwd: &[usize],
        inv: &[usize],
        l_col_ptr: &[usize],
        l_row_idx: &[usize],
    ) -> Option<Self> {
        let n = col_ptr.len().checked_sub(1)?;
        if fwd.len() != n || inv.len() != n || l_col_ptr.len() != n + 1 {
            return None;
        }
        // Permuted upper triangle, entries in the order of a pass over A's storage.
        let mut count = vec![0usize; n];
        let place = |old_i: usize, old_j: usize| {
            let (i, j) = (inv[old_i], inv[old_j]);
            if i <= j { (j, i) } else { (i, j) }
        };
        for old_j in 0..n {
            for &old_i in &row_idx[col_ptr[old_j]..col_ptr[old_j + 1]] {
                if old_i > old_j || old_i >= n {
                    return None;
                }
                count[place(old_i, old_j).0] += 1;
            }
        }
        let a_ptr = prefix_sum(&count);
        let nnz = a_ptr[n];
        let (mut a_row, mut a_src) = (vec![0; nnz], vec![0; nnz]);
        let mut cursor = a_ptr[..n].to_vec();
        for old_j in 0..n {
            for p in col_ptr[old_j]..col_ptr[old_j + 1] {
                let (k, i) = place(row_idx[p], old_j);
                a_row[cursor[k]] = i;
                a_src[cursor[k]] = p;
                cursor[k] += 1;
            }
        }
        // Elimination tree.
        let mut parent = vec![NONE; n];
        let mut flag = vec![NONE; n];
        for k in 0..n {
            flag[k] = k;
            for &i0 in &a_row[a_ptr[k]..a_ptr[k + 1]] {
                let mut i = i0;
                while i < k && flag[i] != k {
                    if parent[i] == NONE {
                        parent[i] = k;
                    }
                    flag[i] = k;
                    i = parent[i];
                }
            }
        }
        // Reach of every column: the tree paths from the rows of A's column k up to k,
        // each path in upward order, later paths first (a stack filled from the top).
        flag.fill(NONE);
        let mut stack = vec![0usize; n];
        let mut reach_ptr = vec![0usize];
        let mut reach_col = Vec::new();
        for k in 0..n {
            flag[k] = k;
            let mut top = n;
            for &i0 in &a_row[a_ptr[k]..a_ptr[k + 1]] {
                if i0 >= k {
                    continue;
                }
                let (mut i, mut len) = (i0, 0);
                while flag[i] != k {
                    stack[len] = i;
                    len += 1;
                    flag[i] = k;
                    i = parent[i];
                    if i == NONE {
                        return None;
                    }
                }
                stack.copy_within(..len, top - len);
                top -= len;
            }
            reach_col.extend_from_slice(&stack[top..]);
            reach_ptr.push(reach_col.len());
        }
        // Pattern of L: row k enters column j (after the diagonal) in increasing k.
        let mut l_count = vec![1usize; n];
        for &j in &reach_col {
            l_count[j] += 1;
        }
        let l_ptr = prefix_sum(&l_count);
        let mut l_row = vec![0usize; l_ptr[n]];
        let mut next: Vec<usize> = l_ptr[..n].to_vec();
        for (j, &p) in next.iter().enumerate() {
            l_row[p] = j;
        }
        let mut reach_pos = Vec::with_capacity(reach_col.len());
        for k in 0..n {
            for &j in &reach_col[reach_ptr[k]..reach_ptr[k + 1]] {
                next[j] += 1;
                l_row[next[j]] = k;
                reach_pos.push(next[j]);
            }
        }
        if l_ptr != l_col_ptr || l_row != l_row_idx {
            return None;
        }
        let len = l_row.len();
        Some(Self {
            n,
            fwd: fwd.to_vec(),
            inv: inv.to_vec(),
            a_ptr,
            a_row,
            a_src,
            reach_ptr,
            reach_col,
            reach_pos,
            l_ptr,
            l_row,
            l_val: vec![0.0; len],
            inv_diag: vec![0.0; n],
            x: vec![0.0; n],
        })
    }

    /// Factor `A` given its upper-triangle values in the storage order of the pattern.
    /// A pivot `d <= epsilon` is replaced by `delta` (dynamic regularization, `delta > 0`).
    /// Returns the number of pivots replaced.
    pub(crate) fn factor(
        &mut self,
        values: &[f64],
        delta: f64,
        epsilon: f64,
    ) -> Result<usize, NonPositivePivot> {
        let (eps, delta) = (epsilon.abs(), delta.abs());
        let mut regularized = 0;
        let (x, inv_diag) = (&mut self.x[..], &mut self.inv_diag[..]);
        let (l_ptr, l_row, l_val) = (&self.l_ptr[..], &self.l_row[..], &mut self.l_val[..]);
        for k in 0..self.n {
            let (a0, a1) = (self.a_ptr[k], self.a_ptr[k + 1]);
            for (&i, &src) in self.a_row[a0..a1].iter().zip(&self.a_src[a0..a1]) {
                x[i] += values[src];
            }
            let mut d = x[k];
            x[k] = 0.0;
            let (r0, r1) = (self.reach_ptr[k], self.reach_ptr[k + 1]);
            for (&j, &pos) in self.reach_col[r0..r1].iter().zip(&self.reach_pos[r0..r1]) {
                let lkj = x[j] * inv_diag[j];
                x[j] = 0.0;
                // Columns of L hold their rows in increasing order: those above k were
                // filled by the earlier rows.
                let p0 = l_ptr[j] + 1;
                let (done, rest) = l_val.split_at_mut(pos);
                for (&i, &lij) in l_row[p0..pos].iter().zip(&done[p0..]) {
                    x[i] -= lij * lkj;
                }
                d -= lkj * lkj;
                rest[0] = lkj;
            }
            if delta > 0.0 && d <= eps {
                d = delta;
                regularized += 1;
            }
            if d.is_nan() || d <= 0.0 {
                x.fill(0.0);
                return Err(NonPositivePivot(k + 1));
            }
            let lkk = d.sqrt();
            l_val[l_ptr[k]] = lkk;
            inv_diag[k] = lkk.recip();
        }
        Ok(regularized)
    }

    /// Solve `A X = R` in place for `cols` right-hand sides stored column-major in `rhs`
    /// (`n` rows each), with the last factor.
    pub(crate) fn solve(&mut self, rhs: &mut [f64], cols: usize) {
        let n = self.n;
        let y = &mut self.x;
        for c in 0..cols {
            let b = &mut rhs[c * n..(c + 1) * n];
            for (yi, &old) in y.iter_mut().zip(&self.fwd) {
                *yi = b[old];
            }
            // L y = P b.
            for j in 0..n {
                let yj = y[j] * self.inv_diag[j];
                y[j] = yj;
                let (p0, p1) = (self.l_ptr[j] + 1, self.l_ptr[j + 1]);
                for (&i, &lij) in self.l_row[p0..p1].iter().zip(&self.l_val[p0..p1]) {
                    y[i] -= lij * yj;
                }
            }
            // L' z = y, each dot product from the last row of the column up.
            for j in (0..n).rev() {
                let (p0, p1) = (self.l_ptr[j] + 1, self.l_ptr[j + 1]);
                let mut acc = 0.0;
                for (&i, &lij) in self.l_row[p0..p1].iter().zip(&self.l_val[p0..p1]).rev() {
                    acc += lij * y[i];
                }
                y[j] = (y[j] - acc) * self.inv_diag[j];
            }
            for (bi, &new) in b.iter_mut().zip(&self.inv) {
                *bi = y[new];
            }
        }
        y.fill(0.0);
    }
}

/// `[0, c0, c0 + c1, ...]`.
fn prefix_sum(count: &[usize]) -> Vec<usize> {
    let mut p = Vec::with_capacity(count.len() + 1);
    p.push(0);
    for &c in count {
        p.push(p[p.len() - 1] + c);
    }
    p
}
