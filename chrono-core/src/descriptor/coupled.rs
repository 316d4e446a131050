//! Coupled variable blocks: `n` dof whose mass operator is a full (sparse or dense)
//! symmetric positive definite matrix, applied by a factorization that a domain crate
//! supplies.
//!
//! The implicit FEA step (chrono-fea) writes its linearized backward-Euler equation
//!
//! ```text
//! (M + h R + h^2 K) v+ = M v + h f(q, v) + D gamma
//! ```
//!
//! in the form every block of the CCP has, `H v+ = k + D gamma`, with the *iteration
//! matrix* `H = M + h R + h^2 K` in the place of the mass (Anitescu–Tasora with a stiff
//! item; Chrono's `ChKRMBlock` with the factors `(1, h, h^2)`). The solvers only need
//! `H^-1 x`, so the descriptor sees `H` through [`CoupledMass`] and chrono-core does not
//! depend on a sparse linear algebra crate. [`DenseMass`] is the small dense
//! implementation (nalgebra Cholesky): tests, and problems loaded from files.

use nalgebra::{DMatrix, Dyn, linalg::Cholesky};

use crate::error::{ChronoError, Result};

/// A symmetric positive definite operator over one block of `ndof` velocities: the
/// "mass" `H` of a coupled block, kg (or the iteration matrix of an implicit item, see the
/// module docs).
///
/// Implementations must be deterministic (the same input gives the same bits) and
/// thread-safe: the descriptor may call them from rayon workers. `apply_inverse` must be
/// the inverse of `apply` to round-off, and `H` must be symmetric positive definite so that
/// `N = D'H^-1 D + E` stays positive semidefinite.
pub trait CoupledMass: std::fmt::Debug + Send + Sync {
    /// Number of dof `n` of the block.
    fn ndof(&self) -> usize;

    /// `out = H x` (both of length `ndof`).
    fn apply(&self, x: &[f64], out: &mut [f64]);

    /// `out = H^-1 x` (both of length `ndof`).
    fn apply_inverse(&self, x: &[f64], out: &mut [f64]);

    /// `X <- H^-1 X` for the `ncols` columns of `x` (column-major, `ndof` values each):
    /// the `M^-1 D` of many rows on one block at once (the descriptor's assembly). Each
    /// column must come out as [`apply_inverse`](Self::apply_inverse) would give it to
    /// round-off. The default solves column by column; a factorization that can solve
    /// several right-hand sides in one sweep (reading its factor once per sweep, not once
    /// per column) overrides it.
    fn apply_inverse_columns(&self, x: &mut [f64], ncols: usize) {
        let n = self.ndof();
        let mut col = vec![0.0; n];
        for c in x.chunks_exact_mut(n).take(ncols) {
            self.apply_inverse(c, &mut col);
            c.copy_from_slice(&col);
        }
    }
}

/// A dense symmetric positive definite mass matrix factorized once by Cholesky
/// (`H = L L'`): fine for blocks of a few hundred dof.
#[derive(Debug, Clone)]
pub struct DenseMass {
    matrix: DMatrix<f64>,
    chol: Cholesky<f64, Dyn>,
}

impl DenseMass {
    /// A dense block from a square, finite, symmetric (to `1e-12` relative) and positive
    /// definite matrix (kg). The error names the property that failed.
    pub fn new(matrix: DMatrix<f64>) -> Result<Self> {
        let field = "coupled mass matrix";
        let n = matrix.nrows();
        if n == 0 || matrix.ncols() != n {
            return Err(ChronoError::invalid(
                field,
                format!("{}x{}", n, matrix.ncols()),
                "must be square and non-empty",
            ));
        }
        if let Some(i) = matrix.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("{field}[{}, {}]", i % n, i / n),
                matrix[i],
                "must be finite",
            ));
        }
        let asym = (&matrix - matrix.transpose()).abs().max();
        if asym > 1e-12 * matrix.abs().max() {
            return Err(ChronoError::invalid(
                field,
                format!("asymmetry {asym:e}"),
                "must be symmetric",
            ));
        }
        let chol = matrix.clone().cholesky().ok_or_else(|| {
            ChronoError::invalid(field, format!("{n}x{n}"), "must be positive definite")
        })?;
        Ok(Self { matrix, chol })
    }

    /// The matrix, kg.
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.matrix
    }
}

impl CoupledMass for DenseMass {
    fn ndof(&self) -> usize {
        self.matrix.nrows()
    }

    fn apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.ndof();
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = (0..n).map(|j| self.matrix[(i, j)] * x[j]).sum();
        }
    }

    fn apply_inverse(&self, x: &[f64], out: &mut [f64]) {
        let mut b = nalgebra::DVector::from_column_slice(&x[..self.ndof()]);
        self.chol.solve_mut(&mut b);
        out[..b.len()].copy_from_slice(b.as_slice());
    }
}

/// The dense matrix of any coupled operator, column by column (`H e_j`): how a problem
/// with a coupled block is saved to a file. `O(n^2)` work and memory.
pub fn dense_matrix(op: &dyn CoupledMass) -> DMatrix<f64> {
    let n = op.ndof();
    let mut m = DMatrix::zeros(n, n);
    let mut e = vec![0.0; n];
    let mut col = vec![0.0; n];
    for j in 0..n {
        e[j] = 1.0;
        op.apply(&e, &mut col);
        e[j] = 0.0;
        m.column_mut(j).copy_from_slice(&col);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_rejects_bad_matrices() {
        let e = DenseMass::new(DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("positive definite"), "{e}");
        let e = DenseMass::new(DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("symmetric"), "{e}");
        let e = DenseMass::new(DMatrix::from_row_slice(1, 1, &[f64::NAN]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("finite"), "{e}");
        assert!(DenseMass::new(DMatrix::zeros(2, 3)).is_err());
    }

    #[test]
    fn dense_matrix_round_trips() {
        let m = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0]);
        let d = DenseMass::new(m.clone()).unwrap();
        assert_eq!(dense_matrix(&d), m);
        let x = [1.0, -2.0, 0.5];
        let (mut y, mut back) = ([0.0; 3], [0.0; 3]);
        d.apply_inverse(&x, &mut y);
        d.apply(&y, &mut back);
        for i in 0..3 {
            assert!((back[i] - x[i]).abs() < 1e-14);
        }
    }
}
