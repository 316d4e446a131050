//! The operators of a [`CcpProblem`]: `M^-1 D g`, `N g`, the gradient and objective, the
//! projection onto `Y`, the common residual and the new velocities. All allocation-free,
//! rayon-parallel above a size threshold, and deterministic (fixed-order reductions).

use rayon::prelude::*;

use super::cone::{
    project_box, project_rolling_cone, project_rolling_per_body_cone, project_unilateral,
};
use super::cone_simd::{friction_residual_terms, project_friction_cones};
use super::frames::NONE;
use super::frames_simd::RowData;
use super::problem::{CcpProblem, CcpWork};
use super::reduce::{self, sum_by};
use super::rows::PER_BODY_ROWS;

/// Below this many rows, row-wise loops run on the calling thread.
const PAR_MIN_ROWS: usize = 4096;

/// Friction triplets per task of the parallel projections and residual terms (element-wise
/// work: the split does not change any value).
const TERM_TASK: usize = 512;

/// Below this many dof, block-wise loops run on the calling thread.
const PAR_MIN_DOF: usize = 8192;

/// Friction triplets per task of the row pass.
const TRIPLET_TASK: usize = 256;

/// Rows per unit of [`CcpProblem::gradient_by_units`]: [`reduce::CHUNK`] friction triplets,
/// i.e. three reduction chunks of rows.
pub const UNIT_ROWS: usize = 3 * reduce::CHUNK;

impl CcpProblem {
    /// `v = M^-1 D g` (length `ndof`), gathered block by block from the block-ordered copy of
    /// the Jacobian (one streaming pass over it; parallel over blocks for large systems).
    pub fn minv_d(&self, gamma: &[f64], v: &mut [f64]) {
        assert_eq!(gamma.len(), self.n_rows, "gamma has the wrong length");
        assert_eq!(v.len(), self.ndof(), "v has the wrong length");
        if self.deferred {
            // (every block with rows is a matrix-free sphere's)
            self.minv_d_deferred(gamma, v);
            return;
        }
        self.minv_d_blocks(gamma, v, false);
    }

    /// [`minv_d`](Self::minv_d) on every block but the matrix-free spheres' (zero there:
    /// their velocities live in world frame, [`mf_gather`](Self::mf_gather)), for a
    /// solver that keeps both: the other blocks get the same bits as from `minv_d`.
    ///
    /// # Panics
    /// If `gamma` does not have one entry per row or `v` one per dof (as `minv_d`).
    pub fn minv_d_explicit(&self, gamma: &[f64], v: &mut [f64]) {
        assert_eq!(gamma.len(), self.n_rows, "gamma has the wrong length");
        assert_eq!(v.len(), self.ndof(), "v has the wrong length");
        if self.mf.explicit_free {
            // (every block with rows is a matrix-free sphere's)
            v.fill(0.0);
            return;
        }
        for (b, &skip) in self.mf.skip_block.iter().enumerate() {
            if skip {
                v[self.vars.range(super::BlockId(b as u32))].fill(0.0);
            }
        }
        self.minv_d_blocks(gamma, v, true);
    }

    /// [`minv_d`](Self::minv_d); with `skip_spheres` the blocks of the matrix-free spheres
    /// are left untouched (only matrix-free triplets touch them, and those read `work.w`).
    fn minv_d_blocks(&self, gamma: &[f64], v: &mut [f64], skip_spheres: bool) {
        if skip_spheres && self.mf.explicit_free {
            return;
        }
        let skip = &self.mf.skip_block;
        // Without the block order (every block with rows is a matrix-free sphere's, see
        // the assembly) `M^-1 D` is read through the spheres' contact sides.
        let copied = self.tr_minv.len() == self.minv.len();
        let gather = |block: usize, out: &mut [f64]| {
            if skip_spheres && skip[block] {
                return;
            }
            out.fill(0.0);
            let nd = out.len();
            let (t0, t1) = (self.tr_ptr[block] as usize, self.tr_ptr[block + 1] as usize);
            if !copied {
                if t0 == t1 {
                    return;
                }
                self.sphere_minv_d(block, gamma, out.try_into().expect("a sphere"));
                return;
            }
            let c = &self.tr_minv[self.tr_cptr[block] as usize..self.tr_cptr[block + 1] as usize];
            if let Ok(out) = <&mut [f64; 6]>::try_from(&mut *out) {
                // A rigid body: fixed-size columns, the same sums in the same order.
                for (&t, col) in self.tr_row[t0..t1].iter().zip(c.chunks_exact(6)) {
                    let g = gamma[t as usize];
                    // A zero impulse (a separating contact, a row a solver fills later)
                    // adds nothing: skipping it keeps the bits (the sums start at +0).
                    if g == 0.0 {
                        continue;
                    }
                    let col: &[f64; 6] = col.try_into().expect("6");
                    for k in 0..6 {
                        out[k] += g * col[k];
                    }
                }
                return;
            }
            if let Ok(out) = <&mut [f64; 3]>::try_from(&mut *out) {
                // A particle (density rows, MPM markers): fixed-size columns, the same
                // sums in the same order as below.
                for (&t, col) in self.tr_row[t0..t1].iter().zip(c.chunks_exact(3)) {
                    let g = gamma[t as usize];
                    let col: &[f64; 3] = col.try_into().expect("3");
                    for k in 0..3 {
                        out[k] += g * col[k];
                    }
                }
                return;
            }
            for (t, col) in (t0..t1).zip(c.chunks_exact(nd)) {
                let g = gamma[self.tr_row[t] as usize];
                for (o, x) in out.iter_mut().zip(col) {
                    *o += g * x;
                }
            }
        };
        let par = self.ndof() >= PAR_MIN_DOF;
        for run in self.vars.runs() {
            let range = run.dof_offset..run.dof_offset + run.n_blocks * run.ndof;
            if par {
                v[range]
                    .par_chunks_mut(run.ndof)
                    .enumerate()
                    .for_each(|(i, o)| gather(run.first_block + i, o));
            } else {
                for (i, o) in v[range].chunks_mut(run.ndof).enumerate() {
                    gather(run.first_block + i, o);
                }
            }
        }
    }

    /// `out = M^-1 D g` on the block of a matrix-free sphere, its entries read through
    /// its contact sides (in contact order, each contact's three rows in order: the
    /// block order's sums in the same order, so the same bits as from it).
    fn sphere_minv_d(&self, block: usize, gamma: &[f64], out: &mut [f64; 6]) {
        let mf = &self.mf;
        let s = mf.block_sphere[block] as usize;
        for q in mf.b_ptr[s] as usize..mf.b_ptr[s + 1] as usize {
            let (i, side) = ((mf.s_row[q] / 2) as usize, mf.s_row[q] % 2);
            for row in i..i + 3 {
                let g = gamma[row];
                // (a zero impulse adds nothing, as in the block order)
                if g == 0.0 {
                    continue;
                }
                // side B is the row's second entry if side A has one too
                let e0 = self.row_ptr[row] as usize;
                let two = self.row_ptr[row + 1] as usize - e0 == 2;
                let e = e0 + usize::from(side == 1 && two);
                debug_assert_eq!(self.ent_block[e] as usize, block);
                let src = self.ent_coef[e] as usize;
                let col: &[f64; 6] = self.minv()[src..src + 6].try_into().expect("6");
                for k in 0..6 {
                    out[k] += g * col[k];
                }
            }
        }
    }

    /// Check the lengths and fill `work.v = M^-1 D g` (the explicit rows' blocks) and
    /// `work.w` (the matrix-free spheres'): the first half of a product.
    fn velocity_changes(&self, gamma: &[f64], out: &[f64], work: &mut CcpWork) {
        assert_eq!(gamma.len(), self.n_rows, "gamma has the wrong length");
        assert_eq!(out.len(), self.n_rows, "out has the wrong length");
        work.resize(self);
        let mf = self.mf.active();
        self.minv_d_blocks(gamma, &mut work.v, mf);
        if mf {
            self.mf.gather(gamma, &mut work.w);
        }
    }

    /// `out = N g + shift` (`shift` = `r` or none): the explicit rows by `D'(M^-1 D g)`, the
    /// matrix-free triplets ([`super::ContactFrame`]) from their frames. Every output is a
    /// fixed-order sum, whatever the thread count.
    fn product(&self, gamma: &[f64], out: &mut [f64], work: &mut CcpWork, shift: Option<&[f64]>) {
        self.velocity_changes(gamma, out, work);
        self.rows_from(gamma, &work.v, &work.w, out, shift);
    }

    /// The first half of a product, for solvers that change the velocity between the two
    /// halves ([`add_row_velocity`](Self::add_row_velocity)): `work.v = M^-1 D' g` for the
    /// explicit rows' blocks and `work.w` for the matrix-free spheres (m/s and rad/s per unit
    /// impulse). [`rows_from_velocity`](Self::rows_from_velocity) then gives `N g`.
    ///
    /// # Panics
    /// If `gamma` does not have one entry per row.
    pub fn velocity_changes_of(&self, gamma: &[f64], work: &mut CcpWork) {
        assert_eq!(gamma.len(), self.n_rows, "gamma has the wrong length");
        work.resize(self);
        let mf = self.mf.active();
        self.minv_d_blocks(gamma, &mut work.v, mf);
        if mf {
            self.mf.gather(gamma, &mut work.w);
        }
    }

    /// `work.v += s M^-1 D_i'`: the velocity change of an impulse `s` on row `i`, added to
    /// the first half of a product ([`velocity_changes_of`](Self::velocity_changes_of)), so
    /// that a solver can extend `g` by a few rows (a Schur solver's joint impulses) without a
    /// second full pass over the Jacobian. A row that touches a matrix-free sphere is not
    /// allowed (such a sphere's velocity lives in `work.w`, and only friction triplets with a
    /// frame touch it).
    ///
    /// # Panics
    /// If `i` is not a row, or (debug builds) if row `i` touches a matrix-free sphere.
    pub fn add_row_velocity(&self, i: usize, s: f64, work: &mut CcpWork) {
        debug_assert!(
            (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize).all(|e| !self
                .mf
                .skip_block
                .get(self.ent_block[e] as usize)
                .copied()
                .unwrap_or(false)),
            "row {i} touches a matrix-free sphere"
        );
        self.row_add_minv(i, s, &mut work.v);
    }

    /// The second half of a product: `out = D' (work's velocities) + E g (+ shift)`, i.e.
    /// `N g (+ shift)` if `work` holds [`velocity_changes_of`](Self::velocity_changes_of)`(g)`
    /// (plus any [`add_row_velocity`](Self::add_row_velocity) of the same `g`'s rows), with
    /// the same operations (so the same bits) as [`apply_n`](Self::apply_n) and
    /// [`gradient`](Self::gradient).
    ///
    /// # Panics
    /// If a length is wrong.
    pub fn rows_from_velocity(
        &self,
        gamma: &[f64],
        work: &CcpWork,
        out: &mut [f64],
        shift: Option<&[f64]>,
    ) {
        self.check_rows_from_velocity(gamma, work, out);
        self.rows_from(gamma, &work.v, &work.w, out, shift);
    }

    /// [`rows_from_velocity`](Self::rows_from_velocity) on every row but the bilateral
    /// ones, whose entries of `out` are left as they are: for a solver that knows those rows
    /// of `N g` without the products (a Schur solver's completed step makes them minus the
    /// joint residual it started from), about a third of a vehicle's rows. The other rows get
    /// the same bits as from [`rows_from_velocity`](Self::rows_from_velocity).
    ///
    /// # Panics
    /// If a length is wrong.
    pub fn rows_from_velocity_except_bilateral(
        &self,
        gamma: &[f64],
        work: &CcpWork,
        out: &mut [f64],
        shift: Option<&[f64]>,
    ) {
        self.check_rows_from_velocity(gamma, work, out);
        let skip = self.sections.bilateral.clone();
        self.rows_from_skipping(gamma, &work.v, &work.w, out, shift, skip);
    }

    /// The lengths the `rows_from_velocity` variants need (panics naming the wrong one).
    fn check_rows_from_velocity(&self, gamma: &[f64], work: &CcpWork, out: &[f64]) {
        assert_eq!(gamma.len(), self.n_rows, "gamma has the wrong length");
        assert_eq!(out.len(), self.n_rows, "out has the wrong length");
        assert_eq!(
            work.v.len(),
            self.ndof(),
            "work is not sized for this problem"
        );
    }

    /// `out = D'(v, w) + E g + shift`: the row half of [`product`](Self::product).
    fn rows_from(
        &self,
        gamma: &[f64],
        v: &[f64],
        w: &[f64],
        out: &mut [f64],
        shift: Option<&[f64]>,
    ) {
        self.rows_from_skipping(gamma, v, w, out, shift, 0..0);
    }

    /// [`rows_from`](Self::rows_from) leaving the rows `skip` (outside the friction
    /// section) of `out` untouched.
    fn rows_from_skipping(
        &self,
        gamma: &[f64],
        v: &[f64],
        w: &[f64],
        out: &mut [f64],
        shift: Option<&[f64]>,
        skip: std::ops::Range<usize>,
    ) {
        let eps = &self.eps;
        // `x + r_i`, or `x` itself (not `x + 0`, which would turn -0 into +0).
        let sh = |x: f64, i: usize| match shift {
            Some(r) => x + r[i],
            None => x,
        };
        let row = |i: usize| sh(self.row_dot(i, v) + eps[i] * gamma[i], i);
        let par = self.n_rows >= PAR_MIN_ROWS;
        let fr = self.sections.friction.clone();
        let (head, rest) = out.split_at_mut(fr.start);
        let (mid, tail) = rest.split_at_mut(fr.len());
        let rows = |o: &mut [f64], start: usize| {
            let f = |(i, o): (usize, &mut f64)| {
                if !skip.contains(&(start + i)) {
                    *o = row(start + i);
                }
            };
            if par {
                o.par_iter_mut().enumerate().for_each(f);
            } else {
                o.iter_mut().enumerate().for_each(f);
            }
        };
        rows(head, 0);
        rows(tail, fr.end);
        let task = |(t, o): (usize, &mut [f64])| {
            self.triplets_into(fr.start + 3 * TRIPLET_TASK * t, gamma, v, w, shift, o);
        };
        if par {
            mid.par_chunks_mut(3 * TRIPLET_TASK)
                .enumerate()
                .for_each(task);
        } else {
            mid.chunks_mut(3 * TRIPLET_TASK).enumerate().for_each(task);
        }
    }

    /// The three rows of `N g + shift` of the friction triplet whose normal row is `i`, into
    /// `o`, from the explicit rows' `v = M^-1 D g` and the spheres' `w` (matrix-free).
    #[inline]
    fn triplet_rows(
        &self,
        i: usize,
        gamma: &[f64],
        v: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        o: &mut [f64],
    ) {
        let eps = &self.eps;
        // `x + r_i`, or `x` itself (not `x + 0`, which would turn -0 into +0).
        let sh = |x: f64, i: usize| match shift {
            Some(r) => x + r[i],
            None => x,
        };
        let k = (i - self.sections.friction.start) / 3;
        match self.mf.of_triplet.get(k) {
            Some(&c) if c != NONE => {
                let d = self.mf.triplet(c as usize, w);
                for j in 0..3 {
                    o[j] = sh(d[j] + eps[i + j] * gamma[i + j], i + j);
                }
            }
            _ => {
                let d = self
                    .triplet_dot(i, v)
                    .unwrap_or_else(|| std::array::from_fn(|j| self.row_dot(i + j, v)));
                for j in 0..3 {
                    o[j] = sh(d[j] + eps[i + j] * gamma[i + j], i + j);
                }
            }
        }
    }

    /// `D_i' v` for the three rows `i, i+1, i+2` of a friction triplet whose rows touch the
    /// same one or two rigid bodies (6 dof each) in the same order, the usual case (a body
    /// on fixed ground touches one): each body's velocity is read once for the three rows.
    /// The same sums in the same order as [`row_dot`](Self::row_dot), so the same bits;
    /// `None` for any other layout.
    #[inline]
    fn triplet_dot(&self, i: usize, v: &[f64]) -> Option<[f64; 3]> {
        let p = self.row_ptr.get(i..i + 4)?;
        let e0 = p[0] as usize;
        let n = p[1] as usize - e0;
        if !(n == 1 || n == 2) || p[2] as usize != e0 + 2 * n || p[3] as usize != e0 + 3 * n {
            return None;
        }
        let off = self.ent_off.get(e0..e0 + 3 * n)?;
        let cp = self.ent_coef.get(e0..e0 + 3)?;
        let c0 = cp[0] as usize;
        // The same blocks in the same order in all three rows (an offset names its block),
        // each of 6 dof: then the coefficients are 18 n consecutive values.
        let same = if n == 1 {
            off[1] == off[0] && off[2] == off[0]
        } else {
            off[2] == off[0] && off[4] == off[0] && off[3] == off[1] && off[5] == off[1]
        };
        if !same || cp[1] as usize != c0 + 6 || (n == 2 && cp[2] as usize != c0 + 12) {
            return None;
        }
        let va: &[f64; 6] = v
            .get(off[0] as usize..off[0] as usize + 6)?
            .try_into()
            .ok()?;
        let c = self.coefs().get(c0..c0 + 18 * n)?;
        if n == 1 {
            return Some(std::array::from_fn(|j| {
                let c: &[f64; 6] = c[6 * j..6 * j + 6].try_into().expect("6");
                let mut s = 0.0;
                for k in 0..6 {
                    s += c[k] * va[k];
                }
                s
            }));
        }
        let ob = off[1] as usize;
        let vb: &[f64; 6] = v.get(ob..ob + 6)?.try_into().ok()?;
        let c: &[f64; 36] = c.try_into().ok()?;
        Some(std::array::from_fn(|j| {
            let mut s = 0.0;
            for k in 0..6 {
                s += c[12 * j + k] * va[k];
            }
            for k in 0..6 {
                s += c[12 * j + 6 + k] * vb[k];
            }
            s
        }))
    }

    /// The rows `start..start + o.len()` (whole friction triplets) of `N g + r` into `o`
    /// ([`triplets_into`](Self::triplets_into) with the shift `r`).
    fn unit_rows(&self, start: usize, gamma: &[f64], v: &[f64], w: &[f64], o: &mut [f64]) {
        self.triplets_into(start, gamma, v, w, Some(&self.r), o);
    }

    /// The rows `start..start + o.len()` (whole friction triplets) of `N g + shift` into
    /// `o`: [`triplet_rows`](Self::triplet_rows) for each triplet, with the runs of
    /// consecutive matrix-free contacts computed together (SIMD over contacts, the same
    /// operations, so the same bits).
    fn triplets_into(
        &self,
        start: usize,
        gamma: &[f64],
        v: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        o: &mut [f64],
    ) {
        let nt = o.len() / 3;
        let k0 = (start - self.sections.friction.start) / 3;
        let Some(of) = self.mf.of_triplet.get(k0..k0 + nt) else {
            // No matrix-free triplets in this problem.
            for (k, oc) in o.chunks_mut(3).enumerate() {
                self.triplet_rows(start + 3 * k, gamma, v, w, shift, oc);
            }
            return;
        };
        let end = start + o.len();
        let rows = RowData {
            eps: &self.eps[start..end],
            g: &gamma[start..end],
            shift: shift.map(|r| &r[start..end]),
            out: o,
        };
        self.mf.triplets_task(w, of, rows, |k, oc| {
            self.triplet_rows(start + 3 * k, gamma, v, w, shift, oc);
        });
    }

    /// Is every row part of a friction triplet (no other section)? Such problems (granular
    /// material, spheres in a box) can use [`gradient_by_units`](Self::gradient_by_units).
    pub fn is_friction_only(&self) -> bool {
        self.sections.friction == (0..self.n_rows)
    }

    /// `out = N g + r` ([`gradient`](Self::gradient), the same bits) for a problem with
    /// [`is_friction_only`](Self::is_friction_only), computed in units of [`UNIT_ROWS`]
    /// rows; right after a unit is computed (while its rows are in cache) `then(rows, out)`
    /// is called with its row range and its part of `out`, and the values it returns are
    /// stored in `results` in unit order. Solvers fuse their reductions over the new
    /// gradient into this pass; since a unit is exactly three chunks of
    /// [`reduce::CHUNK`] rows and one chunk of `CHUNK` triplets, they can keep the order
    /// of [`sum_by`] and so its bits. `results` keeps its allocation.
    ///
    /// A problem with other sections gets the plain [`gradient`](Self::gradient) and then
    /// `then` over the same units of rows (correct, without the fusion).
    ///
    /// # Panics
    /// If a length is wrong.
    pub fn gradient_by_units<T: Send>(
        &self,
        gamma: &[f64],
        out: &mut [f64],
        work: &mut CcpWork,
        results: &mut Vec<T>,
        then: impl Fn(std::ops::Range<usize>, &[f64]) -> T + Sync + Send,
    ) {
        // Friction-only: each unit's rows are computed here; otherwise all rows first.
        let fused = self.is_friction_only();
        if fused {
            self.velocity_changes(gamma, out, work);
        } else {
            self.gradient(gamma, out, work);
        }
        let (v, w) = (&work.v, &work.w);
        let unit = |(u, o): (usize, &mut [f64])| {
            let start = u * UNIT_ROWS;
            if fused {
                self.unit_rows(start, gamma, v, w, o);
            }
            then(start..start + o.len(), o)
        };
        results.clear();
        if self.n_rows >= PAR_MIN_ROWS {
            (out.par_chunks_mut(UNIT_ROWS).enumerate())
                .map(unit)
                .collect_into_vec(results);
        } else {
            results.extend(out.chunks_mut(UNIT_ROWS).enumerate().map(unit));
        }
    }

    /// `out = N g = D'(M^-1 D g) + E g`. `work` must come from [`CcpWork::for_problem`].
    ///
    /// Cost: one pass over each copy of the Jacobian (`2 nnz(D)` multiply-adds) plus the
    /// indices, and for the matrix-free triplets ([`super::ContactFrame`]) two passes over
    /// their frames; this is the unit of cost of every iterative solver
    /// ("`apply_n`-equivalents").
    pub fn apply_n(&self, gamma: &[f64], out: &mut [f64], work: &mut CcpWork) {
        self.product(gamma, out, work, None);
    }

    /// Number of friction triplets whose share of `N g` is computed matrix-free from their
    /// [`super::ContactFrame`] (0 if none were given or none qualified).
    pub fn n_matrix_free(&self) -> usize {
        self.mf.n_mf
    }

    /// True if every block with rows is a matrix-free sphere's (only matrix-free triplets
    /// touch it): then [`minv_d_explicit`](Self::minv_d_explicit) is zero for any `g`.
    pub fn explicit_free(&self) -> bool {
        self.mf.explicit_free
    }

    /// The bytes one [`apply_n`](Self::apply_n) must move at least: every stored array it
    /// reads once and every vector read or written once (gathers of `g` and `v` counted
    /// once, as if cached). Explicit rows: block pass `tr_ptr`, `tr_cptr` (8 B per block),
    /// `tr_row` (4 B per entry), `M^-1 D` (8 B per coefficient), `g` (8 B per row), `v`
    /// written (8 B per dof); row pass `row_ptr` (4 B per row), entry offsets (8 B per
    /// entry), `D` (8 B per coefficient), `v` read (8 B per dof), `eps`, `g` read and `N g`
    /// written (24 B per row). Matrix-free triplets: per sphere its pointer and inverse mass
    /// (20 B) and its 6 velocity changes written and read (96 B); per triplet side the
    /// sphere-ordered normal and arm (48 B) and row (4 B), per triplet `g` (24 B) in the
    /// sphere pass, and in the row pass its row, spheres and frame (84 B), `eps`, `g` and
    /// `N g` (72 B). Divided
    /// by the measured time it gives the achieved bandwidth.
    pub fn apply_n_bytes(&self) -> usize {
        let mf = &self.mf;
        // Explicit rows and entries only (the matrix-free triplets' entries are not read).
        let (mut m, mut ne, mut nc) = (self.n_rows, self.n_entries(), self.n_coefs());
        let mut nd = self.ndof();
        let mf_rows = (mf.of_triplet.iter())
            .filter(|&&c| c != NONE)
            .map(|&c| mf.c_row[c as usize]);
        for i in mf_rows {
            for r in i as usize..i as usize + 3 {
                m -= 1;
                let (e0, e1) = (self.row_ptr[r] as usize, self.row_ptr[r + 1] as usize);
                ne -= e1 - e0;
                nc -= self.ent_coef[e1] as usize - self.ent_coef[e0] as usize;
            }
        }
        for (b, &skip) in mf.skip_block.iter().enumerate() {
            if skip {
                nd -= self.vars.block_ndof(super::BlockId(b as u32));
            }
        }
        let nb = self.vars.len();
        let explicit = (8 * nb + 4 * ne + 8 * nc + 8 * m + 8 * nd)
            + (4 * m + 8 * ne + 8 * nc + 8 * nd + 24 * m);
        let sides = mf.s_row.len();
        let spheres = mf.n_bodies() * (20 + 96);
        let contacts = mf.c_row.len() * 24 + mf.n_mf * (84 + 80) + sides * (56 + 4);
        explicit + spheres + contacts
    }

    /// `out = N g + r`, the gradient of the objective (= the constraint velocities).
    pub fn gradient(&self, gamma: &[f64], out: &mut [f64], work: &mut CcpWork) {
        self.product(gamma, out, work, Some(&self.r));
    }

    /// The objective `f(g) = 1/2 g'N g + r'g`, given the gradient `grad = N g + r`.
    pub fn objective_from_gradient(&self, gamma: &[f64], grad: &[f64], work: &mut CcpWork) -> f64 {
        let r = &self.r;
        sum_by(self.n_rows, &mut work.partials, |i| {
            0.5 * gamma[i] * (grad[i] + r[i])
        })
    }

    /// The objective `f(g)`, computing the gradient into `grad`.
    pub fn objective(&self, gamma: &[f64], grad: &mut [f64], work: &mut CcpWork) -> f64 {
        self.gradient(gamma, grad, work);
        self.objective_from_gradient(gamma, grad, work)
    }

    /// Project `g` onto `Y` in place: bilateral rows unchanged, box rows clamped, unilateral
    /// rows to `>= 0`, friction triplets onto their Coulomb cones, rolling contacts onto
    /// their cones ([`project_rolling_cone`], [`project_rolling_per_body_cone`]).
    pub fn project(&self, gamma: &mut [f64]) {
        let s = &self.sections;
        let (lo, hi) = (&self.lo, &self.hi);
        for (k, g) in gamma[s.boxed.clone()].iter_mut().enumerate() {
            *g = project_box(*g, lo[k], hi[k]);
        }
        let par = self.n_rows >= PAR_MIN_ROWS;
        let uni = &mut gamma[s.unilateral.clone()];
        if par {
            uni.par_iter_mut().for_each(|g| *g = project_unilateral(*g));
        } else {
            uni.iter_mut().for_each(|g| *g = project_unilateral(*g));
        }
        let fr = &mut gamma[s.friction.clone()];
        if par {
            (fr.par_chunks_mut(3 * TERM_TASK))
                .zip(self.mu.par_chunks(TERM_TASK))
                .for_each(|(g, mu)| project_friction_cones(mu, g));
        } else {
            project_friction_cones(&self.mu, fr);
        }
        let ro = &mut gamma[s.rolling.clone()];
        if par {
            ro.par_chunks_mut(6)
                .zip(self.mu_rolling.par_iter())
                .for_each(|(g, &mu)| project_rolling_cone(mu, g));
        } else {
            ro.chunks_mut(6)
                .zip(&self.mu_rolling)
                .for_each(|(g, &mu)| project_rolling_cone(mu, g));
        }
        let pb = &mut gamma[s.rolling_per_body.clone()];
        if par {
            pb.par_chunks_mut(PER_BODY_ROWS)
                .zip(self.mu_per_body.par_iter())
                .for_each(|(g, &mu)| project_rolling_per_body_cone(mu, g));
        } else {
            pb.chunks_mut(PER_BODY_ROWS)
                .zip(&self.mu_per_body)
                .for_each(|(g, &mu)| project_rolling_per_body_cone(mu, g));
        }
    }

    /// The residual of `g`, given its gradient `grad = N g + r`: the root mean square over rows
    /// of the scaled projected-gradient step
    ///
    /// ```text
    /// rho_i = (g_i - P(g - S grad)_i) / S_i,    S = diag(N)^-1 (cone-averaged)
    /// ```
    ///
    /// It is zero exactly at a solution of the CCP, has units of velocity (m/s; the violation
    /// of the complementarity conditions), and being a mean over rows it compares across
    /// problem sizes. Bilateral rows contribute their gradient; rows with a zero diagonal
    /// contribute the part of their gradient that violates the conditions. One pass by
    /// section, each cone projected once.
    pub fn residual(&self, gamma: &[f64], grad: &[f64], work: &mut CcpWork) -> f64 {
        if self.n_rows == 0 {
            return 0.0;
        }
        let s = &self.sections;
        let sc = &self.scale;
        let mut total = sum_by(s.bilateral.len(), &mut work.partials, |i| {
            let i = s.bilateral.start + i;
            grad[i] * grad[i]
        });
        let (lo, hi) = (&self.lo, &self.hi);
        total += sum_by(s.boxed.len(), &mut work.partials, |k| {
            let i = s.boxed.start + k;
            let rho = if sc[i] > 0.0 {
                (gamma[i] - project_box(gamma[i] - sc[i] * grad[i], lo[k], hi[k])) / sc[i]
            } else {
                0.0
            };
            rho * rho
        });
        total += sum_by(s.unilateral.len(), &mut work.partials, |k| {
            let i = s.unilateral.start + k;
            let rho = if sc[i] > 0.0 {
                (gamma[i] - project_unilateral(gamma[i] - sc[i] * grad[i])) / sc[i]
            } else {
                grad[i].min(0.0)
            };
            rho * rho
        });
        // The friction triplets' terms first (their projections in lanes), then summed in
        // `sum_by`'s order.
        let nf = s.friction.len() / 3;
        work.terms.resize(nf, 0.0);
        let fr = s.friction.clone();
        let (g, gr, scf) = (&gamma[fr.clone()], &grad[fr.clone()], &sc[fr]);
        if self.n_rows >= PAR_MIN_ROWS {
            (work.terms.par_chunks_mut(TERM_TASK).enumerate()).for_each(|(b, t)| {
                let rows = 3 * b * TERM_TASK..3 * (b * TERM_TASK + t.len());
                let k = b * TERM_TASK..b * TERM_TASK + t.len();
                friction_residual_terms(
                    &g[rows.clone()],
                    &gr[rows.clone()],
                    &scf[rows],
                    &self.mu[k],
                    t,
                );
            });
        } else {
            friction_residual_terms(g, gr, scf, &self.mu, &mut work.terms);
        }
        let terms = &work.terms;
        total += sum_by(nf, &mut work.partials, |c| terms[c]);
        total += sum_by(s.rolling.len() / 6, &mut work.partials, |c| {
            let t = s.rolling.start + 6 * c;
            let h = sc[t];
            if h <= 0.0 {
                return 0.0;
            }
            let mut z = [0.0; 6];
            for j in 0..6 {
                z[j] = gamma[t + j] - h * grad[t + j];
            }
            project_rolling_cone(self.mu_rolling[c], &mut z);
            (0..6).map(|j| ((gamma[t + j] - z[j]) / h).powi(2)).sum()
        });
        let n = PER_BODY_ROWS;
        total += sum_by(s.rolling_per_body.len() / n, &mut work.partials, |c| {
            let t = s.rolling_per_body.start + n * c;
            let h = sc[t];
            if h <= 0.0 {
                return 0.0;
            }
            let mut z = [0.0; PER_BODY_ROWS];
            for j in 0..n {
                z[j] = gamma[t + j] - h * grad[t + j];
            }
            project_rolling_per_body_cone(self.mu_per_body[c], &mut z);
            (0..n).map(|j| ((gamma[t + j] - z[j]) / h).powi(2)).sum()
        });
        (total / self.n_rows as f64).sqrt()
    }

    /// The new velocities `v+ = M^-1 (k + D g) = M^-1 k + M^-1 D g` (length `ndof`).
    pub fn velocities(&self, gamma: &[f64], v: &mut [f64]) {
        self.minv_d(gamma, v);
        for (x, f) in v.iter_mut().zip(&self.v_free) {
            *x += f;
        }
    }

    /// Dot product in the deterministic order of [`reduce`](super::reduce).
    pub fn dot(&self, a: &[f64], b: &[f64], work: &mut CcpWork) -> f64 {
        reduce::dot(a, b, &mut work.partials)
    }
}
