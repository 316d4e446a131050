//! The bilateral block `N_BB = D_B' M^-1 D_B + E_B` of a problem as a sparse matrix with a
//! reusable Cholesky factorization (faer), for [`crate::Schur`].
//!
//! `N_ij` is non-zero only if rows `i` and `j` touch a common variable block, so for a
//! mechanism (each joint row touches two bodies) `N_BB` is as sparse as the joint graph.
//! The pattern, its fill-reducing ordering (approximate minimum degree) and the symbolic
//! factorization are kept while the rows touch the same blocks (a mechanism's joints do,
//! step after step); each solve refills the values and refactors numerically.
//!
//! The values are refilled through an [`NEntryPlan`] (the products each entry sums, found
//! at analysis).
//!
//! Dependent (redundant) rows make `N_BB` singular. faer's dynamic regularization replaces
//! a pivot below `1e-12 max(diag)` by `max(diag)`: the factor is then that of a slightly
//! different SPD matrix, and a few steps of iterative refinement against the true `N_BB`
//! make the solve exact for the consistent systems the solver produces (the dependent
//! row's multiplier stays about zero, as when [`crate::dense`] drops it).

use chrono_core::descriptor::{CcpProblem, NEntryPlan};

use crate::error::CcpError;
use crate::hubs::Hubs;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

/// The sparse factorization of `N_BB` (see the [module documentation](self)).
#[derive(Default)]
pub(crate) struct SparseBilateral {
    /// The blocks of each bilateral row, rows separated by `u32::MAX`: the pattern's key.
    key: Vec<u32>,
    key_scratch: Vec<u32>,
    /// Upper triangle of `N_BB` (compressed columns).
    upper: Option<SparseColMat<usize, f64>>,
    /// `(i, j)` (local bilateral indices) of each stored value, in storage order.
    entries: Vec<(usize, usize)>,
    /// The products of each stored value.
    plan: NEntryPlan,
    symbolic: Option<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    scratch: Option<MemBuffer>,
    scratch_cols: usize,
    rhs: Vec<f64>,
    res: Vec<f64>,
    /// True once a solve with this factor met the round-off bound without refinement (the
    /// factor is exact: no regularized pivot and no ill-conditioning that shows).
    checked: bool,
    /// Bodies many joint rows touch, kept out of the sparse factor (`crate::hubs`).
    hubs: Hubs,
    /// Set when the factor without the hubs was singular for this pattern (the hubs held
    /// fixed over-constrain another body): the pattern is then factored whole.
    no_hubs: bool,
    /// Whether hubs are looked for at all ([`with_hubs`](Self::with_hubs)): the Schur
    /// solver's joint block, not ADMM's whole-problem blocks (many heavy bodies with
    /// contact rows, unmeasured there).
    hubs_enabled: bool,
}

/// Iterative-refinement steps of a solve with a regularized factor.
const REFINE_STEPS: usize = 4;

impl SparseBilateral {
    /// A factorization that keeps hub bodies out of the sparse factor (`crate::hubs`).
    pub(crate) fn with_hubs() -> Self {
        Self {
            hubs_enabled: true,
            ..Self::default()
        }
    }

    /// Assemble `N_BB` for the bilateral rows `b_rows` of `problem` and factor it.
    /// Returns an error text if the factorization failed (not expected for a PSD matrix
    /// with regularization; the caller falls back).
    pub(crate) fn factor(
        &mut self,
        problem: &CcpProblem,
        b_rows: &[usize],
    ) -> Result<(), CcpError> {
        self.factor_shifted(problem, b_rows, None)
    }

    /// [`factor`](Self::factor) of `N_BB + diag(shift)` (`shift` one value per row of
    /// `b_rows`, in their order): the proximal system of [`crate::Admm`]. Solves and their
    /// refinement are then against the shifted matrix.
    pub(crate) fn factor_shifted(
        &mut self,
        problem: &CcpProblem,
        b_rows: &[usize],
        shift: Option<&[f64]>,
    ) -> Result<(), CcpError> {
        self.key_scratch.clear();
        for &i in b_rows {
            self.key_scratch.extend(problem.row_blocks(i).map(|b| b.0));
            self.key_scratch.push(u32::MAX);
        }
        if self.key_scratch != self.key || self.symbolic.is_none() {
            std::mem::swap(&mut self.key, &mut self.key_scratch);
            self.no_hubs = false;
            self.analyze(problem, b_rows)?;
        }
        let missing = |stage| CcpError::Factorization {
            rows: b_rows.len(),
            stage,
            detail: "not analyzed".to_string(),
        };
        let upper = self.upper.as_mut().ok_or_else(|| missing("pattern"))?;
        let vals = upper.val_mut();
        problem
            .fill_n_entries(&mut self.plan, vals)
            .map_err(|e| CcpError::Factorization {
                rows: b_rows.len(),
                stage: "numeric",
                detail: e.to_string(),
            })?;
        if !self.hubs.is_empty() {
            self.hubs.refresh(problem, b_rows, vals);
        }
        let mut max_diag: f64 = 0.0;
        for (v, &(i, j)) in vals.iter_mut().zip(&self.entries) {
            if i == j {
                if let Some(shift) = shift {
                    *v += shift[i];
                }
                max_diag = max_diag.max(*v);
            }
        }
        let scale = if max_diag > 0.0 { max_diag } else { 1.0 };
        let failed = |detail: String| CcpError::Factorization {
            rows: b_rows.len(),
            stage: "numeric",
            detail,
        };
        let symbolic = self.symbolic.as_ref().ok_or_else(|| missing("symbolic"))?;
        let scratch = self.scratch.as_mut().ok_or_else(|| missing("symbolic"))?;
        symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                upper.as_ref(),
                Side::Upper,
                LltRegularization {
                    dynamic_regularization_delta: scale,
                    dynamic_regularization_epsilon: 1e-12 * scale,
                },
                Par::Seq,
                MemStack::new(scratch),
                Default::default(),
            )
            .map_err(|e| failed(format!("{e:?}")))?;
        self.checked = false;
        if !self.hubs.is_empty() {
            // W = N'^-1 U with the hub-free factor, then the capacitance. A hub held fixed
            // can over-constrain a body (more rows on it than its dof): `N'` is then
            // singular, its regularized factor does not solve `N' W = U`, and the pattern
            // is factored whole instead.
            let mut w = self.hubs.take_u();
            let k = self.hubs.rank();
            self.solve_plain(&mut w, k);
            let exact = match &self.upper {
                Some(upper) => self
                    .hubs
                    .solves_u(&w, |x, out| symmetric_upper_mul_add(upper, x, out)),
                None => true,
            };
            if !exact {
                self.hubs.set_w(w);
                self.no_hubs = true;
                self.analyze(problem, b_rows)?;
                return self.factor_shifted(problem, b_rows, shift);
            }
            self.hubs.set_w(w);
        }
        Ok(())
    }

    /// The pattern, ordering and symbolic factorization for the current key.
    fn analyze(&mut self, problem: &CcpProblem, b_rows: &[usize]) -> Result<(), CcpError> {
        let nb = b_rows.len();
        let n_blocks = problem.variables().len();
        let mut by_block: Vec<Vec<usize>> = vec![Vec::new(); n_blocks];
        for (a, &i) in b_rows.iter().enumerate() {
            for b in problem.row_blocks(i) {
                by_block[b.0 as usize].push(a);
            }
        }
        // A hub's rows would be a dense clique: left out of the pattern (`crate::hubs`).
        let hub = if self.no_hubs || !self.hubs_enabled {
            self.hubs.clear();
            vec![false; by_block.len()]
        } else {
            self.hubs.find(problem, b_rows, &by_block)
        };
        let mut pairs: Vec<(usize, usize)> = (0..nb).map(|a| (a, a)).collect();
        for (rows, _) in by_block.iter().zip(&hub).filter(|(_, h)| !**h) {
            for (k, &a) in rows.iter().enumerate() {
                for &b in &rows[k + 1..] {
                    pairs.push((a.min(b), a.max(b)));
                }
            }
        }
        pairs.sort_unstable_by_key(|&(i, j)| (j, i));
        pairs.dedup();
        let triplets: Vec<Triplet<usize, usize, f64>> = pairs
            .iter()
            .map(|&(i, j)| Triplet::new(i, j, 0.0))
            .collect();
        let upper = SparseColMat::try_new_from_triplets(nb, nb, &triplets).map_err(|e| {
            CcpError::Factorization {
                rows: nb,
                stage: "pattern",
                detail: format!("{e:?}"),
            }
        })?;
        // Storage order of the values (compressed columns, rows sorted within a column).
        let s = upper.symbolic();
        self.entries.clear();
        for j in 0..nb {
            for idx in s.col_ptr()[j]..s.col_ptr()[j + 1] {
                self.entries.push((s.row_idx()[idx], j));
            }
        }
        self.hubs.plan_corrections(&self.entries);
        let symbolic = factorize_symbolic_cholesky(
            upper.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            // faer's choice (simplicial here): forcing the supernodal factor made the
            // M113's solves 1.7x the instructions (docs/validation-vehicle.md, M113 speed).
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| CcpError::Factorization {
            rows: nb,
            stage: "symbolic",
            detail: format!("{e:?}"),
        })?;
        self.plan_values(problem, b_rows)?;
        self.l_values.clear();
        self.l_values.resize(symbolic.len_val(), 0.0);
        self.symbolic = Some(symbolic);
        self.upper = Some(upper);
        self.scratch = None;
        self.scratch_cols = 0;
        self.ensure_scratch(1);
        Ok(())
    }

    /// The plan of the stored values of `N_BB` (see [`NEntryPlan`]).
    fn plan_values(&mut self, problem: &CcpProblem, b_rows: &[usize]) -> Result<(), CcpError> {
        let positions = self.entries.iter().map(|&(i, j)| (b_rows[i], b_rows[j]));
        (problem.plan_n_entries(positions, &mut self.plan)).map_err(|e| CcpError::Factorization {
            rows: b_rows.len(),
            stage: "pattern",
            detail: e.to_string(),
        })
    }

    /// Scratch for the factorization and a solve with `cols` right-hand sides.
    fn ensure_scratch(&mut self, cols: usize) {
        if self.scratch.is_some() && self.scratch_cols >= cols {
            return;
        }
        let Some(symbolic) = &self.symbolic else {
            return;
        };
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(cols, Par::Seq),
        ]);
        self.scratch = Some(MemBuffer::new(req));
        self.scratch_cols = cols;
    }

    /// Solve `N_BB X = R` in place for `cols` right-hand sides stored column-major in `x`
    /// (`nb` rows each), refined against `N_BB` while the residual is above round-off (a
    /// regularized factor; otherwise one residual check).
    pub(crate) fn solve(&mut self, x: &mut [f64], cols: usize) {
        if cols == 0 {
            return;
        }
        let mut rhs = std::mem::take(&mut self.rhs);
        let mut res = std::mem::take(&mut self.res);
        rhs.clear();
        rhs.extend_from_slice(x);
        self.solve_factor(x, cols);
        let nb = x.len() / cols;
        for step in 0..REFINE_STEPS {
            res.clear();
            res.resize(x.len(), 0.0);
            if let Some(upper) = &self.upper {
                for c in 0..cols {
                    let xc = &x[c * nb..(c + 1) * nb];
                    let rc = &mut res[c * nb..(c + 1) * nb];
                    symmetric_upper_mul_add(upper, xc, rc);
                    if !self.hubs.is_empty() {
                        self.hubs.mul_add(xc, rc);
                    }
                }
            }
            let (mut rn, mut bn) = (0.0f64, 0.0f64);
            for (r, b) in res.iter_mut().zip(&rhs) {
                *r = b - *r;
                rn = rn.max(r.abs());
                bn = bn.max(b.abs());
            }
            if rn <= 1e-14 * bn {
                self.checked |= step == 0;
                break;
            }

            self.solve_factor(&mut res, cols);
            for (xi, d) in x.iter_mut().zip(&res) {
                *xi += d;
            }
        }
        self.rhs = rhs;
        self.res = res;
    }

    /// Solve `N_BB x = r` in place (one right-hand side) inside an iteration that corrects
    /// its own joint residual (the Schur solver's completed steps start from the residual the
    /// last one left): with an unregularized factor, the factor's solve alone (round-off of
    /// the Cholesky factor, no residual check) once a checked solve with this factor needed
    /// no refinement; otherwise [`solve`](Self::solve), which records that.
    pub(crate) fn solve_corrected_later(&mut self, x: &mut [f64]) {
        if self.checked {
            self.solve_factor(x, 1);
        } else {
            self.solve(x, 1);
        }
    }

    /// One solve with the factor, the hubs put back (`N_BB^-1`).
    fn solve_factor(&mut self, x: &mut [f64], cols: usize) {
        self.solve_plain(x, cols);
        if !self.hubs.is_empty() && cols > 0 {
            let nb = x.len() / cols;
            for xc in x.chunks_mut(nb) {
                self.hubs.apply(xc);
            }
        }
    }

    /// One solve with the sparse factor alone (`N'^-1`: without the hubs).
    fn solve_plain(&mut self, x: &mut [f64], cols: usize) {
        self.ensure_scratch(cols);
        let (Some(symbolic), Some(scratch)) = (&self.symbolic, &mut self.scratch) else {
            x.fill(f64::NAN);
            return;
        };
        let nb = x.len() / cols;
        let rhs = MatMut::from_column_major_slice_mut(x, nb, cols);
        LltRef::new(symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(scratch),
        );
    }
}

/// `out += A x` for the symmetric matrix whose upper triangle is `upper`.
fn symmetric_upper_mul_add(upper: &SparseColMat<usize, f64>, x: &[f64], out: &mut [f64]) {
    let s = upper.symbolic();
    let (cp, ri, val) = (s.col_ptr(), s.row_idx(), upper.val());
    for j in 0..upper.ncols() {
        // Column j is the first to touch out[j] (earlier columns hold rows < j), so its
        // sum is kept in a register, in the same order.
        let (xj, mut oj) = (x[j], out[j]);
        let (r0, r1) = (cp[j], cp[j + 1]);
        for (&i, &a) in ri[r0..r1].iter().zip(&val[r0..r1]) {
            if i != j {
                out[i] += a * xj;
                oj += a * x[i];
            } else {
                oj += a * xj;
            }
        }
        out[j] = oj;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_core::descriptor::{ConstraintRows, MassOperator, RowEntry, Variables};
    use chrono_core::math::Matrix3;
    use chrono_core::rng::Rng;

    /// A hub (a heavy rigid body) with `n` light rigid satellites, each held to it by 3
    /// joint rows and paired with a neighbour by one more. With `over`, the first satellite
    /// has 7 rows to the hub: with the hub held fixed, more rows than its 6 dof (`N'`
    /// singular) while the whole block stays regular (the hub takes the seventh). The
    /// hub's rows are a clique of `N_BB`.
    fn star(n: usize, over: bool, seed: u64) -> CcpProblem {
        let mut rng = Rng::splitmix64(seed);
        let mut vars = Variables::new();
        let inertia = |m: f64| Matrix3::from_diagonal_element(0.1 * m);
        let hub = vars.add(MassOperator::rigid_body(1.0e4, inertia(1.0e4)).unwrap());
        let sats: Vec<_> = (0..n)
            .map(|_| {
                let m = rng.range(5.0, 50.0);
                vars.add(MassOperator::rigid_body(m, inertia(m)).unwrap())
            })
            .collect();
        let mut cr = ConstraintRows::new();
        // one bilateral row between blocks `a` and `b`, random coefficients (same draw order)
        let mut pair = |cr: &mut ConstraintRows, a, b| {
            let ca: [f64; 6] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
            let cb: [f64; 6] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
            let e = [
                RowEntry {
                    block: a,
                    coefs: &ca,
                },
                RowEntry {
                    block: b,
                    coefs: &cb,
                },
            ];
            cr.push_bilateral(&e, 0.0, 0.0);
        };
        for (k, &s) in sats.iter().enumerate() {
            for _ in 0..if over && k == 0 { 7 } else { 3 } {
                pair(&mut cr, hub, s);
            }
            if k + 1 < n && k % 2 == 0 {
                pair(&mut cr, s, sats[k + 1]);
            }
        }
        let k = vec![0.0; vars.ndof()];
        let mut p = CcpProblem::new();
        p.assemble(&vars, &cr, &k).unwrap();
        p
    }

    /// With a hub the solve is still `N_BB^-1` (to round-off against the dense product),
    /// and the factor is smaller than the whole block's would be.
    #[test]
    fn a_hub_kept_out_of_the_factor_still_solves_the_joint_block() {
        for (n, over, seed) in [
            (11, false, 1),
            (16, false, 2),
            (24, false, 3),
            (11, true, 4),
            (16, true, 5),
        ] {
            let p = star(n, over, seed);
            let rows: Vec<usize> = p.sections().bilateral.clone().collect();
            let nb = rows.len();
            let mut f = SparseBilateral::with_hubs();
            f.factor(&p, &rows).unwrap();
            // Kept out where the rest stays regular; factored whole where it does not.
            assert_eq!(f.hubs.is_empty(), over, "n {n}, over {over}");
            let mut rng = Rng::splitmix64(seed + 10);
            let r: Vec<f64> = (0..nb).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut x = r.clone();
            f.solve(&mut x, 1);
            let mut worst: f64 = 0.0;
            let scale = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, &i) in rows.iter().enumerate() {
                let nx: f64 = rows
                    .iter()
                    .zip(&x)
                    .map(|(&j, xj)| p.n_entry(i, j) * xj)
                    .sum();
                worst = worst.max((nx - r[a]).abs());
            }
            assert!(worst < 1e-9 * scale, "n {n}: residual {worst:e}");
            if over {
                continue;
            }
            // The plain factor alone (without the hubs put back) is not N_BB's solve.
            let mut y = r.clone();
            f.solve_plain(&mut y, 1);
            let diff = x
                .iter()
                .zip(&y)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                diff > 1e-6 * x.iter().fold(0.0f64, |m, v| m.max(v.abs())),
                "n {n}"
            );
            // Fewer factor entries than the hub's clique alone.
            let clique = 3 * n * (3 * n + 1) / 2;
            assert!(
                f.l_values.len() < clique,
                "n {n}: {} entries",
                f.l_values.len()
            );
        }
    }
}
