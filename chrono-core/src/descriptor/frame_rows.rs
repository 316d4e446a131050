//! Friction triplets given as their geometry alone ([`ConstraintRows::push_friction_frame`],
//! the crate's contacts between rigid bodies): the assembly gives each one its entries
//! (one per side with variables and row, 6 coefficients each) and builds the
//! coefficients `[s d; (R' r) x (R' s d)]` (`s = -1` on side A, `+1` on side B, `R` the
//! block's rotation) from the frame only where they are read.
//!
//! When every row of a problem is such a triplet between spheres applied matrix-free (a
//! granular bed), nothing of the step reads them: `diag(N)` and `r = b + D' M^-1 k` come
//! from the geometry (the world-frame velocities of the spheres), the new velocities from
//! the spheres' world-frame velocity changes rotated into the body frames, and the explicit
//! coefficients and `M^-1 D` are built on the first row-level access ([`LazyCoefs`]) — the
//! same values as an eager assembly of the same triplets. Otherwise they are built at
//! assembly. Every value is computed on its own (the same bits for any thread count).

use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;

use super::frames::NONE;
use super::problem::CcpProblem;
use super::rows::{ConstraintRows, ContactFrame, FrameKind, GroupRows, RowGroup};
use super::variables::{BlockId, Variables};
use crate::body::arm_jacobians;
use crate::error::{ChronoError, Result};
use crate::parallel::split_parts;

/// Friction triplets per task of the parallel passes.
const TASK: usize = 1024;

/// Below this many triplets the passes run on the calling thread.
const PAR_MIN_TRIPLETS: usize = 2048;

/// The explicit coefficients of a problem whose rows are all frame-only triplets, built
/// on first use: `D` and `M^-1 D`, laid out as the entries say (`ent_coef`).
#[derive(Debug, Clone, Default)]
pub(super) struct LazyCoefs {
    pub coefs: Vec<f64>,
    pub minv: Vec<f64>,
}

/// The rows `n, u, w` of one side of a frame-only triplet on its rigid body's 6 dof:
/// `[s d; (R' r) x (R' s d)]` ([`arm_jacobians`], as
/// [`RigidBody::point_jacobians`](crate::RigidBody::point_jacobians): the same bits as rows
/// built from the body).
#[inline]
fn side_coefs(rot: &UnitQuaternion<f64>, arm: &[f64; 3], n: &[f64; 3], sign: f64) -> [[f64; 6]; 3] {
    let n = Vector3::from(*n);
    let (u, w) = crate::math::tangent_frame(&n);
    arm_jacobians(rot, &Vector3::from(*arm), &[n, u, w].map(|d| d * sign))
}

/// The sides of `frame` with variables, in order (A, then B), with their signs.
fn sides(frame: &ContactFrame) -> impl Iterator<Item = (usize, BlockId, f64)> + '_ {
    (frame.blocks.iter().enumerate())
        .filter_map(|(s, b)| b.map(|b| (s, b, if s == 0 { -1.0 } else { 1.0 })))
}

/// Is `g` (the friction group) holding frame-only triplets?
pub(super) fn has_frame_only(g: &GroupRows) -> bool {
    g.frame_kind.contains(&FrameKind::Only)
}

/// Is every row of `rows` a frame-only triplet (and is there one)?
pub(super) fn all_frame_only(rows: &ConstraintRows) -> bool {
    let fr = RowGroup::Friction as usize;
    let g = &rows.groups[fr];
    let others_empty = (rows.groups.iter().enumerate()).all(|(i, g)| i == fr || g.n_rows() == 0);
    others_empty
        && !g.mu.is_empty()
        && g.frame_kind.len() == g.mu.len()
        && g.frame_kind.iter().all(|&k| k == FrameKind::Only)
}

/// Does `frame` pass [`CcpProblem::check_frame_only`]? (no error built; `offsets` from
/// [`oriented_offsets`])
fn frame_only_ok(offsets: &[u32], frame: &ContactFrame) -> bool {
    let block_ok = |b: &BlockId| offsets.get(b.0 as usize).is_some_and(|&o| o != NONE);
    frame.blocks.iter().flatten().all(block_ok)
        && frame
            .normal
            .iter()
            .chain(frame.arms.iter().flatten())
            .all(|x| x.is_finite())
}

/// Has block `blk` a finite rotation (the rows of a frame-only triplet are built from it)?
fn oriented(vars: &Variables, blk: BlockId) -> bool {
    vars.rotation(blk)
        .is_some_and(|q| q.coords.iter().all(|x| x.is_finite()))
}

/// Per block of `vars`: its first dof if it is a rigid body's (6 dof) with a rotation, else
/// `NONE` (a compact table: the frames' checks and entries read it, not the blocks).
fn oriented_offsets(vars: &Variables, out: &mut Vec<u32>) {
    out.clear();
    let one = |b: usize| {
        let blk = BlockId(b as u32);
        let ok = vars.block_ndof(blk) == 6 && oriented(vars, blk);
        if ok { vars.offset(blk) as u32 } else { NONE }
    };
    if vars.len() >= PAR_MIN_TRIPLETS {
        out.par_extend((0..vars.len()).into_par_iter().map(one));
    } else {
        out.extend((0..vars.len()).map(one));
    }
}

impl CcpProblem {
    /// The coefficients of `D` by entry (`ent_coef`): built on first use in a deferred
    /// problem ([`super::frame_rows`]).
    #[inline]
    pub(super) fn coefs(&self) -> &[f64] {
        if self.deferred {
            &self.lazy_coefs().coefs
        } else {
            &self.coefs
        }
    }

    /// The coefficients of `M^-1 D`, laid out as [`coefs`](Self::coefs).
    #[inline]
    pub(super) fn minv(&self) -> &[f64] {
        if self.deferred {
            &self.lazy_coefs().minv
        } else {
            &self.minv
        }
    }

    /// A deferred problem's coefficients, built on the first call.
    fn lazy_coefs(&self) -> &LazyCoefs {
        self.lazy.get_or_init(|| self.build_lazy())
    }

    /// Whether this problem's explicit coefficients are deferred (every row a frame-only
    /// triplet applied matrix-free, see `ConstraintRows::push_friction_frame`), and if so
    /// whether a row-level access has built them: for tests and benches that check a path
    /// does not need them.
    pub fn coefficients_deferred(&self) -> (bool, bool) {
        (self.deferred, self.lazy.get().is_some())
    }

    /// The check of frame-only triplet `k` of `g` against `vars`: each block exists, has 6
    /// dof and a rotation; the normal and the arms are finite. The error names the row.
    fn check_frame_only(vars: &Variables, k: usize, frame: &ContactFrame) -> Result<()> {
        let row = format!("rows.friction[{}].frame", 3 * k);
        for (s, blk, _) in sides(frame) {
            let b = blk.0 as usize;
            if b >= vars.len() {
                return Err(ChronoError::UnknownHandle {
                    kind: "variable block",
                    index: b,
                    field: format!("{row}.blocks[{s}]"),
                });
            }
            if vars.block_ndof(blk) != 6 || !oriented(vars, blk) {
                return Err(ChronoError::invalid(
                    format!("{row}.blocks[{s}]"),
                    b,
                    "a frame-only triplet needs a rigid body's block with its rotation, \
                     finite (Variables::add_oriented)",
                ));
            }
        }
        if let Some(x) = frame.normal.iter().find(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("{row}.normal"),
                x,
                "must be finite",
            ));
        }
        if let Some(x) = frame.arms.iter().flatten().find(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("{row}.arms"),
                x,
                "must be finite",
            ));
        }
        Ok(())
    }

    /// Append the friction group `g` (checked for its explicit rows), which holds
    /// frame-only triplets: their frames checked, then the entries of every row (the
    /// explicit rows' copied, the frame-only triplets' one per side with variables and
    /// row) and `b`, `eps`. The coefficients of frame-only triplets are built now if
    /// `eager`, else left to [`build_lazy`](Self::build_lazy) (`coefs` untouched: every
    /// row is then a frame-only triplet). Returns the coefficient count the entries span.
    pub(super) fn load_frame_group(
        &mut self,
        vars: &Variables,
        g: &GroupRows,
        eager: bool,
    ) -> Result<usize> {
        let nt = g.mu.len();
        // Per triplet: its frame if frame-only.
        let mut only = std::mem::take(&mut self.only_of);
        only.clear();
        only.resize(nt, NONE);
        for (f, (&(k, _), &kind)) in g.frames.iter().zip(&g.frame_kind).enumerate() {
            if kind == FrameKind::Only {
                only[k as usize] = f as u32;
            }
        }
        let mut offsets = std::mem::take(&mut self.block_offsets);
        oriented_offsets(vars, &mut offsets);
        let bad = (0..g.frames.len())
            .into_par_iter()
            .with_min_len(TASK)
            .find_first(|&f| {
                g.frame_kind[f] == FrameKind::Only && !frame_only_ok(&offsets, &g.frames[f].1)
            });
        if let Some(f) = bad {
            (self.only_of, self.block_offsets) = (only, offsets);
            let (k, frame) = &g.frames[f];
            return Self::check_frame_only(vars, *k as usize, frame).map(|_| 0);
        }
        let n_ent = g.row_ptr.get(g.n_rows()).map_or(0, |&p| p as usize);
        let n_coef = if n_ent == 0 { 0 } else { g.coefs.len() };
        let coef_at = |e: usize| g.ent_coef.get(e).map_or(n_coef, |&c| c as usize);
        let nb = |f: u32| sides(&g.frames[f as usize].1).count();
        // Entries and coefficients of triplet k.
        let size = |k: usize| match only[k] {
            NONE => {
                let (e0, e1) = (g.row_ptr[3 * k] as usize, g.row_ptr[3 * k + 3] as usize);
                (e1 - e0, coef_at(e1) - coef_at(e0))
            }
            f => (3 * nb(f), 18 * nb(f)),
        };
        let par = nt >= PAR_MIN_TRIPLETS;
        let n_tasks = nt.div_ceil(TASK);
        let task_size = |t: usize| {
            (t * TASK..((t + 1) * TASK).min(nt))
                .map(size)
                .fold((0, 0), |(e, c), (de, dc)| (e + de, c + dc))
        };
        let sizes: Vec<(usize, usize)> = if par {
            (0..n_tasks).into_par_iter().map(task_size).collect()
        } else {
            (0..n_tasks).map(task_size).collect()
        };
        let (ne, nc) = sizes
            .iter()
            .fold((0, 0), |(e, c), &(de, dc)| (e + de, c + dc));
        // Not `eager`: every row is a frame-only triplet, this group is the only one, and
        // the entry arrays kept their old length (`load_rows`): resized, not zeroed, as
        // every value is written below.
        let r0 = self.b.len();
        let e0 = if eager { self.ent_block.len() } else { 0 };
        let c0 = if eager { self.coefs.len() } else { 0 };
        self.row_ptr.resize(r0 + 1 + 3 * nt, 0);
        self.row_ptr[r0] = e0 as u32;
        for v in [&mut self.ent_block, &mut self.ent_off, &mut self.ent_coef] {
            v.resize(e0 + ne, 0);
        }
        self.ent_span.resize(e0 + ne, [0, 0]);
        if eager {
            self.coefs.resize(c0 + nc, 0.0);
        }
        // Each task's slices of the outputs.
        let rows_of = |t: usize| 3 * ((t + 1) * TASK).min(nt) - 3 * t * TASK;
        let row_ptr = split_parts(&mut self.row_ptr[r0 + 1..], (0..n_tasks).map(rows_of));
        let ent_lens = || sizes.iter().map(|s| s.0);
        let (blocks, offs, coef_idx) = (
            split_parts(&mut self.ent_block[e0..], ent_lens()),
            split_parts(&mut self.ent_off[e0..], ent_lens()),
            split_parts(&mut self.ent_coef[e0..], ent_lens()),
        );
        let spans = split_parts(&mut self.ent_span[e0..], sizes.iter().map(|s| s.0));
        let mut coefs = if eager {
            split_parts(&mut self.coefs[c0..], sizes.iter().map(|s| s.1))
        } else {
            Vec::new()
        };
        let mut starts = Vec::with_capacity(n_tasks);
        let (mut e, mut c) = (e0, c0);
        for s in &sizes {
            starts.push((e, c));
            (e, c) = (e + s.0, c + s.1);
        }
        type Task<'a> = (
            usize,
            (usize, usize),
            &'a mut [u32],
            &'a mut [u32],
            &'a mut [u32],
            &'a mut [u32],
            &'a mut [[u32; 2]],
            Option<&'a mut [f64]>,
        );
        let mut coefs_it = coefs.drain(..);
        let tasks: Vec<Task> = (0..n_tasks)
            .zip(row_ptr)
            .zip(
                blocks
                    .into_iter()
                    .zip(offs)
                    .zip(coef_idx.into_iter().zip(spans)),
            )
            .map(|((t, rp), ((bl, of), (ci, sp)))| {
                let co = if eager { coefs_it.next() } else { None };
                (t, starts[t], rp, bl, of, ci, sp, co)
            })
            .collect();
        drop(coefs_it);
        let fill = |(t, (e_at, c_at), rp, bl, of, ci, sp, mut co): Task| {
            let (mut e, mut c) = (0usize, 0usize);
            for k in t * TASK..((t + 1) * TASK).min(nt) {
                let q = 3 * (k - t * TASK);
                match only[k] {
                    NONE => {
                        for r in 0..3 {
                            let i = 3 * k + r;
                            for ge in g.row_ptr[i] as usize..g.row_ptr[i + 1] as usize {
                                let (gc0, gc1) = (coef_at(ge), coef_at(ge + 1));
                                bl[e] = g.ent_block[ge];
                                of[e] = vars.offset(BlockId(g.ent_block[ge])) as u32;
                                ci[e] = (c_at + c) as u32;
                                sp[e] = super::assemble::nonzero_span(&g.coefs[gc0..gc1]);
                                if let Some(co) = co.as_deref_mut() {
                                    co[c..c + gc1 - gc0].copy_from_slice(&g.coefs[gc0..gc1]);
                                }
                                (e, c) = (e + 1, c + gc1 - gc0);
                            }
                            rp[q + r] = (e_at + e) as u32;
                        }
                    }
                    f => {
                        let frame = &g.frames[f as usize].1;
                        let mut rows = [[[0.0; 6]; 3]; 2];
                        if co.is_some() {
                            for (s, blk, sign) in sides(frame) {
                                let rot = vars.rotation(blk).expect("checked");
                                rows[s] = side_coefs(rot, &frame.arms[s], &frame.normal, sign);
                            }
                        }
                        for r in 0..3 {
                            for (s, blk, _) in sides(frame) {
                                bl[e] = blk.0;
                                of[e] = offsets[blk.0 as usize];
                                ci[e] = (c_at + c) as u32;
                                sp[e] = [0, 6];
                                if let Some(co) = co.as_deref_mut() {
                                    co[c..c + 6].copy_from_slice(&rows[s][r]);
                                }
                                (e, c) = (e + 1, c + 6);
                            }
                            rp[q + r] = (e_at + e) as u32;
                        }
                    }
                }
            }
        };
        if par {
            tasks.into_par_iter().for_each(fill);
        } else {
            tasks.into_iter().for_each(fill);
        }
        self.b.extend_from_slice(&g.b);
        self.eps.extend_from_slice(&g.eps);
        (self.only_of, self.block_offsets) = (only, offsets);
        Ok(c0 + nc)
    }

    /// `D` and `M^-1 D` of a deferred problem ([`fill_frame_coefs`](Self::fill_frame_coefs)
    /// from the frames the matrix-free storage keeps).
    pub(super) fn build_lazy(&self) -> LazyCoefs {
        let mut out = LazyCoefs::default();
        self.fill_frame_coefs(&self.mf.frames, &mut out.coefs, Some(&mut out.minv));
        out
    }

    /// `coefs = D` (and `minv = M^-1 D` if given) of a problem whose rows are all
    /// frame-only triplets, `frames` (the entries built, the coefficients not), from the
    /// frames and the blocks' rotations: the values of rows built from the bodies.
    pub(super) fn fill_frame_coefs(
        &self,
        frames: &[(u32, ContactFrame)],
        coefs: &mut Vec<f64>,
        mut minv: Option<&mut Vec<f64>>,
    ) {
        let n_coef = self.ent_coef.last().map_or(0, |&c| c as usize);
        let nt = frames.len();
        // Every value is written below.
        coefs.resize(n_coef, 0.0);
        if let Some(m) = minv.as_deref_mut() {
            m.resize(n_coef, 0.0);
        }
        let fs = self.sections.friction.start;
        // Each task's coefficients start at its first row's first entry.
        let coef_of_triplet = |k: usize| self.ent_coef[self.row_ptr[fs + 3 * k] as usize] as usize;
        let n_tasks = nt.div_ceil(TASK);
        let lens = || {
            (0..n_tasks)
                .map(|t| coef_of_triplet(((t + 1) * TASK).min(nt)) - coef_of_triplet(t * TASK))
        };
        let with_minv = minv.is_some();
        let co = split_parts(&mut coefs[..], lens());
        let mi: Vec<&mut [f64]> = match minv {
            Some(m) => split_parts(&mut m[..], lens()),
            None => (0..n_tasks).map(|_| &mut [][..]).collect(),
        };
        let fill = |(t, (co, mi)): (usize, (&mut [f64], &mut [f64]))| {
            let mut c = 0;
            for (_, frame) in &frames[t * TASK..((t + 1) * TASK).min(nt)] {
                let mut rows = [[[0.0; 6]; 3]; 2];
                for (s, blk, sign) in sides(frame) {
                    let rot = self.vars.rotation(blk).expect("checked at assembly");
                    rows[s] = side_coefs(rot, &frame.arms[s], &frame.normal, sign);
                }
                for r in 0..3 {
                    for (s, blk, _) in sides(frame) {
                        co[c..c + 6].copy_from_slice(&rows[s][r]);
                        if with_minv {
                            (self.vars.mass(blk)).apply_inverse(&rows[s][r], &mut mi[c..c + 6]);
                        }
                        c += 6;
                    }
                }
            }
        };
        if nt >= PAR_MIN_TRIPLETS {
            co.into_par_iter().zip(mi).enumerate().for_each(fill);
        } else {
            co.into_iter().zip(mi).enumerate().for_each(fill);
        }
    }

    /// `diag(N)` and `r = b + D' v_free` of a deferred problem (every row a frame-only
    /// triplet applied matrix-free) from the contacts' geometry: `diag = eps + ` the
    /// diagonal of the contact's block of `D M^-1 D'`
    /// ([`SphereContact::block_diagonal`](super::SphereContact::block_diagonal)), and `D' v_free` the
    /// relative velocity of the contact points along the frame, from the spheres'
    /// free velocities in the world frame (`R w_body`). Equal to the explicit rows' values
    /// to rounding.
    pub(super) fn deferred_diag_r(&mut self) {
        // The spheres' free velocities, world frame (6 per sphere).
        let mut vw = std::mem::take(&mut self.v_free_w);
        let ns = self.mf.n_bodies();
        vw.clear();
        vw.resize(6 * ns, 0.0);
        {
            let (vars, v_free, sphere_block) = (&self.vars, &self.v_free, &self.mf.sphere_block);
            let one = |(s, o): (usize, &mut [f64])| {
                let blk = BlockId(sphere_block[s]);
                let off = vars.offset(blk);
                let v = &v_free[off..off + 6];
                let w = vars.rotation(blk).expect("checked at assembly")
                    * Vector3::new(v[3], v[4], v[5]);
                o.copy_from_slice(&[v[0], v[1], v[2], w.x, w.y, w.z]);
            };
            if ns >= PAR_MIN_TRIPLETS {
                vw.par_chunks_mut(6).enumerate().for_each(one);
            } else {
                vw.chunks_mut(6).enumerate().for_each(one);
            }
        }
        let n = self.n_rows;
        let mut diag = std::mem::take(&mut self.diag);
        let mut r = std::mem::take(&mut self.r);
        diag.resize(n, 0.0);
        r.resize(n, 0.0);
        let fs = self.sections.friction.start;
        let this = &*self;
        let one = |(k, (d, rr)): (usize, (&mut [f64], &mut [f64]))| {
            let t = fs + 3 * k;
            let c = this.mf.of_triplet[k];
            // (deferred: every triplet is matrix-free)
            debug_assert_ne!(c, NONE, "triplet {k} is not matrix-free");
            let sc = this.mf_sphere_contact(c);
            let blk = sc.block_diagonal();
            let rel = sc.dots_in(&vw, 0);
            for j in 0..3 {
                d[j] = this.eps[t + j] + blk[j];
                rr[j] = this.b[t + j] + rel[j];
            }
        };
        let (df, rf) = (&mut diag[fs..], &mut r[fs..]);
        if n >= 3 * PAR_MIN_TRIPLETS {
            (df.par_chunks_mut(3).zip(rf.par_chunks_mut(3)))
                .with_min_len(TASK)
                .enumerate()
                .for_each(one);
        } else {
            df.chunks_mut(3)
                .zip(rf.chunks_mut(3))
                .enumerate()
                .for_each(one);
        }
        (self.diag, self.r, self.v_free_w) = (diag, r, vw);
    }

    /// `v = M^-1 D g` of a deferred problem: the spheres' world-frame velocity changes
    /// (the matrix-free gather), their angular part rotated into the body frame (`R' dw`);
    /// zero on every other block (they have no rows).
    pub(super) fn minv_d_deferred(&self, gamma: &[f64], v: &mut [f64]) {
        const BLOCKS: usize = 128;
        let mf = &self.mf;
        let task = |b0: usize, out: &mut [f64]| {
            let b1 = b0 + out.len() / 6;
            let (s0, s1) = (self.mf_spheres_before(b0), self.mf_spheres_before(b1));
            let mut buf = [0.0; 6 * BLOCKS];
            let w = &mut buf[..6 * (s1 - s0)];
            if s1 > s0 {
                mf.gather_task(gamma, s0, w);
            }
            for (i, o) in out.chunks_mut(6).enumerate() {
                let blk = b0 + i;
                match mf.block_sphere.get(blk) {
                    Some(&s) if s != NONE => {
                        let x = &w[6 * (s as usize - s0)..6 * (s as usize - s0) + 6];
                        let rot = self.vars.rotation(BlockId(blk as u32)).expect("checked");
                        let a = rot.inverse() * Vector3::new(x[3], x[4], x[5]);
                        o.copy_from_slice(&[x[0], x[1], x[2], a.x, a.y, a.z]);
                    }
                    _ => o.fill(0.0),
                }
            }
        };
        let par = self.ndof() >= 6 * PAR_MIN_TRIPLETS;
        for run in self.vars.runs() {
            let range = run.dof_offset..run.dof_offset + run.n_blocks * run.ndof;
            if run.ndof != 6 {
                // (no rows on these blocks)
                v[range].fill(0.0);
                continue;
            }
            let one = |(i, o): (usize, &mut [f64])| task(run.first_block + i * BLOCKS, o);
            if par {
                v[range]
                    .par_chunks_mut(6 * BLOCKS)
                    .enumerate()
                    .for_each(one);
            } else {
                v[range].chunks_mut(6 * BLOCKS).enumerate().for_each(one);
            }
        }
    }
}
