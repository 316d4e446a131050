//! The coloured parallel sweep of [`Psor`] ([`PsorOptions::parallel`](super::PsorOptions::parallel)):
//! units coloured greedily so that units of one colour share no variable block; each
//! colour updated from the same velocities in parallel (Jacobi within a colour).

use chrono_core::descriptor::CcpProblem;
use rayon::prelude::*;

use super::Psor;
use super::unit::{ReadVel, SweepData, current, unit_update};

impl Psor {
    /// One coloured sweep: the colours in order (reversed backwards); within a colour every
    /// unit is updated from the same `w` in parallel (they share no variable block), then
    /// `g` is written and `w` updated block by block in parallel.
    pub(super) fn sweep_coloured(&mut self, problem: &CcpProblem, g: &mut [f64], forward: bool) {
        let col = self.colouring.as_ref().expect("coloured sweep");
        let data = SweepData {
            problem,
            setup: &self.setup,
            omega: self.options.omega,
        };
        let nc = col.ptr.len() - 1;
        let nb = problem.variables().len();
        for k in 0..nc {
            let c = if forward { k } else { nc - 1 - k };
            let units_c = &col.order[col.ptr[c]..col.ptr[c + 1]];
            let (units, w) = (&self.units, &self.w);
            let gr: &[f64] = g;
            let update = |&u: &u32| {
                let unit = units[u as usize];
                unit_update(&data, unit, &current(unit, gr), &ReadVel::explicit(w))
            };
            if units_c.len() >= PAR_MIN_UNITS {
                units_c
                    .par_iter()
                    .map(update)
                    .collect_into_vec(&mut self.deltas);
            } else {
                self.deltas.clear();
                self.deltas.extend(units_c.iter().map(update));
            }
            // g <- new values; keep the changes dg for w.
            for d in &mut self.deltas {
                for j in 0..d.len {
                    let i = d.start + j;
                    let dg = d.new[j] - g[i];
                    g[i] = d.new[j];
                    d.new[j] = dg;
                }
            }
            // w += M^-1 D dg, each block by the one unit of colour c that touches it.
            let deltas = &self.deltas;
            let block_unit = &col.block_unit[c * nb..(c + 1) * nb];
            let add = |b: usize, wb: &mut [f64]| {
                let k = block_unit[b];
                if k == u32::MAX {
                    return;
                }
                let d = &deltas[k as usize];
                for j in 0..d.len {
                    let dg = d.new[j];
                    if dg == 0.0 {
                        continue;
                    }
                    for (blk, m) in problem.row_minv_entries(d.start + j) {
                        if blk.0 as usize == b {
                            for (x, mv) in wb.iter_mut().zip(m) {
                                *x += dg * mv;
                            }
                        }
                    }
                }
            };
            let par = problem.ndof() >= PAR_MIN_DOF;
            for run in problem.variables().runs() {
                let range = run.dof_offset..run.dof_offset + run.n_blocks * run.ndof;
                if par {
                    let chunks = self.w[range].par_chunks_mut(run.ndof).enumerate();
                    chunks.for_each(|(i, wb)| add(run.first_block + i, wb));
                } else {
                    for (i, wb) in self.w[range].chunks_mut(run.ndof).enumerate() {
                        add(run.first_block + i, wb);
                    }
                }
            }
        }
    }

    /// Colour the units greedily in storage order (a unit gets the smallest colour not used
    /// by a unit sharing one of its blocks); `None` if more than 64 colours are needed.
    pub(super) fn colour(&self, problem: &CcpProblem) -> Option<Colouring> {
        let nb = problem.variables().len();
        let mut used = vec![0u64; nb];
        let mut colour = Vec::with_capacity(self.units.len());
        let mut blocks = Vec::new();
        let mut nc = 0;
        for &unit in &self.units {
            let (start, len) = unit.rows();
            blocks.clear();
            for i in start..start + len {
                blocks.extend(problem.row_blocks(i).map(|b| b.0 as usize));
            }
            let mask = blocks.iter().fold(0u64, |m, &b| m | used[b]);
            let c = (!mask).trailing_zeros() as usize;
            if c >= 64 {
                return None;
            }
            for &b in &blocks {
                used[b] |= 1 << c;
            }
            colour.push(c);
            nc = nc.max(c + 1);
        }
        let mut ptr = vec![0usize; nc + 1];
        for &c in &colour {
            ptr[c + 1] += 1;
        }
        for c in 0..nc {
            ptr[c + 1] += ptr[c];
        }
        let mut cursor = ptr.clone();
        let mut order = vec![0u32; self.units.len()];
        let mut block_unit = vec![u32::MAX; nc * nb];
        for (u, &c) in colour.iter().enumerate() {
            let k = cursor[c] - ptr[c];
            order[cursor[c]] = u as u32;
            cursor[c] += 1;
            let (start, len) = self.units[u].rows();
            for i in start..start + len {
                for b in problem.row_blocks(i) {
                    block_unit[c * nb + b.0 as usize] = k as u32;
                }
            }
        }
        Some(Colouring {
            ptr,
            order,
            block_unit,
        })
    }
}

/// Units of one colour below this count are updated on the calling thread.
const PAR_MIN_UNITS: usize = 256;

/// Below this many dof the block-wise `w` update of a colour runs on the calling thread.
const PAR_MIN_DOF: usize = 8192;

/// The colouring of the units for the parallel sweep.
#[derive(Debug, Clone)]
pub(super) struct Colouring {
    /// Units of colour `c`: `order[ptr[c]..ptr[c + 1]]` (storage order within a colour).
    ptr: Vec<usize>,
    order: Vec<u32>,
    /// For colour `c` and block `b`, the index (within the colour) of the unit touching it,
    /// or `u32::MAX`: `block_unit[c * n_blocks + b]`.
    block_unit: Vec<u32>,
}
