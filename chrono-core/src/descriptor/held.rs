//! A sub-problem kept across the sweeps of a block method: the rows of one block on only
//! the variables they touch, with the other rows' impulses held.
//!
//! A block Gauss–Seidel (e.g. `chrono_ccp::LocalDirect`) solves, sweep after sweep, the
//! CCP of a set of rows `R` with the other rows `O` held at their impulses `g_O`:
//!
//! ```text
//! min 1/2 x' N_RR x + (r_R + N_RO g_O)' x,   x in the cones of R
//! ```
//!
//! which is the CCP of the rows `R` for the momentum `k + D_O g_O` ([`CcpProblem::subproblem_rows`]).
//! Between sweeps only `g_O` changes. [`HeldSubproblem`] therefore assembles the rows once
//! ([`build`](HeldSubproblem::build)) and afterwards only recomputes the momentum
//! ([`update`](HeldSubproblem::update)): `D_O g_O` needs only the *coupling* rows, those of
//! `O` that touch a body of `R`, and `r = b + D' M^-1 k` only the sub-problem's own
//! variables. The variables are compacted to the blocks the rows of `R` touch (a few hundred
//! bodies around a vehicle in a bed of 20 000 grains), so a solver's per-iteration vectors
//! are that size, not the whole system's.

use super::{BlockId, CcpProblem, ConstraintRows, Variables};
use crate::error::Result;

/// The sub-problem of a fixed set of rows with the others held; see the module docs.
#[derive(Debug, Clone, Default)]
pub struct HeldSubproblem {
    rows: Vec<usize>,
    /// Parent block of each sub-problem block.
    blocks: Vec<u32>,
    /// Sub-problem block of each parent block (`u32::MAX`: not touched).
    map: Vec<u32>,
    /// Offset of each sub-problem block in the sub-problem's velocity vector.
    offsets: Vec<usize>,
    /// Rows outside the set that touch one of its blocks.
    coupling: Vec<usize>,
    k: Vec<f64>,
    /// Scratch kept across builds (no allocation per step once sized).
    member: Vec<bool>,
    sub_rows: ConstraintRows,
    problem: CcpProblem,
}

impl HeldSubproblem {
    /// An empty sub-problem (no rows).
    pub fn new() -> Self {
        Self::default()
    }

    /// Assemble the sub-problem of `rows` (strictly increasing, whole cone blocks, as
    /// [`CcpProblem::subproblem_rows`]) of `parent` with the other rows held at `gamma`.
    /// The sub-problem's row `j` is `parent`'s row `rows[j]`; its variable blocks are the
    /// parent's blocks touched by `rows`, in the parent's order.
    ///
    /// # Errors
    /// A row list that is not increasing, out of range or cuts a cone block (naming the
    /// entry); `gamma` of the wrong length or a momentum the masses cannot take (as
    /// [`CcpProblem::assemble`]).
    pub fn build(&mut self, parent: &CcpProblem, rows: &[usize], gamma: &[f64]) -> Result<()> {
        let blocks = parent.whole_blocks(rows)?;
        check_gamma(parent, gamma)?;
        let vars = parent.variables();
        self.rows.clear();
        self.rows.extend_from_slice(rows);
        self.map.clear();
        self.map.resize(vars.len(), u32::MAX);
        self.member.clear();
        self.member.resize(parent.n_rows(), false);
        for &i in rows {
            self.member[i] = true;
            for b in parent.row_blocks(i) {
                self.map[b.0 as usize] = 0;
            }
        }
        self.blocks.clear();
        let mut sub_vars = Variables::new();
        for (b, m) in self.map.iter_mut().enumerate() {
            if *m == 0 {
                *m = self.blocks.len() as u32;
                self.blocks.push(b as u32);
                let blk = BlockId(b as u32);
                let mass = vars.mass(blk).clone();
                // (a frame-only triplet's rows are built from its blocks' rotations)
                match vars.rotation(blk) {
                    Some(q) => sub_vars.add_oriented(mass, *q),
                    None => sub_vars.add(mass),
                };
            }
        }
        self.coupling.clear();
        let (member, map) = (&self.member, &self.map);
        self.coupling.extend((0..parent.n_rows()).filter(|&i| {
            !member[i] && parent.row_blocks(i).any(|b| map[b.0 as usize] != u32::MAX)
        }));
        self.sub_rows.clear();
        for (i, len) in blocks {
            parent.push_rows_mapped(i..i + len, Some(&self.map), &mut self.sub_rows);
        }
        self.offsets.clear();
        self.offsets
            .extend((0..self.blocks.len()).map(|b| sub_vars.offset(BlockId(b as u32))));
        self.held_momentum(parent, gamma);
        self.problem.assemble(&sub_vars, &self.sub_rows, &self.k)
    }

    /// Recompute the momentum for new held impulses `gamma` (the parent's full vector; the
    /// entries of the sub-problem's own rows are ignored). The same result, bit for bit, as
    /// [`build`](Self::build) with this `gamma`.
    ///
    /// # Errors
    /// As [`build`](Self::build) for `gamma` and the momentum.
    pub fn update(&mut self, parent: &CcpProblem, gamma: &[f64]) -> Result<()> {
        check_gamma(parent, gamma)?;
        self.held_momentum(parent, gamma);
        self.problem.set_momentum(&self.k)
    }

    /// `k_sub = k + D_O g_O` on the sub-problem's blocks, from the coupling rows in order.
    fn held_momentum(&mut self, parent: &CcpProblem, gamma: &[f64]) {
        let vars = parent.variables();
        self.k.clear();
        for &b in &self.blocks {
            self.k
                .extend_from_slice(&parent.momentum()[vars.range(BlockId(b))]);
        }
        for &i in &self.coupling {
            let g = gamma[i];
            if g == 0.0 {
                continue;
            }
            for (b, coefs) in parent.row_entries_raw(i) {
                let nb = self.map[b as usize];
                if nb == u32::MAX {
                    continue;
                }
                let off = self.offsets[nb as usize];
                for (x, c) in self.k[off..off + coefs.len()].iter_mut().zip(coefs) {
                    *x += g * c;
                }
            }
        }
    }

    /// The assembled sub-problem.
    pub fn problem(&self) -> &CcpProblem {
        &self.problem
    }

    /// The parent's rows, in the sub-problem's order.
    pub fn rows(&self) -> &[usize] {
        &self.rows
    }

    /// The parent's rows outside the set whose impulses enter the momentum.
    pub fn coupling_rows(&self) -> &[usize] {
        &self.coupling
    }

    /// The parent's block of each sub-problem block.
    pub fn parent_blocks(&self) -> &[u32] {
        &self.blocks
    }
}

fn check_gamma(parent: &CcpProblem, gamma: &[f64]) -> Result<()> {
    if gamma.len() != parent.n_rows() {
        return Err(crate::error::ChronoError::invalid(
            "gamma.len()",
            gamma.len(),
            format!("must equal the parent's row count {}", parent.n_rows()),
        ));
    }
    Ok(())
}
