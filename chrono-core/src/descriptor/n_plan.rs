//! Entries of `N` at fixed positions, with the Jacobian entries each one sums found once
//! ([`NEntryPlan`]), for solvers that refill the same entries step after step (the joint
//! block of a mechanism).

use super::problem::CcpProblem;

/// A list of entries `N_ij = D_i'M^-1 D_j + eps_i delta_ij` (rows `i`, `j` of a
/// [`CcpProblem`]) with, for each, the pairs of Jacobian entries `(e, f)` (the `e`-th entry
/// of row `i` and the `f`-th of row `j`, on a common variable block) whose products it
/// sums.
///
/// [`CcpProblem::n_entry`] finds those pairs by comparing the blocks of the two rows on
/// every call; a plan finds them once ([`CcpProblem::plan_n_entries`]) and
/// [`CcpProblem::fill_n_entries`] then only multiplies, in the same order, so the values
/// are bit-identical to `n_entry`'s. A plan holds for every problem in which the rows it
/// names touch the same blocks in the same order as in the problem it was made from (the
/// joint rows of a mechanism from one step to the next); the caller re-plans when they
/// change.
#[derive(Debug, Clone, Default)]
pub struct NEntryPlan {
    /// The rows `(i, j)` of each entry.
    rows: Vec<[u32; 2]>,
    /// The pairs of entry `k` are `pairs[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    /// Entry indices within rows `i` and `j`, in `n_entry`'s summation order.
    pairs: Vec<[u32; 2]>,
}

impl NEntryPlan {
    /// Number of entries planned.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True if no entry is planned.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

impl CcpProblem {
    /// Plan the entries `N_ij` at `positions` (row pairs `(i, j)`) for
    /// [`fill_n_entries`](Self::fill_n_entries), reusing `plan`'s buffers.
    ///
    /// # Panics
    /// If a row index is out of range.
    pub fn plan_n_entries(
        &self,
        positions: impl IntoIterator<Item = (usize, usize)>,
        plan: &mut NEntryPlan,
    ) {
        plan.rows.clear();
        plan.start.clear();
        plan.pairs.clear();
        plan.start.push(0);
        for (i, j) in positions {
            assert!(i < self.n_rows && j < self.n_rows, "row out of range");
            plan.rows.push([i as u32, j as u32]);
            let (ei, ej) = (self.row_ptr[i], self.row_ptr[j]);
            for e in ei..self.row_ptr[i + 1] {
                for f in ej..self.row_ptr[j + 1] {
                    if self.ent_block[e as usize] == self.ent_block[f as usize] {
                        plan.pairs.push([e - ei, f - ej]);
                    }
                }
            }
            plan.start.push(plan.pairs.len() as u32);
        }
    }

    /// The planned entries of `N` into `out` (one per planned position, in the plan's
    /// order), bit-identical to [`n_entry`](Self::n_entry) for a problem the plan holds for
    /// (see [`NEntryPlan`]).
    ///
    /// # Panics
    /// If `out` does not have the plan's length, or the plan names entries this problem
    /// does not have.
    pub fn fill_n_entries(&self, plan: &NEntryPlan, out: &mut [f64]) {
        assert_eq!(out.len(), plan.len(), "out has the wrong length");
        for (k, o) in out.iter_mut().enumerate() {
            let [i, j] = plan.rows[k];
            let (i, j) = (i as usize, j as usize);
            let (ei, ej) = (self.row_ptr[i] as usize, self.row_ptr[j] as usize);
            // The same sum as `n_entry`: the compliance first, then every product in order.
            let mut s = if i == j { self.eps[i] } else { 0.0 };
            for &[a, b] in &plan.pairs[plan.start[k] as usize..plan.start[k + 1] as usize] {
                let (e, f) = (ei + a as usize, ej + b as usize);
                debug_assert_eq!(self.ent_block[e], self.ent_block[f]);
                let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
                let m0 = self.ent_coef[f] as usize;
                let (a, b) = (&self.coefs[c0..c1], &self.minv[m0..m0 + (c1 - c0)]);
                if let (Ok(a), Ok(b)) = (<&[f64; 6]>::try_from(a), <&[f64; 6]>::try_from(b)) {
                    // A rigid body's block, unrolled (the same sequential sum).
                    for t in 0..6 {
                        s += a[t] * b[t];
                    }
                } else {
                    for (a, b) in a.iter().zip(b) {
                        s += a * b;
                    }
                }
            }
            *o = s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::NEntryPlan;
    use crate::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};

    /// A small mechanism-like problem: three bodies, rows on one or two of them.
    fn problem(scale: f64) -> CcpProblem {
        let mut vars = Variables::new();
        let mut blocks = Vec::new();
        for k in 0..3 {
            let m = 1.0 + k as f64;
            let j = nalgebra::Matrix3::new(2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0) * m;
            blocks.push(vars.add(MassOperator::rigid_body(m, j).unwrap()));
        }
        let c = |s: f64| -> [f64; 6] { std::array::from_fn(|t| scale * (s + t as f64).sin()) };
        let (a, b, d) = (c(0.3), c(1.7), c(2.9));
        let mut rows = ConstraintRows::new();
        rows.push_bilateral(
            &[
                RowEntry { block: blocks[0], coefs: &a },
                RowEntry { block: blocks[1], coefs: &b },
            ],
            0.0,
            1e-3,
        );
        rows.push_bilateral(&[RowEntry { block: blocks[1], coefs: &d }], 0.0, 0.0);
        rows.push_bilateral(
            &[
                RowEntry { block: blocks[2], coefs: &a },
                RowEntry { block: blocks[0], coefs: &d },
            ],
            0.0,
            2e-3,
        );
        let mut p = CcpProblem::new();
        p.assemble(&vars, &rows, &[0.0; 18]).unwrap();
        p
    }

    #[test]
    fn planned_entries_equal_n_entry_bit_for_bit_and_hold_for_new_values() {
        let p = problem(1.0);
        let positions: Vec<(usize, usize)> =
            (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).collect();
        let mut plan = NEntryPlan::default();
        p.plan_n_entries(positions.iter().copied(), &mut plan);
        assert_eq!(plan.len(), 9);
        // Same rows and blocks, other coefficients: the plan still holds.
        for q in [p, problem(0.37)] {
            let mut out = vec![f64::NAN; plan.len()];
            q.fill_n_entries(&plan, &mut out);
            for (&(i, j), v) in positions.iter().zip(&out) {
                assert_eq!(v.to_bits(), q.n_entry(i, j).to_bits(), "N[{i},{j}]");
            }
        }
    }
}
