//! Assembly of a [`CcpProblem`] from the step's variables, rows and momentum: the two
//! copies of the Jacobian (by row with `M^-1 D`, by block), `diag(N)`, the residual
//! scales, the cones' diagonal blocks, the matrix-free triplets and `r`. The row-wise
//! loops are parallel for large problems, each value computed on its own (the same bits
//! for any thread count).

use rayon::prelude::*;

use super::frame_rows::{all_frame_only, has_frame_only};
use super::problem::{CcpProblem, GROUP_ORDER, Sections, group_name};
use super::row_checks::{check_row, rows_ok};
use super::rows::{ConstraintRows, GroupRows, N_GROUPS, PER_BODY_ROWS, RowGroup};
use super::variables::{BlockId, MassOperator, Variables, rigid_inverse};
use crate::error::{ChronoError, Result};

/// Below this many rows the assembly's row-wise loops run on the calling thread.
const PAR_MIN_ASSEMBLY_ROWS: usize = 4096;

impl CcpProblem {
    /// Assemble from the step's variables, rows and momentum `k = M v + h f` (length `ndof`,
    /// N s). Reuses this problem's buffers. Rejects malformed input (a row naming a block
    /// that does not exist, coefficient counts that do not match a block, non-finite
    /// numbers, negative compliance or friction, `lo > hi`, a non-finite `M^-1 k`) with an
    /// error naming the row or field.
    pub fn assemble(&mut self, vars: &Variables, rows: &ConstraintRows, k: &[f64]) -> Result<()> {
        let (n_coef, all_only) = self.load_rows(vars, rows, k, None)?;
        self.ent_coef.push(n_coef as u32);
        self.finish_assembly(rows, all_only)
    }

    /// [`assemble`](Self::assemble) (the same problem, bit for bit) that may take the rows'
    /// storage instead of copying it: when a single group has rows (e.g. only friction
    /// triplets, a granular scene), its Jacobian, `b` and `eps` arrays are swapped with this
    /// problem's previous ones. `rows` is left empty (cleared, its capacity kept), unless a
    /// row is rejected (then it is unchanged; an error of `M^-1 k` comes after the rows were
    /// taken, and leaves them empty too).
    pub fn assemble_taking(
        &mut self,
        vars: &Variables,
        rows: &mut ConstraintRows,
        k: &[f64],
    ) -> Result<()> {
        let mut full = (0..N_GROUPS).filter(|&g| rows.groups[g].n_rows() > 0);
        // (a group with frame-only triplets gets its entries from the assembly)
        let single = match (full.next(), full.next()) {
            (Some(g), None) if !has_frame_only(&rows.groups[g]) => Some(g),
            _ => None,
        };
        let (n_coef, all_only) = self.load_rows(vars, rows, k, single)?;
        if let Some(g) = single {
            // The only group with rows starts at row 0, entry 0 and coefficient 0: its
            // arrays are the problem's (`load_rows` left these empty).
            let g = &mut rows.groups[g];
            std::mem::swap(&mut self.row_ptr, &mut g.row_ptr);
            std::mem::swap(&mut self.ent_block, &mut g.ent_block);
            std::mem::swap(&mut self.ent_coef, &mut g.ent_coef);
            std::mem::swap(&mut self.coefs, &mut g.coefs);
            std::mem::swap(&mut self.b, &mut g.b);
            std::mem::swap(&mut self.eps, &mut g.eps);
        }
        // (a taken group's coefficients were swapped in after `load_rows` counted them)
        let n_coef = if all_only { n_coef } else { self.coefs.len() };
        self.ent_coef.push(n_coef as u32);
        let done = self.finish_assembly(rows, all_only);
        rows.clear();
        done
    }

    /// The checks and the copy of the rows (all but the final sentinel of `ent_coef`);
    /// the group `taken` (the only one with rows) is checked and indexed but its
    /// `row_ptr`, `ent_block`, `ent_coef`, `coefs`, `b` and `eps` are not copied (left
    /// empty, with `row_ptr` empty too, for the caller to swap in). Returns the number of
    /// coefficients the entries span (the sentinel) and whether every row is a
    /// frame-only triplet (then their coefficients are not built yet: `coefs` is empty).
    fn load_rows(
        &mut self,
        vars: &Variables,
        rows: &ConstraintRows,
        k: &[f64],
        taken: Option<usize>,
    ) -> Result<(usize, bool)> {
        self.deferred = false;
        self.lazy.take();
        // (filled again by `load_frame_group` if the friction group has frame-only triplets)
        self.only_of.clear();
        let all_only = all_frame_only(rows);
        let mut n_frame_coefs = 0;
        if k.len() != vars.ndof() {
            return Err(ChronoError::invalid(
                "k.len()",
                k.len(),
                format!("must equal ndof = {}", vars.ndof()),
            ));
        }
        if let Some(i) = k.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("k[{i}]"),
                k[i],
                "must be finite",
            ));
        }
        self.vars.copy_from(vars);
        self.k.clear();
        self.k.extend_from_slice(k);
        // Every row a frame-only triplet: the friction group is built in place, each value
        // written (`load_frame_group`), so the entry arrays keep their length (not zeroed).
        if !all_only {
            for v in [
                &mut self.row_ptr,
                &mut self.ent_block,
                &mut self.ent_off,
                &mut self.ent_coef,
            ] {
                v.clear();
            }
            self.ent_span.clear();
        }
        // (`minv` is resized and overwritten by `fill_minv`.)
        for v in [
            &mut self.coefs,
            &mut self.b,
            &mut self.eps,
            &mut self.lo,
            &mut self.hi,
            &mut self.mu,
        ] {
            v.clear();
        }
        self.mu_rolling.clear();
        self.mu_per_body.clear();
        if taken.is_none() && !all_only {
            self.row_ptr.push(0);
        }

        let mut row = 0usize;
        for (gi, &group) in GROUP_ORDER.iter().enumerate() {
            let g = &rows.groups[group as usize];
            self.group_start[gi] = row;
            let name = group_name(group);
            // Check every row (its entries, then `b` and `eps`: the first bad field in row
            // order is named; for many rows the first bad row is found in parallel and
            // checked again for its error), then copy the group's arrays in bulk.
            let n = g.n_rows();
            if n >= PAR_MIN_ASSEMBLY_ROWS {
                // All rows at once (streaming passes); only a group that fails is searched
                // row by row for its first bad field.
                let ndof = &mut self.block_ndof;
                ndof.clear();
                ndof.extend((0..vars.len()).map(|b| vars.block_ndof(BlockId(b as u32)) as u32));
                if !rows_ok(g, ndof) {
                    let bad = (0..n)
                        .into_par_iter()
                        .with_min_len(1024)
                        .find_first(|&i| check_row(g, i, vars, name).is_err());
                    if let Some(i) = bad {
                        check_row(g, i, vars, name)?;
                    }
                }
            } else {
                for i in 0..n {
                    check_row(g, i, vars, name)?;
                }
            }
            if has_frame_only(g) {
                n_frame_coefs = self.load_frame_group(vars, g, !all_only)?;
            } else {
                self.copy_group(vars, g, taken != Some(group as usize));
            }
            row += g.n_rows();
            self.load_bounds(g, group)?;
        }
        self.n_rows = row;
        Ok(if all_only {
            (n_frame_coefs, true)
        } else {
            (self.coefs.len(), false)
        })
    }

    /// Append group `g`'s entries (the offsets and spans built here) and, if `copy`, its
    /// `row_ptr`, `ent_block`, `ent_coef`, coefficients, `b` and `eps`.
    fn copy_group(&mut self, vars: &Variables, g: &GroupRows, copy: bool) {
        {
            // The group's entries are those of its rows, and its coefficients those of its
            // entries, in order (`GroupRows::push`).
            let n_ent = g.row_ptr.get(g.n_rows()).map_or(0, |&p| p as usize);
            let (ent_base, coef_base) = (self.ent_block.len() as u32, self.coefs.len() as u32);
            let n_coef = if n_ent == 0 { 0 } else { g.coefs.len() };
            if copy {
                self.ent_block.extend_from_slice(&g.ent_block[..n_ent]);
            }
            let offset = |&b: &u32| vars.offset(BlockId(b)) as u32;
            let span = |e: usize| {
                let c1 = g.ent_coef.get(e + 1).map_or(n_coef, |&c| c as usize);
                nonzero_span(&g.coefs[g.ent_coef[e] as usize..c1])
            };
            // Each value on its own: in parallel (written in place) for many entries.
            if n_ent >= PAR_MIN_ASSEMBLY_ROWS {
                (self.ent_off).par_extend(g.ent_block[..n_ent].par_iter().map(offset));
                (self.ent_span).par_extend((0..n_ent).into_par_iter().map(span));
            } else {
                (self.ent_off).extend(g.ent_block[..n_ent].iter().map(offset));
                (self.ent_span).extend((0..n_ent).map(span));
            }
            if copy {
                (self.ent_coef).extend(g.ent_coef[..n_ent].iter().map(|&c| c + coef_base));
                self.coefs.extend_from_slice(&g.coefs[..n_coef]);
                let rows_end = g.row_ptr.get(1..g.n_rows() + 1).unwrap_or(&[]);
                (self.row_ptr).extend(rows_end.iter().map(|&p| p + ent_base));
                self.b.extend_from_slice(&g.b);
                self.eps.extend_from_slice(&g.eps);
            }
        }
    }

    /// Check and append group `g`'s bounds (box rows) or friction coefficients.
    fn load_bounds(&mut self, g: &GroupRows, group: RowGroup) -> Result<()> {
        let name = group_name(group);
        {
            let bad_mu = |i: usize, m: f64| {
                ChronoError::invalid(format!("rows.{name}[{i}].mu"), m, "must be finite and >= 0")
            };
            match group {
                RowGroup::Box => {
                    for (i, (&lo, &hi)) in g.lo.iter().zip(&g.hi).enumerate() {
                        if lo.is_nan() || hi.is_nan() || lo > hi {
                            return Err(ChronoError::invalid(
                                format!("rows.box[{i}].lo/hi"),
                                format!("[{lo}, {hi}]"),
                                "need lo <= hi",
                            ));
                        }
                    }
                    self.lo.extend_from_slice(&g.lo);
                    self.hi.extend_from_slice(&g.hi);
                }
                RowGroup::Friction => {
                    if let Some(i) = g.mu.iter().position(|m| !(m.is_finite() && *m >= 0.0)) {
                        return Err(bad_mu(i, g.mu[i]));
                    }
                    self.mu.extend_from_slice(&g.mu);
                }
                RowGroup::Rolling => {
                    if let Some(i) = g.mu.iter().position(|m| !(m.is_finite() && *m >= 0.0)) {
                        return Err(bad_mu(i / 3, g.mu[i]));
                    }
                    self.mu_rolling
                        .extend(g.mu.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
                }
                RowGroup::RollingPerBody => {
                    if let Some(i) = g.mu.iter().position(|m| !(m.is_finite() && *m >= 0.0)) {
                        return Err(bad_mu(i / 3, g.mu[i]));
                    }
                    self.mu_per_body
                        .extend(g.mu.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The rest of an assembly after [`load_rows`](Self::load_rows) (and the sentinel of
    /// `ent_coef`): the sections, `M^-1 D`, `diag(N)`, the scales, the block-ordered copy,
    /// the matrix-free triplets (from `rows`' frames) and `r`.
    fn finish_assembly(&mut self, rows: &ConstraintRows, all_only: bool) -> Result<()> {
        let (row, nblocks) = (self.n_rows, self.vars.len());
        let vars = &self.vars;
        let gs = self.group_start;
        self.sections = Sections {
            bilateral: gs[0]..gs[1],
            boxed: gs[1]..gs[2],
            unilateral: gs[2]..gs[3],
            friction: gs[3]..gs[4],
            rolling: gs[4]..gs[5],
            rolling_per_body: gs[5]..row,
        };
        let coupled =
            (0..nblocks).any(|b| matches!(vars.mass(BlockId(b as u32)), MassOperator::Coupled(_)));
        let frames = &rows.groups[RowGroup::Friction as usize].frames;
        if coupled {
            if all_only {
                let mut coefs = std::mem::take(&mut self.coefs);
                self.fill_frame_coefs(frames, &mut coefs, None);
                self.coefs = coefs;
            }
            // `M^-1 D` of the coupled blocks' entries is solved per block, in batches of
            // columns: the passes one after the other.
            self.fill_minv();
            self.count_blocks(nblocks);
            self.sort_entries();
            self.copy_transpose();
            self.build_diagonal();
            self.build_matrix_free(rows);
            self.set_free_velocity()
        } else {
            self.fill_v_free()?;
            self.count_blocks(nblocks);
            self.build_matrix_free(rows);
            if all_only {
                if self.mf.explicit_free {
                    // Nothing of a step reads the explicit coefficients (`frame_rows`).
                    self.deferred_diag_r();
                    self.fill_scales();
                    self.deferred = true;
                    return Ok(());
                }
                let mut coefs = std::mem::take(&mut self.coefs);
                self.fill_frame_coefs(frames, &mut coefs, None);
                self.coefs = coefs;
            }
            self.fill_rows_fused();
            self.fill_scales();
            // Every block touched only by matrix-free triplets: products skip the
            // explicit gather, and `minv_d` reads `M^-1 D` through the spheres' contact
            // sides (no block order needed).
            if !self.mf.explicit_free {
                self.sort_entries();
                self.copy_transpose();
            }
            Ok(())
        }
    }

    /// `M^-1 D`, `diag(N)` and `r = b + D' v_free` in one pass over the rows (each row's
    /// entries once, in parallel over chunks of rows for large problems), when no entry is
    /// on a coupled block: the same operations per value as [`fill_minv`](Self::fill_minv),
    /// [`build_diagonal`](Self::build_diagonal) and
    /// [`set_free_velocity`](Self::set_free_velocity), so the same bits. Needs `v_free`.
    fn fill_rows_fused(&mut self) {
        const ROWS: usize = 1024;
        let n = self.n_rows;
        let mut minv = std::mem::take(&mut self.minv);
        let mut diag = std::mem::take(&mut self.diag);
        let mut r = std::mem::take(&mut self.r);
        // Every value is written below: the previous assembly's are not cleared first.
        minv.resize(self.coefs.len(), 0.0);
        diag.resize(n, 0.0);
        r.resize(n, 0.0);
        let this = &*self;
        let chunk = |i0: usize, minv: &mut [f64], diag: &mut [f64], r: &mut [f64]| {
            let base = this.ent_coef[this.row_ptr[i0] as usize] as usize;
            for (k, (d, r)) in diag.iter_mut().zip(r.iter_mut()).enumerate() {
                let i = i0 + k;
                if let Some((x, s)) = this.rigid_row_fused(i, base, minv) {
                    (*d, *r) = (x, this.b[i] + s);
                    continue;
                }
                let mut x = this.eps[i];
                for e in this.row_ptr[i] as usize..this.row_ptr[i + 1] as usize {
                    let (c0, c1) = (this.ent_coef[e] as usize, this.ent_coef[e + 1] as usize);
                    let out = &mut minv[c0 - base..c1 - base];
                    (this.vars.mass(BlockId(this.ent_block[e])))
                        .apply_inverse(&this.coefs[c0..c1], out);
                    let (a0, a1) = this.nonzero_span(e);
                    x = entry_dot(x, &this.coefs[a0..a1], &minv[a0 - base..a1 - base]);
                }
                *d = x;
                *r = this.b[i] + this.row_dot(i, &this.v_free);
            }
        };
        // Split the outputs at the chunks' first rows (and their first coefficients).
        let mut parts = Vec::with_capacity(n.div_ceil(ROWS));
        let (mut rest_m, mut rest_d, mut rest_r) = (&mut minv[..], &mut diag[..], &mut r[..]);
        let mut at = 0;
        for i0 in (0..n).step_by(ROWS) {
            let i1 = (i0 + ROWS).min(n);
            let end = self.ent_coef[self.row_ptr[i1] as usize] as usize;
            let (m, tm) = rest_m.split_at_mut(end - at);
            let (d, td) = rest_d.split_at_mut(i1 - i0);
            let (q, tr) = rest_r.split_at_mut(i1 - i0);
            parts.push((i0, m, d, q));
            (rest_m, rest_d, rest_r, at) = (tm, td, tr, end);
        }
        if n >= PAR_MIN_ASSEMBLY_ROWS {
            parts
                .into_par_iter()
                .for_each(|(i0, m, d, q)| chunk(i0, m, d, q));
        } else {
            parts
                .into_iter()
                .for_each(|(i0, m, d, q)| chunk(i0, m, d, q));
        }
        (self.minv, self.diag, self.r) = (minv, diag, r);
    }

    /// Replace the momentum `k` of an assembled problem (same variables and rows) and
    /// recompute what depends on it, `v_free = M^-1 k` and `r = b + D' v_free`: bit for bit
    /// what [`assemble`](Self::assemble) with this `k` gives, without rebuilding the rows.
    pub fn set_momentum(&mut self, k: &[f64]) -> Result<()> {
        if k.len() != self.vars.ndof() {
            return Err(ChronoError::invalid(
                "k.len()",
                k.len(),
                format!("must equal ndof = {}", self.vars.ndof()),
            ));
        }
        if let Some(i) = k.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("k[{i}]"),
                k[i],
                "must be finite",
            ));
        }
        self.k.clear();
        self.k.extend_from_slice(k);
        self.set_free_velocity()
    }

    /// `v_free = M^-1 k` and `r = b + D' v_free` from the stored `k`.
    fn set_free_velocity(&mut self) -> Result<()> {
        self.fill_v_free()?;
        if self.deferred {
            // (`diag` is recomputed with `r`: the same values)
            self.deferred_diag_r();
            return Ok(());
        }
        // Every value is written below: the previous assembly's are not cleared first.
        let mut r = std::mem::take(&mut self.r);
        r.resize(self.n_rows, 0.0);
        let one = |(i, r): (usize, &mut f64)| *r = self.b[i] + self.row_dot(i, &self.v_free);
        if self.n_rows >= PAR_MIN_ASSEMBLY_ROWS {
            r.par_iter_mut().enumerate().for_each(one);
        } else {
            r.iter_mut().enumerate().for_each(one);
        }
        self.r = r;
        Ok(())
    }

    /// `v_free = M^-1 k` from the stored `k` (an error if not finite).
    fn fill_v_free(&mut self) -> Result<()> {
        let vars = &self.vars;
        let k = &self.k;
        self.v_free.clear();
        self.v_free.resize(vars.ndof(), 0.0);
        vars.apply_inverse(k, &mut self.v_free);
        if let Some(i) = self.v_free.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("M^-1 k [dof {i}]"),
                self.v_free[i],
                "must be finite (momentum too large for the mass)",
            ));
        }
        Ok(())
    }

    /// `M^-1 D` (`minv`, laid out like `coefs`). Entries on diagonal blocks (particles,
    /// bodies) one by one, in parallel over chunks of entries for large problems (each
    /// entry on its own: the same bits for any thread count). Entries on a coupled block
    /// (an implicit mesh, `H^-1 D_i` through a factorization) are gathered per block into
    /// the columns of one right-hand side and solved together
    /// ([`CoupledMass::apply_inverse_columns`](super::CoupledMass::apply_inverse_columns)): one sweep over the factor per batch of
    /// columns instead of one per row, the same values column by column.
    fn fill_minv(&mut self) {
        const ENTRIES: usize = 2048;
        // Every coefficient is written below (each entry's, diagonal or coupled): the
        // previous assembly's values are not cleared first.
        let mut minv = std::mem::take(&mut self.minv);
        minv.resize(self.coefs.len(), 0.0);
        let n_ent = self.ent_block.len();
        let coupled = |e: usize| {
            matches!(
                self.vars.mass(BlockId(self.ent_block[e])),
                MassOperator::Coupled(_)
            )
        };
        let chunk = |e0: usize, out: &mut [f64]| {
            let e1 = (e0 + ENTRIES).min(n_ent);
            let base = self.ent_coef[e0] as usize;
            for e in (e0..e1).filter(|&e| !coupled(e)) {
                let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
                (self.vars.mass(BlockId(self.ent_block[e])))
                    .apply_inverse(&self.coefs[c0..c1], &mut out[c0 - base..c1 - base]);
            }
        };
        // Split `minv` at the chunks' first coefficients (a few dozen slices).
        let mut parts = Vec::with_capacity(n_ent.div_ceil(ENTRIES));
        let (mut rest, mut at) = (&mut minv[..], 0);
        for e0 in (0..n_ent).step_by(ENTRIES) {
            let end = self.ent_coef[(e0 + ENTRIES).min(n_ent)] as usize;
            let (mine, tail) = rest.split_at_mut(end - at);
            parts.push((e0, mine));
            (rest, at) = (tail, end);
        }
        if n_ent >= 2 * ENTRIES {
            parts.into_par_iter().for_each(|(e0, out)| chunk(e0, out));
        } else {
            parts.into_iter().for_each(|(e0, out)| chunk(e0, out));
        }
        // The coupled blocks' entries, per block in entry order, in batches of columns
        // (bounded scratch: `COLUMNS ndof` values).
        const COLUMNS: usize = 64;
        let mut by_block: Vec<(u32, Vec<usize>)> = Vec::new();
        for e in (0..n_ent).filter(|&e| coupled(e)) {
            let b = self.ent_block[e];
            match by_block.iter_mut().find(|(blk, _)| *blk == b) {
                Some((_, list)) => list.push(e),
                None => by_block.push((b, vec![e])),
            }
        }
        let mut columns = Vec::new();
        for (b, list) in &by_block {
            let MassOperator::Coupled(op) = self.vars.mass(BlockId(*b)) else {
                continue;
            };
            let n = op.ndof();
            for batch in list.chunks(COLUMNS) {
                columns.clear();
                for &e in batch {
                    let c0 = self.ent_coef[e] as usize;
                    columns.extend_from_slice(&self.coefs[c0..c0 + n]);
                }
                op.apply_inverse_columns(&mut columns, batch.len());
                for (&e, col) in batch.iter().zip(columns.chunks_exact(n)) {
                    let c0 = self.ent_coef[e] as usize;
                    minv[c0..c0 + n].copy_from_slice(col);
                }
            }
        }
        self.minv = minv;
    }

    /// The block order of the Jacobian's entries (counting sort of entries by block,
    /// stable: row order kept within a block): each block's slots and coefficient range
    /// (the slots themselves: [`sort_entries`](Self::sort_entries)).
    fn count_blocks(&mut self, nblocks: usize) {
        self.tr_ptr.clear();
        self.tr_ptr.resize(nblocks + 1, 0);
        for &blk in &self.ent_block {
            self.tr_ptr[blk as usize + 1] += 1;
        }
        for i in 0..nblocks {
            self.tr_ptr[i + 1] += self.tr_ptr[i];
        }
        self.tr_cptr.clear();
        let mut c = 0u32;
        for i in 0..nblocks {
            self.tr_cptr.push(c);
            let n = self.tr_ptr[i + 1] - self.tr_ptr[i];
            c += n * self.vars.block_ndof(BlockId(i as u32)) as u32;
        }
        self.tr_cptr.push(c);
        self.tr_row.clear();
        self.tr_ent.clear();
        self.tr_minv.clear();
    }

    /// The slots of the block order ([`count_blocks`](Self::count_blocks)'s): each one's
    /// row and entry (a counting sort, u32 work only).
    fn sort_entries(&mut self) {
        let n_ent = self.ent_block.len();
        // Every slot of `tr_row` and `tr_ent` is written below: the previous assembly's
        // values are not cleared first.
        self.tr_row.resize(n_ent, 0);
        let mut tr_ent = std::mem::take(&mut self.tr_ent);
        tr_ent.resize(n_ent, 0);
        // (`tr_minv` is not built yet: its length serves as the cursor store)
        let mut cursor = std::mem::take(&mut self.tr_cursor);
        cursor.clear();
        cursor.extend_from_slice(&self.tr_ptr[..self.tr_ptr.len() - 1]);
        for i in 0..self.n_rows {
            for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                let blk = self.ent_block[e] as usize;
                let t = cursor[blk] as usize;
                cursor[blk] += 1;
                self.tr_row[t] = i as u32;
                tr_ent[t] = e as u32;
            }
        }
        // (the coefficients: `copy_transpose`)
        self.tr_ent = tr_ent;
        self.tr_cursor = cursor;
    }

    /// The block-ordered copy of `M^-1 D` ([`sort_entries`](Self::sort_entries)'s
    /// slots), which [`minv_d`](Self::minv_d) streams (without it, every block being a
    /// matrix-free sphere's, it reads `M^-1 D` through the spheres' contact sides, the
    /// same values in the same order). Slot by slot over
    /// each run of equal-size blocks (a run's slots are contiguous and of one size), in
    /// parallel for large problems.
    fn copy_transpose(&mut self) {
        let n_ent = self.ent_block.len();
        let tr_ent = std::mem::take(&mut self.tr_ent);
        self.tr_minv.resize(self.minv.len(), 0.0);
        let par = n_ent >= PAR_MIN_ASSEMBLY_ROWS;
        for run in self.vars.runs() {
            let (b0, b1) = (run.first_block, run.first_block + run.n_blocks);
            let (t0, t1) = (self.tr_ptr[b0] as usize, self.tr_ptr[b1] as usize);
            let (c0, c1) = (self.tr_cptr[b0] as usize, self.tr_cptr[b1] as usize);
            if t1 == t0 || run.ndof == 0 {
                continue;
            }
            let (minv, ent_coef, tr_ent) = (&self.minv, &self.ent_coef, &tr_ent);
            let copy = |(k, out): (usize, &mut [f64])| {
                let src = ent_coef[tr_ent[t0 + k] as usize] as usize;
                // a rigid body's 6 or a particle's 3 values as one fixed-size move (not a
                // library call per entry: density rows have ~60 entries a row)
                if let Ok(o) = <&mut [f64; 6]>::try_from(&mut *out) {
                    *o = minv[src..src + 6].try_into().expect("6");
                } else if let Ok(o) = <&mut [f64; 3]>::try_from(&mut *out) {
                    *o = minv[src..src + 3].try_into().expect("3");
                } else {
                    out.copy_from_slice(&minv[src..src + out.len()]);
                }
            };
            let slots = &mut self.tr_minv[c0..c1];
            if par {
                slots.par_chunks_mut(run.ndof).enumerate().for_each(copy);
            } else {
                slots.chunks_mut(run.ndof).enumerate().for_each(copy);
            }
        }
        self.tr_ent = tr_ent;
    }

    /// `diag(N)`, the residual scales and the diagonal blocks of the cones (each value on
    /// its own, in parallel for large problems: the same bits for any thread count).
    fn build_diagonal(&mut self) {
        let par = self.n_rows >= PAR_MIN_ASSEMBLY_ROWS;
        // Every value is written below: the previous assembly's are not cleared first.
        let mut diag = std::mem::take(&mut self.diag);
        diag.resize(self.n_rows, 0.0);
        let one = |(i, d): (usize, &mut f64)| {
            let mut x = self.eps[i];
            for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                let (c0, c1) = self.nonzero_span(e);
                x = entry_dot(x, &self.coefs[c0..c1], &self.minv[c0..c1]);
            }
            *d = x;
        };
        if par {
            diag.par_iter_mut().enumerate().for_each(one);
        } else {
            diag.iter_mut().enumerate().for_each(one);
        }
        self.diag = diag;
        self.fill_scales();
    }

    /// [`fill_rows_fused`](Self::fill_rows_fused) for a row whose entries are all on rigid
    /// bodies (6 coefficients each, the usual contact row): writes the entries' `M^-1 D`
    /// into `minv` (which starts at coefficient `base`) and returns `diag(N)_i` and
    /// `D_i' v_free` with fixed-size arrays, the same sums in the same order as
    /// [`build_diagonal`](Self::build_diagonal) and [`row_dot`](Self::row_dot). `None`
    /// (nothing written) for any other row.
    #[inline]
    fn rigid_row_fused(&self, i: usize, base: usize, minv: &mut [f64]) -> Option<(f64, f64)> {
        let (e0, e1) = (self.row_ptr[i] as usize, self.row_ptr[i + 1] as usize);
        let six = |e: usize| self.ent_coef[e + 1] - self.ent_coef[e] == 6;
        if !(e0..e1).all(six) {
            return None;
        }
        let (mut x, mut s) = (self.eps[i], 0.0);
        for e in e0..e1 {
            let c0 = self.ent_coef[e] as usize;
            let off = self.ent_off[e] as usize;
            let c: &[f64; 6] = self.coefs[c0..c0 + 6].try_into().expect("6");
            let v: &[f64; 6] = self.v_free.get(off..off + 6)?.try_into().expect("6");
            let m: &mut [f64; 6] = (&mut minv[c0 - base..c0 - base + 6]).try_into().expect("6");
            match self.vars.mass(BlockId(self.ent_block[e])) {
                // `MassOperator::apply_inverse`'s rigid arm on fixed-size arrays, inlined.
                MassOperator::RigidBody {
                    mass, inv_inertia, ..
                } => rigid_inverse(*mass, inv_inertia, c, m),
                op => op.apply_inverse(c, m),
            }
            for k in 0..6 {
                x += c[k] * m[k];
            }
            for k in 0..6 {
                s += c[k] * v[k];
            }
        }
        Some((x, s))
    }

    /// The residual scales from `diag(N)`, and the cone blocks marked for rebuilding.
    fn fill_scales(&mut self) {
        // Every value is written below (by cone block).
        self.scale.resize(self.n_rows, 0.0);
        let inv = |d: f64| if d > 0.0 { 1.0 / d } else { 0.0 };
        // The friction triplets (most rows of a granular problem) in parallel, each on its
        // own (the same values).
        let fr = self.sections.friction.clone();
        let (diag, scale) = (&self.diag, &mut self.scale);
        let triplet = |(d, s): (&[f64], &mut [f64])| s.fill(inv((d[0] + d[1] + d[2]) / 3.0));
        if fr.len() >= PAR_MIN_ASSEMBLY_ROWS {
            (diag[fr.clone()].par_chunks(3))
                .zip(scale[fr.clone()].par_chunks_mut(3))
                .with_min_len(1024)
                .for_each(triplet);
        } else {
            (diag[fr.clone()].chunks(3))
                .zip(scale[fr.clone()].chunks_mut(3))
                .for_each(triplet);
        }
        let mut i = 0;
        while i < self.n_rows {
            if i == fr.start && !fr.is_empty() {
                i = fr.end;
                continue;
            }
            let (start, n) = self.sections.block_of(i);
            let mean = self.diag[start..start + n].iter().sum::<f64>() / n as f64;
            self.scale[start..start + n].fill(inv(mean));
            i = start + n;
        }
        // The cone blocks (`cone_block`) are built on first use: only PSOR reads them.
        self.cone_blocks.reset();
    }

    /// The upper triangles of the diagonal blocks of `N` ([`CcpProblem::cone_block`]'s
    /// layout) into `blocks`: per section, a fixed-size upper triangle per contact.
    pub(super) fn fill_cone_blocks(&self, blocks: &mut Vec<f64>) {
        let par = self.n_rows >= PAR_MIN_ASSEMBLY_ROWS;
        // Cone blocks: per section, a fixed-size upper triangle per contact.
        blocks.clear();
        let s = self.sections.clone();
        let sizes = [
            (s.friction.clone(), 3),
            (s.rolling.clone(), 6),
            (s.rolling_per_body.clone(), PER_BODY_ROWS),
        ];
        let total: usize = (sizes.iter())
            .map(|(r, n)| r.len() / n * (n * (n + 1) / 2))
            .sum();
        blocks.resize(total, 0.0);
        let mut rest = &mut blocks[..];
        for (rows, n) in sizes {
            let len = n * (n + 1) / 2;
            let (mine, tail) = rest.split_at_mut(rows.len() / n * len);
            rest = tail;
            let fill = |(c, out): (usize, &mut [f64])| {
                let start = rows.start + c * n;
                let mut q = 0;
                for j in 0..n {
                    for k in j..n {
                        out[q] = self.n_entry(start + j, start + k);
                        q += 1;
                    }
                }
            };
            if par {
                mine.par_chunks_mut(len).enumerate().for_each(fill);
            } else {
                mine.chunks_mut(len).enumerate().for_each(fill);
            }
        }
    }
}

/// `[lo, hi)`: the span of `c` outside which every coefficient is zero (`[0, 0]` if all
/// are); the whole range for up to 6 coefficients (a body's or a particle's block, summed
/// unrolled). See [`CcpProblem::nonzero_span`].
pub(super) fn nonzero_span(c: &[f64]) -> [u32; 2] {
    if c.len() <= 6 {
        return [0, c.len() as u32];
    }
    match c.iter().position(|&x| x != 0.0) {
        Some(lo) => {
            let hi = c.iter().rposition(|&x| x != 0.0).map_or(lo, |h| h + 1);
            [lo as u32, hi as u32]
        }
        None => [0, 0],
    }
}

/// `x + sum_k c_k m_k` over one entry's coefficients, in order: a rigid body's 6 values as
/// fixed-size arrays (the same sums in the same order, so the same bits), others as slices.
/// The diagonal `diag(N)_i = eps_i + sum_e D_e . (M^-1 D)_e` is built from it.
#[inline(always)]
fn entry_dot(mut x: f64, c: &[f64], m: &[f64]) -> f64 {
    if let (Ok(c), Ok(m)) = (<&[f64; 6]>::try_from(c), <&[f64; 6]>::try_from(m)) {
        for k in 0..6 {
            x += c[k] * m[k];
        }
        return x;
    }
    for (c, m) in c.iter().zip(m) {
        x += c * m;
    }
    x
}
