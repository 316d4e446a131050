//! The matrix-free share of `N g` for friction triplets between spheres
//! ([`ContactFrame`]): instead of 36 Jacobian coefficients (twice: `D` and `M^-1 D`) a
//! triplet stores its normal, two lever arms and its tangent frame's one division (10
//! numbers), and a sphere's `M^-1` is a scalar mass and a scalar inertia.
//!
//! With `F = n g_n + u g_u + w g_w` the triplet's impulse on B (and `-F` on A), the
//! velocity change of a sphere is `dv = F_sum / m` and `dw = (sum r x F) / J` (world frame:
//! for an isotropic inertia `R J^-1 R' = J^-1`, so the body rotation drops out of `N`), and
//! the triplet's rows of `N g` are `d . ((dv_B + dw_B x r_B) - (dv_A + dw_A x r_A))`.
//! Both passes are gathers in a fixed order (per body over its contacts in row order, per
//! triplet), so the result is bit-identical for any thread count.

use rayon::prelude::*;

use super::problem::CcpProblem;
use super::rows::{ConstraintRows, ContactFrame, FrameKind, RowGroup};
use super::variables::{BlockId, MassOperator};
use crate::math::Vector3;

/// No index.
pub(super) const NONE: u32 = u32::MAX;

/// Below this many spheres the gather runs on the calling thread.
const PAR_MIN_BODIES: usize = 1024;

/// Spheres per task of the sphere pass (one SIMD dispatch each).
const GATHER_TASK: usize = 128;

/// Relative tolerance of the check of the angular coefficients against the arms.
const ARM_CHECK_TOL: f64 = 1e-9;

/// The matrix-free triplets of a problem and their spheres.
#[derive(Debug, Clone, Default)]
pub(super) struct MatrixFree {
    /// The frames as given with the rows (triplet index, frame), to rebuild the rows.
    pub frames: Vec<(u32, ContactFrame)>,
    /// Per friction triplet: its contact if applied matrix-free, or [`NONE`].
    pub of_triplet: Vec<u32>,
    /// Contacts: the triplets with a checked frame (matrix-free or not: a pure sphere
    /// gathers from all of them). Per contact: the global index of its normal row.
    pub c_row: Vec<u32>,
    /// Per contact: the pure sphere of side A and of side B, or [`NONE`].
    pub c_body: Vec<[u32; 2]>,
    /// Per contact, by component (one array per quantity, so that SIMD lanes load them
    /// directly): the normal `n`, the arms `r_A`, `r_B` (world) and the frame's division
    /// ([`frame_recip`]).
    pub c_n: [Vec<f64>; 3],
    pub c_ra: [Vec<f64>; 3],
    pub c_rb: [Vec<f64>; 3],
    pub c_rc: Vec<f64>,
    /// Per sphere: `[1/m, 1/J]`.
    pub b_inv: Vec<[f64; 2]>,
    /// Per sphere: its contact sides `b_ptr[s]..b_ptr[s+1]` (in contact order) in the
    /// sphere-ordered copies below, so that the sphere pass streams them.
    pub b_ptr: Vec<u32>,
    /// Per contact side: `2 i + side` with `i` the normal row (side 0 = A, 1 = B).
    pub s_row: Vec<u32>,
    /// Per contact side, by component: the normal, this side's arm and the frame's
    /// division.
    pub s_n: [Vec<f64>; 3],
    pub s_r: [Vec<f64>; 3],
    pub s_rc: Vec<f64>,
    /// Per variable block: its sphere, or [`NONE`].
    pub block_sphere: Vec<u32>,
    /// Per sphere: its variable block.
    pub sphere_block: Vec<u32>,
    /// Per variable block: true if only matrix-free triplets touch it (its explicit
    /// velocity is not needed by `apply_n`).
    pub skip_block: Vec<bool>,
    /// True if no block needs its explicit velocity in `apply_n` (every block with rows
    /// is touched only by matrix-free triplets): the explicit gather is skipped.
    pub explicit_free: bool,
    /// Number of triplets applied matrix-free.
    pub n_mf: usize,
    /// Scratch of [`CcpProblem::fill_matrix_free`] (kept so that a step allocates
    /// nothing): per block its isotropic `[1/m, 1/J]`, its entries, its entries hinted by
    /// frames and in matrix-free triplets; per sphere its side count; the picked frames;
    /// per side (sphere order) `2 c + side` of its contact `c`.
    scratch: FillScratch,
}

/// See [`MatrixFree::scratch`].
#[derive(Debug, Clone, Default)]
pub(super) struct FillScratch {
    inv: Vec<Option<[f64; 2]>>,
    total: Vec<u32>,
    hinted: Vec<u32>,
    in_mf: Vec<u32>,
    count: Vec<u32>,
    picked: Vec<u32>,
    side_of: Vec<u32>,
}

/// Arrays per task of [`fill_many`].
const FILL_TASK: usize = 2048;

/// `vs[j] = [f(0)[j], .., f(n - 1)[j]]` for every `j` (capacities kept): one pass over
/// the inputs for all the arrays, in parallel over tasks if `par`.
fn fill_many<const N: usize>(
    vs: [&mut Vec<f64>; N],
    n: usize,
    par: bool,
    f: impl Fn(usize) -> [f64; N] + Sync,
) {
    // Every value is written below: the old ones are kept, not zeroed (only a longer
    // array's new tail is).
    let mut chunks = vs.map(|v| {
        v.resize(n, 0.0);
        v.chunks_mut(FILL_TASK)
    });
    let tasks: Vec<[&mut [f64]; N]> = (0..n.div_ceil(FILL_TASK))
        .map(|_| {
            chunks
                .each_mut()
                .map(|c| c.next().expect("one chunk per task"))
        })
        .collect();
    let task = |(t, mut out): (usize, [&mut [f64]; N])| {
        for j in 0..out[0].len() {
            let x = f(t * FILL_TASK + j);
            for (o, x) in out.iter_mut().zip(x) {
                o[j] = x;
            }
        }
    };
    if par {
        tasks.into_par_iter().enumerate().for_each(task);
    } else {
        tasks.into_iter().enumerate().for_each(task);
    }
}

/// `v = [f(0), .., f(n - 1)]` (its capacity kept), in parallel if `par`.
fn fill<T: Send>(v: &mut Vec<T>, n: usize, par: bool, f: impl Fn(usize) -> T + Sync + Send) {
    v.clear();
    if par {
        v.par_extend((0..n).into_par_iter().map(f));
    } else {
        v.extend((0..n).map(f));
    }
}

impl MatrixFree {
    /// True if some triplet is applied matrix-free.
    #[inline]
    pub fn active(&self) -> bool {
        self.n_mf > 0
    }

    /// Number of spheres.
    #[inline]
    pub fn n_bodies(&self) -> usize {
        self.b_inv.len()
    }

    fn clear(&mut self) {
        self.frames.clear();
        self.of_triplet.clear();
        self.c_row.clear();
        self.c_body.clear();
        for x in self
            .c_n
            .iter_mut()
            .chain(&mut self.c_ra)
            .chain(&mut self.c_rb)
        {
            x.clear();
        }
        self.c_rc.clear();
        self.b_inv.clear();
        self.b_ptr.clear();
        self.clear_sides();
        self.block_sphere.clear();
        self.sphere_block.clear();
        self.skip_block.clear();
        self.explicit_free = false;
        self.n_mf = 0;
    }

    /// Empty the sphere-ordered contact sides (`s_*`).
    fn clear_sides(&mut self) {
        self.s_row.clear();
        for x in self.s_n.iter_mut().chain(&mut self.s_r) {
            x.clear();
        }
        self.s_rc.clear();
    }

    /// `w = M^-1 D g` restricted to the spheres, in the world frame: `[dv; dw]` (6 per
    /// sphere), in tasks of [`GATHER_TASK`] spheres ([`super::frames_simd`]).
    pub fn gather(&self, gamma: &[f64], w: &mut [f64]) {
        let w = &mut w[..6 * self.n_bodies()];
        let task = |(t, o): (usize, &mut [f64])| self.gather_task(gamma, t * GATHER_TASK, o);
        if self.n_bodies() >= PAR_MIN_BODIES {
            w.par_chunks_mut(6 * GATHER_TASK).enumerate().for_each(task);
        } else {
            w.chunks_mut(6 * GATHER_TASK).enumerate().for_each(task);
        }
    }

    /// The triplet `c`'s rows of `D' w`: the relative velocity of the contact points along
    /// `n, u, w`.
    #[inline(always)]
    pub fn triplet(&self, c: usize, w: &[f64]) -> [f64; 3] {
        let at = |x: &[Vec<f64>; 3]| [x[0][c], x[1][c], x[2][c]];
        let mut rel = [0.0; 3];
        let [sa, sb] = self.c_body[c];
        if sa != NONE {
            let x: &[f64; 6] = w[6 * sa as usize..6 * sa as usize + 6]
                .try_into()
                .expect("6");
            let vp = point_velocity(x, &at(&self.c_ra));
            for k in 0..3 {
                rel[k] -= vp[k];
            }
        }
        if sb != NONE {
            let x: &[f64; 6] = w[6 * sb as usize..6 * sb as usize + 6]
                .try_into()
                .expect("6");
            let vp = point_velocity(x, &at(&self.c_rb));
            for k in 0..3 {
                rel[k] += vp[k];
            }
        }
        let n = at(&self.c_n);
        let (u, v) = frame_from(&n, self.c_rc[c]);
        [dot(&n, &rel), dot(&u, &rel), dot(&v, &rel)]
    }
}

#[inline(always)]
fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `dv + dw x r` for `x = [dv; dw]`.
#[inline(always)]
fn point_velocity(x: &[f64; 6], r: &[f64; 3]) -> [f64; 3] {
    let c = cross(&[x[3], x[4], x[5]], r);
    [x[0] + c[0], x[1] + c[1], x[2] + c[2]]
}

/// The tangents of [`tangent_frame`](crate::math::tangent_frame), inlined here (the same operations, so the same bits:
/// the assembly checks the rows' coefficients against this function).
#[inline(always)]
fn frame(n: &[f64; 3]) -> ([f64; 3], [f64; 3]) {
    frame_from(n, frame_recip(n))
}

/// The one division of [`frame`], `-1 / (sign(n_z) + n_z)`: stored with each contact's
/// geometry, so the iterations rebuild the tangents without dividing.
#[inline(always)]
fn frame_recip(n: &[f64; 3]) -> f64 {
    -1.0 / (1.0f64.copysign(n[2]) + n[2])
}

/// [`frame`] from `n` and its [`frame_recip`] `a`.
#[inline(always)]
pub(super) fn frame_from(n: &[f64; 3], a: f64) -> ([f64; 3], [f64; 3]) {
    let sign = 1.0f64.copysign(n[2]);
    let b = n[0] * n[1] * a;
    let u = [1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]];
    let w = [b, sign + n[1] * n[1] * a, -n[1]];
    (u, w)
}

/// `[1/m, 1/J]` of a rigid body whose inverse inertia is `(1/J) I` exactly.
fn isotropic(m: &MassOperator) -> Option<[f64; 2]> {
    match m {
        MassOperator::RigidBody {
            mass, inv_inertia, ..
        } => {
            let j = inv_inertia[(0, 0)];
            let iso =
                (0..3).all(|a| (0..3).all(|b| inv_inertia[(a, b)] == if a == b { j } else { 0.0 }));
            iso.then_some([1.0 / mass, j])
        }
        _ => None,
    }
}

impl CcpProblem {
    /// Build the matrix-free triplets from the frames of `rows` (after the explicit
    /// storage, whose entries it checks the frames against).
    pub(super) fn build_matrix_free(&mut self, rows: &ConstraintRows) {
        let mut mf = std::mem::take(&mut self.mf);
        // The sides and the contacts' geometry keep their length: `fill_matrix_free`
        // resizes and overwrites them (no zeroing of what is overwritten).
        let sides = (
            std::mem::take(&mut mf.s_row),
            std::mem::take(&mut mf.s_n),
            std::mem::take(&mut mf.s_r),
            std::mem::take(&mut mf.s_rc),
        );
        let contacts = (
            std::mem::take(&mut mf.c_n),
            std::mem::take(&mut mf.c_ra),
            std::mem::take(&mut mf.c_rb),
            std::mem::take(&mut mf.c_rc),
        );
        mf.clear();
        (mf.s_row, mf.s_n, mf.s_r, mf.s_rc) = sides;
        (mf.c_n, mf.c_ra, mf.c_rb, mf.c_rc) = contacts;
        let mut filled = false;
        let group = &rows.groups[RowGroup::Friction as usize];
        if !group.frames.is_empty() {
            if group.frames.len() >= PAR_MIN_BODIES {
                mf.frames.par_extend(group.frames.par_iter().copied());
            } else {
                mf.frames.extend_from_slice(&group.frames);
            }
            // `s_row` packs `2 row + side` in 32 bits.
            if self.n_rows < 1 << 31 {
                self.fill_matrix_free(&mut mf, &group.frame_kind);
                filled = true;
            }
        }
        if !filled {
            mf.clear_sides();
            for x in mf.c_n.iter_mut().chain(&mut mf.c_ra).chain(&mut mf.c_rb) {
                x.clear();
            }
            mf.c_rc.clear();
        }
        self.mf = mf;
    }

    /// Does row `i`'s explicit storage match `frame` with direction `d` (row `k` of the
    /// triplet)?
    fn row_matches(&self, i: usize, frame: &ContactFrame, d: &Vector3<f64>) -> bool {
        let mut e = self.row_ptr[i] as usize;
        let e1 = self.row_ptr[i + 1] as usize;
        for (side, blk) in frame.blocks.iter().enumerate() {
            let Some(blk) = blk else { continue };
            if e >= e1 || self.ent_block[e] != blk.0 {
                return false;
            }
            let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
            if c1 - c0 != 6 {
                return false;
            }
            let c = &self.coefs[c0..c1];
            let ds = if side == 0 { -d } else { *d };
            if c[0] != ds.x || c[1] != ds.y || c[2] != ds.z {
                return false;
            }
            let r = Vector3::from(frame.arms[side]);
            let want = r.cross(&ds).norm_squared();
            let have = c[3] * c[3] + c[4] * c[4] + c[5] * c[5];
            let scale = r.norm_squared();
            if (have - want).abs() > ARM_CHECK_TOL * scale {
                return false;
            }
            e += 1;
        }
        e == e1
    }

    /// `kind[f]`: how frame `f`'s rows relate to it; only [`FrameKind::Checked`] rows are
    /// checked against it (frame-only triplets have their rows built from it).
    fn fill_matrix_free(&self, mf: &mut MatrixFree, kind: &[FrameKind]) {
        let nblocks = self.vars.len();
        let mut sc = std::mem::take(&mut mf.scratch);
        let isotropic_of = |b: usize| isotropic(self.vars.mass(BlockId(b as u32)));
        fill(
            &mut sc.inv,
            nblocks,
            nblocks >= PAR_MIN_BODIES,
            isotropic_of,
        );
        let inv = &sc.inv;
        let fs = self.sections.friction.start;
        // Candidates: frames whose rows match and whose blocks are spheres (each frame
        // checked on its own, in parallel for many; `collect` keeps the order).
        let check = |(f, &(k, fr)): (usize, &(u32, ContactFrame))| {
            let n = Vector3::from(fr.normal);
            if !(n.iter().all(|x| x.is_finite()) && fr.arms.iter().flatten().all(|x| x.is_finite()))
            {
                return None;
            }
            let spheres = fr
                .blocks
                .iter()
                .flatten()
                .all(|b| (b.0 as usize) < nblocks && inv[b.0 as usize].is_some());
            if !spheres {
                return None;
            }
            if kind.get(f).is_some_and(|&k| k != FrameKind::Checked) {
                return Some(f as u32);
            }
            let (u, w) = frame(&fr.normal);
            let (u, w) = (Vector3::from(u), Vector3::from(w));
            let t = fs + 3 * k as usize;
            let ok = [n, u, w]
                .iter()
                .enumerate()
                .all(|(r, d)| self.row_matches(t + r, &fr, d));
            ok.then_some(f as u32)
        };
        // Indices into `mf.frames`.
        let mut picked = std::mem::take(&mut sc.picked);
        picked.clear();
        if mf.frames.len() >= PAR_MIN_BODIES {
            picked.par_extend(mf.frames.par_iter().enumerate().filter_map(check));
        } else {
            picked.extend(mf.frames.iter().enumerate().filter_map(check));
        }
        // (Taken out of `mf` while its other fields are filled; put back at the end.)
        let frames = std::mem::take(&mut mf.frames);
        let cand = || picked.iter().map(|&f| &frames[f as usize]);
        // A sphere is pure if all its entries belong to checked frames: then its world-frame
        // velocity change is complete. A triplet is matrix-free if all its spheres are pure;
        // the others (touching a body with other rows) use the explicit rows, so no
        // fallback spreads beyond the bodies it touches.
        let mut total = std::mem::take(&mut sc.total);
        total.clear();
        total.extend((0..nblocks).map(|b| self.tr_ptr[b + 1] - self.tr_ptr[b]));
        let mut hinted = std::mem::take(&mut sc.hinted);
        hinted.clear();
        hinted.resize(nblocks, 0);
        for (_, f) in cand() {
            for b in f.blocks.iter().flatten() {
                hinted[b.0 as usize] += 3;
            }
        }
        mf.block_sphere.resize(nblocks, NONE);
        for b in 0..nblocks {
            if hinted[b] > 0 && hinted[b] == total[b] {
                mf.block_sphere[b] = mf.b_inv.len() as u32;
                mf.sphere_block.push(b as u32);
                mf.b_inv.push(inv[b].expect("checked isotropic"));
            }
        }
        mf.of_triplet.resize(self.sections.friction.len() / 3, NONE);
        // Per candidate (each value on its own, in parallel for many): its normal row, its
        // spheres, its geometry.
        let nc = picked.len();
        let par = nc >= PAR_MIN_BODIES;
        let frame_of = |c: usize| &frames[picked[c] as usize];
        let block_sphere = &mf.block_sphere;
        fill(&mut mf.c_row, nc, par, |c| {
            (fs + 3 * frame_of(c).0 as usize) as u32
        });
        fill(&mut mf.c_body, nc, par, |c| {
            (frame_of(c).1.blocks).map(|b| b.map_or(NONE, |b| block_sphere[b.0 as usize]))
        });
        {
            let ([n0, n1, n2], [a0, a1, a2], [b0, b1, b2]) =
                (&mut mf.c_n, &mut mf.c_ra, &mut mf.c_rb);
            let outs = [n0, n1, n2, a0, a1, a2, b0, b1, b2, &mut mf.c_rc];
            fill_many(outs, nc, par, |c| {
                let f = &frame_of(c).1;
                let ([a, b], n) = (f.arms, f.normal);
                let rc = frame_recip(&n);
                [n[0], n[1], n[2], a[0], a[1], a[2], b[0], b[1], b[2], rc]
            });
        }
        // Entries of each block in matrix-free triplets: a block all of whose entries are
        // needs no explicit velocity. A triplet is matrix-free if all its spheres are pure.
        let mut in_mf = std::mem::take(&mut sc.in_mf);
        in_mf.clear();
        in_mf.resize(nblocks, 0);
        let mut count = std::mem::take(&mut sc.count);
        count.clear();
        count.resize(mf.b_inv.len() + 1, 0);
        for (c, (body, &f)) in mf.c_body.iter().zip(&picked).enumerate() {
            let (k, fr) = &frames[f as usize];
            let pure = fr
                .blocks
                .iter()
                .flatten()
                .all(|b| mf.block_sphere[b.0 as usize] != NONE);
            if pure {
                mf.of_triplet[*k as usize] = c as u32;
                for b in fr.blocks.iter().flatten() {
                    in_mf[b.0 as usize] += 3;
                }
            }
            for &s in body.iter().filter(|&&s| s != NONE) {
                count[s as usize + 1] += 1;
            }
        }
        mf.n_mf = mf.of_triplet.iter().filter(|&&c| c != NONE).count();
        mf.skip_block.clear();
        (mf.skip_block).extend((0..nblocks).map(|b| total[b] > 0 && in_mf[b] == total[b]));
        mf.explicit_free = (0..nblocks).all(|b| total[b] == 0 || mf.skip_block[b]);
        for s in 0..mf.b_inv.len() {
            count[s + 1] += count[s];
        }
        mf.b_ptr.extend_from_slice(&count);
        let n_sides = count[mf.b_inv.len()] as usize;
        // The sides in sphere order (a counting sort: `count` becomes the cursor of each
        // sphere's next side), then their geometry gathered from the contacts.
        let mut side_of = std::mem::take(&mut sc.side_of);
        side_of.resize(n_sides, 0);
        mf.s_row.resize(n_sides, 0);
        let cursor = &mut count;
        for (c, body) in mf.c_body.iter().enumerate() {
            for (side, &s) in body.iter().enumerate() {
                if s != NONE {
                    let slot = &mut cursor[s as usize];
                    let q = *slot as usize;
                    mf.s_row[q] = 2 * mf.c_row[c] + side as u32;
                    side_of[q] = 2 * c as u32 + side as u32;
                    *slot += 1;
                }
            }
        }
        let par = n_sides >= PAR_MIN_BODIES;
        let (c_n, c_ra, c_rb, c_rc) = (&mf.c_n, &mf.c_ra, &mf.c_rb, &mf.c_rc);
        let at = |q: usize| ((side_of[q] / 2) as usize, side_of[q] % 2);
        {
            let ([n0, n1, n2], [r0, r1, r2]) = (&mut mf.s_n, &mut mf.s_r);
            let outs = [n0, n1, n2, r0, r1, r2, &mut mf.s_rc];
            fill_many(outs, n_sides, par, |q| {
                let (c, side) = at(q);
                let r = if side == 0 { c_ra } else { c_rb };
                let n = [c_n[0][c], c_n[1][c], c_n[2][c]];
                [n[0], n[1], n[2], r[0][c], r[1][c], r[2][c], c_rc[c]]
            });
        }
        mf.frames = frames;
        (
            sc.total, sc.hinted, sc.in_mf, sc.count, sc.picked, sc.side_of,
        ) = (total, hinted, in_mf, count, picked, side_of);
        mf.scratch = sc;
    }
}
