//! A sparse symmetric positive definite operator with a reusable Cholesky factorization:
//! the coupled mass operator ([`CoupledMass`]) of an implicit mesh in the system's CCP.
//!
//! The pattern (upper triangle, compressed columns) is fixed when the operator is built,
//! and so is the fill-reducing ordering and the symbolic analysis (faer's
//! `factorize_symbolic_cholesky`, approximate minimum degree). Each step only the values
//! change: [`SparseSpd::refactor`] copies them and runs the numeric `L L'` factorization
//! into the same buffers, so a step allocates nothing and does no symbolic work.
//!
//! The values live behind a mutex: the descriptor holds the operator through an `Arc`
//! (shared with the mesh that refactorizes it), and a solve needs scratch memory. The
//! descriptor calls the operator sequentially per block, so the lock is never contended.

use std::sync::{Mutex, MutexGuard};

use chrono_core::descriptor::CoupledMass;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, SparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::error::{FeaError, Result};

/// Right-hand sides solved per sweep in [`CoupledMass::apply_inverse_columns`] (the
/// scratch is sized for this many; faer's simplicial solves take them four at a time).
const SOLVE_COLUMNS: usize = 16;

struct Factor {
    /// The matrix: upper triangle, its values overwritten by each refactorization.
    upper: SparseColMat<usize, f64>,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// Scratch for factorization and solves (the larger of the two requirements).
    scratch: MemBuffer,
    /// Whether `l_values` holds the factor of the current values.
    factorized: bool,
    /// Whether faer chose a supernodal factor (see
    /// [`apply_inverse_columns`](CoupledMass::apply_inverse_columns)).
    supernodal: bool,
}

/// A sparse symmetric positive definite `n x n` operator `H` with a fixed pattern and a
/// reusable Cholesky factorization `P H P' = L L'` (see the module docs).
pub struct SparseSpd {
    n: usize,
    factor: Mutex<Factor>,
}

impl std::fmt::Debug for SparseSpd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let g = self.lock();
        f.debug_struct("SparseSpd")
            .field("n", &self.n)
            .field("nnz_upper", &g.upper.val().len())
            .field("nnz_factor", &g.l_values.len())
            .finish()
    }
}

impl SparseSpd {
    /// Build from the upper triangle `upper` (its values are not used; its pattern is
    /// analysed once). The operator must be [`refactor`](Self::refactor)ed before use.
    pub fn new(upper: SparseColMat<usize, f64>) -> Result<Self> {
        let n = upper.nrows();
        if n == 0 || upper.ncols() != n {
            return Err(FeaError::invalid(
                "spd.shape",
                format!("{}x{}", n, upper.ncols()),
                "must be square and non-empty",
            ));
        }
        let symbolic = factorize_symbolic_cholesky(
            upper.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| FeaError::Assembly(format!("symbolic Cholesky: {e:?}")))?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(SOLVE_COLUMNS, Par::Seq),
        ]);
        let l_values = vec![0.0; symbolic.len_val()];
        let supernodal = !matches!(symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_));
        Ok(Self {
            n,
            factor: Mutex::new(Factor {
                upper,
                symbolic,
                l_values,
                scratch: MemBuffer::new(req),
                factorized: false,
                supernodal,
            }),
        })
    }

    fn lock(&self) -> MutexGuard<'_, Factor> {
        // A panic inside a solve leaves plain numbers behind: the data is still usable.
        self.factor.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Number of stored values of the upper triangle (the length [`refactor`](Self::refactor)
    /// takes).
    pub fn nnz(&self) -> usize {
        self.lock().upper.val().len()
    }

    /// The pattern: column pointers and row indices of the upper triangle.
    pub fn pattern(&self) -> (Vec<usize>, Vec<usize>) {
        let g = self.lock();
        let s = g.upper.symbolic();
        (s.col_ptr().to_vec(), s.row_idx().to_vec())
    }

    /// Replace the values of `H` (upper triangle, in the order of the pattern) and
    /// factorize. Errors: wrong length, a non-finite value, a matrix that is not
    /// numerically positive definite (the operator then refuses to solve until the next
    /// successful refactorization).
    pub fn refactor(&self, values: &[f64]) -> Result<()> {
        let mut g = self.lock();
        let f = &mut *g;
        f.factorized = false;
        if values.len() != f.upper.val().len() {
            return Err(FeaError::invalid(
                "spd.values.len",
                values.len(),
                format!("must equal the pattern's {} entries", f.upper.val().len()),
            ));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(FeaError::invalid(
                format!("spd.values[{i}]"),
                values[i],
                "must be finite",
            ));
        }
        f.upper.val_mut().copy_from_slice(values);
        f.symbolic
            .factorize_numeric_llt(
                &mut f.l_values,
                f.upper.as_ref(),
                Side::Upper,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut f.scratch),
                Default::default(),
            )
            .map_err(|e| FeaError::Singular {
                step: 0,
                detail: format!("the matrix is not positive definite ({e:?})"),
            })?;
        f.factorized = true;
        Ok(())
    }
}

/// `out = A x` for the symmetric matrix whose upper triangle is `upper`.
pub(crate) fn symmetric_upper_mul(
    upper: SparseColMatRef<'_, usize, f64>,
    x: &[f64],
    out: &mut [f64],
) {
    out.fill(0.0);
    let s = upper.symbolic();
    let (cp, ri, val) = (s.col_ptr(), s.row_idx(), upper.val());
    for j in 0..upper.ncols() {
        for idx in cp[j]..cp[j + 1] {
            let (i, a) = (ri[idx], val[idx]);
            out[i] += a * x[j];
            if i != j {
                out[j] += a * x[i];
            }
        }
    }
}

impl CoupledMass for SparseSpd {
    fn ndof(&self) -> usize {
        self.n
    }

    fn apply(&self, x: &[f64], out: &mut [f64]) {
        let g = self.lock();
        symmetric_upper_mul(g.upper.as_ref(), &x[..self.n], &mut out[..self.n]);
    }

    /// `H^-1 x` by the two triangular solves; NaN if the last refactorization failed (the
    /// descriptor then reports a non-finite `M^-1 k` naming the dof).
    fn apply_inverse(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        let mut g = self.lock();
        let f = &mut *g;
        if !f.factorized {
            out[..n].fill(f64::NAN);
            return;
        }
        out[..n].copy_from_slice(&x[..n]);
        let rhs = MatMut::from_column_major_slice_mut(&mut out[..n], n, 1);
        LltRef::new(&f.symbolic, &f.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut f.scratch),
        );
    }

    /// `X <- H^-1 X` for `ncols` columns. A simplicial factor (the meshes' usual case:
    /// sparse columns) solves `SOLVE_COLUMNS` (16) per faer sweep: the factor is read once
    /// per sweep instead of once per column, and each column gets the same operations in
    /// the same order as in [`apply_inverse`](CoupledMass::apply_inverse) (the same bits,
    /// tested). A supernodal factor (dense blocks) solves column by column: its updates
    /// are dense matrix products whose kernel for several columns sums in another order
    /// than for one (last-digit differences, tested), and the descriptor's `M^-1 D` must
    /// not depend on how many rows share a block. NaN if the last refactorization failed.
    fn apply_inverse_columns(&self, x: &mut [f64], ncols: usize) {
        let n = self.n;
        let x = &mut x[..n * ncols];
        let mut g = self.lock();
        let f = &mut *g;
        if !f.factorized {
            x.fill(f64::NAN);
            return;
        }
        let per_sweep = if f.supernodal { 1 } else { SOLVE_COLUMNS };
        for block in x.chunks_mut(n * per_sweep) {
            let k = block.len() / n;
            let rhs = MatMut::from_column_major_slice_mut(block, n, k);
            LltRef::new(&f.symbolic, &f.l_values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                Par::Seq,
                MemStack::new(&mut f.scratch),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;

    fn tridiagonal(n: usize, d: f64) -> (SparseColMat<usize, f64>, Vec<f64>) {
        let mut t = Vec::new();
        for j in 0..n {
            if j > 0 {
                t.push(Triplet::new(j - 1, j, -1.0));
            }
            t.push(Triplet::new(j, j, d));
        }
        let m = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let v = m.val().to_vec();
        (m, v)
    }

    #[test]
    fn solves_and_refactors_with_the_same_pattern() {
        let n = 7;
        let (m, v) = tridiagonal(n, 4.0);
        let op = SparseSpd::new(m).unwrap();
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let (mut y, mut back) = (vec![0.0; n], vec![0.0; n]);
        for scale in [1.0, 3.0] {
            let vals: Vec<f64> = v.iter().map(|a| a * scale).collect();
            op.refactor(&vals).unwrap();
            op.apply_inverse(&x, &mut y);
            op.apply(&y, &mut back);
            for i in 0..n {
                assert!((back[i] - x[i]).abs() < 1e-13, "{scale} {i}");
            }
        }
    }

    #[test]
    fn indefinite_is_an_error_and_poisons_solves() {
        let (m, v) = tridiagonal(4, 1.0);
        let op = SparseSpd::new(m).unwrap();
        let e = op.refactor(&v).unwrap_err().to_string();
        assert!(e.contains("positive definite"), "{e}");
        let mut y = [0.0; 4];
        op.apply_inverse(&[1.0; 4], &mut y);
        assert!(y.iter().all(|x| x.is_nan()));
        let mut cols = [1.0; 8];
        op.apply_inverse_columns(&mut cols, 2);
        assert!(cols.iter().all(|x| x.is_nan()));
        assert!(op.refactor(&v[..2]).is_err());
    }

    /// Whether `op`'s factor is supernodal (dense blocks, solved by matrix products).
    fn supernodal(op: &SparseSpd) -> bool {
        op.lock().supernodal
    }

    /// Many right-hand sides at once (more than one sweep of [`SOLVE_COLUMNS`], and a
    /// remainder) give each column the bits of a one-column solve.
    fn assert_batches_equal_single_solves(m: SparseColMat<usize, f64>) {
        let n = m.nrows();
        let vals = m.val().to_vec();
        let op = SparseSpd::new(m).unwrap();
        op.refactor(&vals).unwrap();
        let ncols = 2 * SOLVE_COLUMNS + 3;
        let mut cols: Vec<f64> = (0..n * ncols)
            .map(|k| ((k * 7919) % 1013) as f64 / 1013.0 - 0.5)
            .collect();
        let rhs = cols.clone();
        op.apply_inverse_columns(&mut cols, ncols);
        let mut y = vec![0.0; n];
        for c in 0..ncols {
            op.apply_inverse(&rhs[c * n..(c + 1) * n], &mut y);
            for i in 0..n {
                assert_eq!(
                    y[i].to_bits(),
                    cols[c * n + i].to_bits(),
                    "column {c}, row {i} (supernodal: {})",
                    supernodal(&op)
                );
            }
        }
    }

    /// A 2-D grid Laplacian plus a diagonal shift (fill-in, a non-trivial ordering): a
    /// simplicial factor.
    #[test]
    fn column_batches_equal_single_solves_bit_for_bit() {
        let side = 12;
        let n = side * side;
        let mut t = Vec::new();
        for j in 0..n {
            let (x, y) = (j % side, j / side);
            t.push(Triplet::new(j, j, 4.5 + 0.01 * (j % 7) as f64));
            if x > 0 {
                t.push(Triplet::new(j - 1, j, -1.0));
            }
            if y > 0 {
                t.push(Triplet::new(j - side, j, -1.0));
            }
        }
        let m = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        assert!(!supernodal(&SparseSpd::new(m.clone()).unwrap()));
        assert_batches_equal_single_solves(m);
    }

    /// A wide band (every dof coupled to the next 150: a dense-block factor, supernodal,
    /// its updates by dense matrix products) gives the same bits too. (Solved 16 columns
    /// per sweep it does not: column 0, row 0 differs.)
    #[test]
    fn column_batches_equal_single_solves_on_a_supernodal_factor() {
        let (n, band): (usize, usize) = (400, 150);
        let mut t = Vec::new();
        for j in 0..n {
            t.push(Triplet::new(
                j,
                j,
                2.0 * band as f64 + 0.01 * (j % 7) as f64,
            ));
            for i in j.saturating_sub(band)..j {
                t.push(Triplet::new(
                    i,
                    j,
                    -1.0 + 0.3 * (((i * 31 + j * 17) % 11) as f64 / 11.0),
                ));
            }
        }
        let m = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        assert!(supernodal(&SparseSpd::new(m.clone()).unwrap()));
        assert_batches_equal_single_solves(m);
    }
}
