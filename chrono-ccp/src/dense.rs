//! Dense symmetric positive semi-definite matrices: `LDL'` factorization in place and
//! solves with the pseudo-inverse of `D`, for the block Gauss–Seidel update of the rows of
//! one joint ([`crate::Psor`]) and the bilateral block of [`crate::Schur`].

/// Largest block handled (rows of one bilateral group).
pub(crate) const MAX_BLOCK: usize = 12;

/// Relative pivot threshold: a pivot below `PIVOT_TOL * max(diag)` marks a row that depends
/// on the previous ones (redundant constraints); it is dropped from the solve.
const PIVOT_TOL: f64 = 1e-12;

/// `LDL'` of a symmetric positive semi-definite `n x n` matrix stored row-major.
pub(crate) struct DenseLdl;

impl DenseLdl {
    /// Factor `a` (row-major, `n x n`, symmetric PSD) in place: on return the strict lower
    /// triangle holds `L` (unit diagonal implied) and the diagonal holds `D^+` (the inverse
    /// pivots; 0 for dropped rows). For a PSD matrix a zero pivot implies a zero column
    /// below it, so dropping it keeps `L D L'` equal to `a` and the solve returns a solution
    /// of every consistent system `a x = c` (Golub and Van Loan, "Matrix Computations",
    /// 4th ed., sec. 4.2.8, semidefinite case).
    pub(crate) fn factor(a: &mut [f64], n: usize) {
        debug_assert!(n <= MAX_BLOCK);
        let mut d = [0.0f64; MAX_BLOCK];
        Self::factor_with(a, n, &mut d);
    }

    /// [`factor`](Self::factor) for any `n`, with `d` a scratch of at least `n` values
    /// (the pivots). Returns the number of dropped (dependent) rows.
    pub(crate) fn factor_with(a: &mut [f64], n: usize, d: &mut [f64]) -> usize {
        debug_assert!(a.len() >= n * n && d.len() >= n);
        let max_diag = (0..n).map(|i| a[i * n + i]).fold(0.0f64, f64::max);
        let tol = PIVOT_TOL * max_diag;
        let mut dropped = 0;
        for j in 0..n {
            let mut dj = a[j * n + j];
            for k in 0..j {
                dj -= a[j * n + k] * a[j * n + k] * d[k];
            }
            let keep = dj > tol;
            dropped += usize::from(!keep);
            d[j] = if keep { dj } else { 0.0 };
            for i in j + 1..n {
                let mut v = a[i * n + j];
                for k in 0..j {
                    v -= a[i * n + k] * a[j * n + k] * d[k];
                }
                a[i * n + j] = if keep { v / dj } else { 0.0 };
            }
            a[j * n + j] = if keep { 1.0 / dj } else { 0.0 };
        }
        dropped
    }

    /// Solve `a x = c` in place (`x` holds `c` on entry) with a matrix factored by
    /// [`factor`](Self::factor).
    pub(crate) fn solve(a: &[f64], n: usize, x: &mut [f64]) {
        for i in 0..n {
            for k in 0..i {
                x[i] -= a[i * n + k] * x[k];
            }
        }
        for i in 0..n {
            x[i] *= a[i * n + i];
        }
        for i in (0..n).rev() {
            for k in i + 1..n {
                x[i] -= a[k * n + i] * x[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_and_consistent_singular_systems() {
        // SPD: [[4,2,0],[2,3,1],[0,1,2]] x = [2,4,3] has x = [0,1,1].
        let mut a = [4.0, 2.0, 0.0, 2.0, 3.0, 1.0, 0.0, 1.0, 2.0];
        DenseLdl::factor(&mut a, 3);
        let mut x = [2.0, 4.0, 3.0];
        DenseLdl::solve(&a, 3, &mut x);
        for (xi, e) in x.iter().zip([0.0, 1.0, 1.0]) {
            assert!((xi - e).abs() < 1e-14, "{x:?}");
        }
        // Rank 1 (two identical rows): [[1,1],[1,1]] x = [2,2]: any x with x0 + x1 = 2.
        let mut a = [1.0, 1.0, 1.0, 1.0];
        DenseLdl::factor(&mut a, 2);
        let mut x = [2.0, 2.0];
        DenseLdl::solve(&a, 2, &mut x);
        assert!((x[0] + x[1] - 2.0).abs() < 1e-14 && x.iter().all(|v| v.is_finite()));
    }
}
