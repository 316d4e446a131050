//! Entries of `N` at fixed positions, with the Jacobian entries each one sums found once
//! ([`NEntryPlan`]), for solvers that refill the same entries step after step (the joint
//! block of a mechanism).

use super::problem::CcpProblem;
use crate::error::{ChronoError, Result};

/// A list of entries `N_ij = D_i'M^-1 D_j + eps_i delta_ij` (rows `i`, `j` of a
/// [`CcpProblem`]) with, for each, the products it sums: the coefficients of `D_i` and of
/// `M^-1 D_j` on every variable block both rows touch.
///
/// [`CcpProblem::n_entry`] finds those products by comparing the blocks of the two rows on
/// every call; a plan finds them once ([`CcpProblem::plan_n_entries`]) and
/// [`CcpProblem::fill_n_entries`] then only multiplies, in the same order, so the values
/// are bit-identical to `n_entry`'s. The plan remembers the layout it was made from (the
/// entries of the rows it names: their blocks, where their coefficients are stored and the
/// span of `D_i` outside which all are zero, which the products are limited to);
/// `fill_n_entries` checks it (a pass over those rows' entries) and plans again if it
/// changed, so a plan is never stale: the joint rows of a mechanism keep their layout from
/// one step to the next and are planned once. (The span is part of the layout because it
/// moves with the coefficients: a mesh node's row whose slope coefficients are zero in the
/// reference pose gains non-zeros once the mesh turns; a plan that kept the old span would
/// drop those products.)
#[derive(Debug, Clone, Default)]
pub struct NEntryPlan {
    /// The rows `(i, j)` of each entry.
    rows: Vec<[u32; 2]>,
    /// The products of entry `k` are `pairs[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    /// Start of the coefficients of `D_i` and of `M^-1 D_j`, and their number, in
    /// `n_entry`'s summation order.
    pairs: Vec<[u32; 3]>,
    /// The layout planned on: each row named (row, first entry, end of its entries) ...
    layout_rows: Vec<[u32; 3]>,
    /// ... and each of their entries (block, first coefficient, end of its coefficients,
    /// first and end of its non-zero span).
    layout_entries: Vec<[u32; 5]>,
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
    /// # Errors
    /// A position with a row out of range (the plan is then left empty).
    pub fn plan_n_entries(
        &self,
        positions: impl IntoIterator<Item = (usize, usize)>,
        plan: &mut NEntryPlan,
    ) -> Result<()> {
        plan.rows.clear();
        for (k, (i, j)) in positions.into_iter().enumerate() {
            if i >= self.n_rows || j >= self.n_rows {
                plan.rows.clear();
                self.replan(plan);
                return Err(ChronoError::invalid(
                    format!("positions[{k}]"),
                    format!("({i}, {j})"),
                    format!("rows must be below n_rows = {}", self.n_rows),
                ));
            }
            plan.rows.push([i as u32, j as u32]);
        }
        self.replan(plan);
        Ok(())
    }

    /// The products and layout of `plan.rows` in this problem.
    fn replan(&self, plan: &mut NEntryPlan) {
        plan.start.clear();
        plan.pairs.clear();
        plan.start.push(0);
        for &[i, j] in &plan.rows {
            let (i, j) = (i as usize, j as usize);
            for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                for f in self.row_ptr[j] as usize..self.row_ptr[j + 1] as usize {
                    if self.ent_block[e] == self.ent_block[f] {
                        // Only `D_i`'s non-zero span (`n_entry` sums the same products).
                        let (c0, c1) = self.nonzero_span(e);
                        let lo = c0 as u32 - self.ent_coef[e];
                        let len = (c1 - c0) as u32;
                        plan.pairs.push([c0 as u32, self.ent_coef[f] + lo, len]);
                    }
                }
            }
            plan.start.push(plan.pairs.len() as u32);
        }
        let mut named: Vec<u32> = plan.rows.iter().flatten().copied().collect();
        named.sort_unstable();
        named.dedup();
        plan.layout_rows.clear();
        plan.layout_entries.clear();
        for i in named {
            let (e0, e1) = (self.row_ptr[i as usize], self.row_ptr[i as usize + 1]);
            plan.layout_rows.push([i, e0, e1]);
            for e in e0 as usize..e1 as usize {
                plan.layout_entries.push(self.entry_layout(e));
            }
        }
    }

    /// True if the rows `plan` names have the layout it was made from.
    fn plan_holds(&self, plan: &NEntryPlan) -> bool {
        let mut seen = plan.layout_entries.iter();
        for &[i, e0, e1] in &plan.layout_rows {
            let i = i as usize;
            if i + 1 >= self.row_ptr.len() || self.row_ptr[i] != e0 || self.row_ptr[i + 1] != e1 {
                return false;
            }
            for e in e0 as usize..e1 as usize {
                if seen.next() != Some(&self.entry_layout(e)) {
                    return false;
                }
            }
        }
        true
    }

    /// What a plan depends on of entry `e`: its block, its coefficients' range and their
    /// non-zero span.
    fn entry_layout(&self, e: usize) -> [u32; 5] {
        let [lo, hi] = self.ent_span[e];
        [
            self.ent_block[e],
            self.ent_coef[e],
            self.ent_coef[e + 1],
            lo,
            hi,
        ]
    }

    /// The planned entries of `N` into `out` (one per planned position, in the plan's
    /// order), bit-identical to [`n_entry`](Self::n_entry); `plan` is made again first if
    /// the layout of its rows changed (see [`NEntryPlan`]).
    ///
    /// # Errors
    /// If `out` does not have the plan's length, or a planned row is out of range of this
    /// problem (nothing is written then).
    pub fn fill_n_entries(&self, plan: &mut NEntryPlan, out: &mut [f64]) -> Result<()> {
        if out.len() != plan.len() {
            return Err(ChronoError::invalid(
                "out.len()",
                out.len(),
                format!("must equal the planned entries ({})", plan.len()),
            ));
        }
        if let Some(k) =
            (plan.rows.iter()).position(|r| r.iter().any(|&i| i as usize >= self.n_rows))
        {
            let [i, j] = plan.rows[k];
            return Err(ChronoError::invalid(
                format!("plan position {k}"),
                format!("({i}, {j})"),
                format!("rows must be below n_rows = {}", self.n_rows),
            ));
        }
        if !self.plan_holds(plan) {
            self.replan(plan);
        }
        for (k, o) in out.iter_mut().enumerate() {
            let [i, j] = plan.rows[k];
            // The same sum as `n_entry`: the compliance first, then every product in order.
            let mut s = if i == j { self.eps[i as usize] } else { 0.0 };
            for &[c0, m0, len] in &plan.pairs[plan.start[k] as usize..plan.start[k + 1] as usize] {
                let (c0, m0, len) = (c0 as usize, m0 as usize, len as usize);
                let (a, b) = (&self.coefs()[c0..c0 + len], &self.minv()[m0..m0 + len]);
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
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::NEntryPlan;
    use crate::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};

    /// A small mechanism-like problem: three bodies, rows on one or two of them.
    /// With `moved`, the second row is on the third body instead of the second.
    fn problem(scale: f64, moved: bool) -> CcpProblem {
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
                RowEntry {
                    block: blocks[0],
                    coefs: &a,
                },
                RowEntry {
                    block: blocks[1],
                    coefs: &b,
                },
            ],
            0.0,
            1e-3,
        );
        let second = if moved { blocks[2] } else { blocks[1] };
        rows.push_bilateral(
            &[RowEntry {
                block: second,
                coefs: &d,
            }],
            0.0,
            0.0,
        );
        rows.push_bilateral(
            &[
                RowEntry {
                    block: blocks[2],
                    coefs: &a,
                },
                RowEntry {
                    block: blocks[0],
                    coefs: &d,
                },
            ],
            0.0,
            2e-3,
        );
        let mut p = CcpProblem::new();
        p.assemble(&vars, &rows, &[0.0; 18]).unwrap();
        p
    }

    #[test]
    fn planned_entries_equal_n_entry_bit_for_bit_whatever_the_layout() {
        let p = problem(1.0, false);
        let positions: Vec<(usize, usize)> =
            (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).collect();
        let mut plan = NEntryPlan::default();
        p.plan_n_entries(positions.iter().copied(), &mut plan)
            .unwrap();
        assert_eq!(plan.len(), 9);
        // Same rows and blocks, other coefficients: the plan holds; a row on another
        // block: the plan is made again.
        for q in [
            p,
            problem(0.37, false),
            problem(0.5, true),
            problem(0.9, false),
        ] {
            let mut out = vec![f64::NAN; plan.len()];
            q.fill_n_entries(&mut plan, &mut out).unwrap();
            for (&(i, j), v) in positions.iter().zip(&out) {
                assert_eq!(v.to_bits(), q.n_entry(i, j).to_bits(), "N[{i},{j}]");
            }
        }
    }

    #[test]
    fn bad_positions_and_lengths_are_errors_naming_them() {
        let p = problem(1.0, false);
        let mut plan = NEntryPlan::default();
        let e = p
            .plan_n_entries([(0, 1), (2, 7)], &mut plan)
            .unwrap_err()
            .to_string();
        assert!(e.contains("positions[1]") && e.contains("(2, 7)"), "{e}");
        assert!(plan.is_empty());
        p.plan_n_entries([(0, 1), (2, 2)], &mut plan).unwrap();
        let e = p
            .fill_n_entries(&mut plan, &mut [0.0; 3])
            .unwrap_err()
            .to_string();
        assert!(e.contains("out.len()") && e.contains('3'), "{e}");
        // A plan made on a larger problem, filled from a smaller one.
        let mut small_rows = ConstraintRows::new();
        let mut vars = Variables::new();
        let b = vars.add(MassOperator::rigid_body(1.0, nalgebra::Matrix3::identity()).unwrap());
        small_rows.push_bilateral(
            &[RowEntry {
                block: b,
                coefs: &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            }],
            0.0,
            0.0,
        );
        let mut small = CcpProblem::new();
        small.assemble(&vars, &small_rows, &[0.0; 6]).unwrap();
        let mut out = [7.0; 2];
        let e = small
            .fill_n_entries(&mut plan, &mut out)
            .unwrap_err()
            .to_string();
        assert!(e.contains("plan position 0") && e.contains("(0, 1)"), "{e}");
        assert_eq!(out, [7.0; 2]);
    }
}
