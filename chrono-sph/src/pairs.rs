//! The specialized pair passes: the continuity and force passes of
//! [`interact`](crate::interact) (same equations, see there), monomorphized per kernel,
//! density diffusion form and artificial viscosity switch (no per-pair `match`), and
//! evaluated with SIMD over groups of neighbours through `pulp` (safe, runtime dispatch:
//! AVX2 + FMA where the CPU has them, one lane otherwise).
//!
//! Per fluid particle `a`, its neighbour list is walked in tiles of [`TILE`] entries:
//!
//! 1. *compaction*: the positions of `lanes` list entries at a time are loaded as whole
//!    record rows and transposed into columns ([`Packed`] is three groups of four
//!    values; AVX2: 4 loads and 8 shuffles per group of 4 neighbours), their squared
//!    distances computed in SIMD (the scalar arithmetic, unfused), and the indices of the
//!    entries inside the support `r < 2 h` compacted into the tile (the list's Verlet
//!    skin, a third of the entries, costs no kernel work and no branch: the write index
//!    advances by `r2 < (2 h)^2`); on periodic grids the displacement wraps, so this
//!    step is scalar and also stores the displacements;
//! 2. *compute* (SIMD): the pair terms of the compacted entries, `lanes` neighbours at a
//!    time, their records loaded and transposed the same way (no per-entry column
//!    stores), branch-free (masks and selects), accumulated into per-lane sums. The
//!    compacted entries are padded to a whole number of vectors with `a` itself, whose
//!    terms are exact zeros (zero displacement, zero velocity difference, zero density
//!    and pressure differences). Adding a zero of either sign leaves a lane sum
//!    unchanged unless the sum is `-0`, and the sums never are: they start at `+0` (or,
//!    lane 0 of the acceleration, at the body force), and a rounded sum is `-0` only when
//!    both addends are. So the sums are bit-identical to those of the zero-mass neutral
//!    neighbour the earlier passes padded with (a body-force component of exactly `-0`
//!    aside).
//!
//! The continuity pass (first in a step) records, per fluid particle, the sequence of list
//! entries its tiles kept, padding included ([`Support`]); the force pass (same
//! positions) walks that sequence instead of the whole list: no skin entries, no
//! compaction, and the very same vectors, so its sums are bit-identical to a pass that
//! filters the list itself.
//!
//! The per-lane sums are reduced once per particle in a fixed order, so a result depends
//! on the SIMD level (lane count, FMA) but never on the thread count. With one lane and no
//! FMA (the baseline x86-64 path) the arithmetic is the reference pass's, term by term in
//! the same order: bit-identical (checked by the unit tests). With AVX2 + FMA the sums
//! are split over 4 lanes and products are fused into additions (`mul_add_e`): the
//! results differ from the reference by rounding only (bound checked by a proptest).
//!
//! Each fluid-fluid pair is evaluated twice (once from each side): a symmetric
//! evaluation would scatter into the neighbour's sums, which needs per-thread copies of
//! the accumulators and a fixed-order reduction, and breaks the gather/compute split
//! (`docs/performance.md`, SPH section).

use chrono_core::particles::KernelKind;
use pulp::{Arch, Simd, WithSimd};

use crate::data::Deriv;
use crate::interact::{Packed, PassCtx};
use crate::settings::DensityDiffusion;

/// Neighbour-list entries per tile (a multiple of every lane count).
pub(crate) const TILE: usize = 64;
/// Room for the padding after a full tile (the largest lane count, AVX-512).
const PAD: usize = 8;
/// Particles per rayon task (one SIMD dispatch and one stack tile each).
const CHUNK: usize = 256;

/// Kernel codes of the monomorphized passes.
const WENDLAND: u8 = 0;
const CUBIC: u8 = 1;
/// Density diffusion codes.
const DIFF_NONE: u8 = 0;
const DIFF_MC: u8 = 1;
const DIFF_FOURTAKAS: u8 = 2;

/// One tile of a particle's neighbours: the list entries inside the support (compacted,
/// padded with the particle itself) and, on periodic grids only, their displacements.
struct Tile {
    /// The list entry of each slot (padding: the particle itself).
    idx: [u32; TILE + PAD],
    /// Displacement `x_a - x_b` and squared distance (periodic grids only: elsewhere
    /// the compute recomputes them from the transposed positions).
    x: [f64; TILE + PAD],
    y: [f64; TILE + PAD],
    z: [f64; TILE + PAD],
    r2: [f64; TILE + PAD],
}

impl Tile {
    fn new() -> Self {
        let z = [0.0; TILE + PAD];
        Self {
            idx: [0; TILE + PAD],
            x: z,
            y: z,
            z,
            r2: z,
        }
    }

    /// Periodic grids: compacts the in-support entries of `list` (at most [`TILE`])
    /// around `pa` (slot `a`) with their displacements (only positions are read), `lanes`
    /// entries at a time ([`periodic_images`]: the bits of `CellGrid::displacement`). Pads
    /// to a multiple of `lanes` with `a` itself (zero displacement); returns the padded
    /// count.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn compact<S: Simd>(
        &mut self,
        s: S,
        c: &PassCtx<'_>,
        nb: &[Packed],
        pa: &Packed,
        pos_a: &[S::f64s; 3],
        a: u32,
        list: &[u32],
        support2: f64,
    ) -> usize {
        debug_assert!(list.len() <= TILE);
        let lanes = S::F64_LANES;
        let mut k = 0usize;
        let whole = list.len() / lanes * lanes;
        let mut g = Group::default();
        for ids in list[..whole].chunks_exact(lanes) {
            periodic_images(s, c, nb, pa, pos_a, ids, &mut g);
            for (j, &b) in ids.iter().enumerate() {
                // k < TILE: the mask only tells the compiler so (no bounds checks)
                let i = k & (TILE - 1);
                self.idx[i] = b;
                self.x[i] = g.x[j];
                self.y[i] = g.y[j];
                self.z[i] = g.z[j];
                self.r2[i] = g.r2[j];
                k += (g.r2[j] < support2) as usize;
            }
        }
        let pos = pa.pos();
        for &b in &list[whole..] {
            let d = c.grid.displacement(pos, nb[b as usize].pos());
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let i = k & (TILE - 1);
            self.idx[i] = b;
            self.x[i] = d[0];
            self.y[i] = d[1];
            self.z[i] = d[2];
            self.r2[i] = r2;
            k += (r2 < support2) as usize;
        }
        let kp = k.next_multiple_of(lanes);
        for i in k..kp {
            self.idx[i] = a;
            self.x[i] = 0.0;
            self.y[i] = 0.0;
            self.z[i] = 0.0;
            self.r2[i] = 0.0;
        }
        kp
    }

    /// [`compact`](Self::compact) without periodic axes, `lanes` list entries at a time:
    /// their positions transposed, the squared distances in SIMD (the same unfused
    /// arithmetic), the compaction per lane.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn compact_simd<S: Simd>(
        &mut self,
        s: S,
        nb: &[Packed],
        pa: &Packed,
        pos_a: &[S::f64s; 3],
        a: u32,
        list: &[u32],
        support2: f64,
    ) -> usize {
        debug_assert!(list.len() <= TILE);
        let lanes = S::F64_LANES;
        let mut r2s = [0.0f64; 16];
        let mut k = 0usize;
        let whole = list.len() / lanes * lanes;
        for ids in list[..whole].chunks_exact(lanes) {
            let [xb, yb, zb, _] = columns(s, nb, ids, |r| &r.pos_p);
            let (_, r2) = displacement(s, pos_a, xb, yb, zb);
            S::as_mut_simd_f64s(&mut r2s[..lanes]).0[0] = r2;
            for (&b, &r2) in ids.iter().zip(&r2s[..lanes]) {
                self.idx[k & (TILE - 1)] = b;
                k += (r2 < support2) as usize;
            }
        }
        let pos = pa.pos();
        for &b in &list[whole..] {
            let q = nb[b as usize].pos();
            let d = [pos[0] - q[0], pos[1] - q[1], pos[2] - q[2]];
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            self.idx[k & (TILE - 1)] = b;
            k += (r2 < support2) as usize;
        }
        let kp = k.next_multiple_of(lanes);
        for i in k..kp {
            self.idx[i] = a;
        }
        kp
    }

    /// Periodic grids: the displacements of the entries `seq` around `pa` (at most
    /// [`TILE`], a whole number of vectors), `lanes` at a time ([`periodic_images`]).
    #[inline(always)]
    fn displacements<S: Simd>(
        &mut self,
        s: S,
        c: &PassCtx<'_>,
        nb: &[Packed],
        pa: &Packed,
        pos_a: &[S::f64s; 3],
        seq: &[u32],
    ) {
        debug_assert!(seq.len() <= TILE);
        let lanes = S::F64_LANES;
        debug_assert!(seq.len().is_multiple_of(lanes));
        let mut g = Group::default();
        for (v, ids) in seq.chunks_exact(lanes).enumerate() {
            periodic_images(s, c, nb, pa, pos_a, ids, &mut g);
            let i0 = (v * lanes) & (TILE - 1);
            self.x[i0..i0 + lanes].copy_from_slice(&g.x[..lanes]);
            self.y[i0..i0 + lanes].copy_from_slice(&g.y[..lanes]);
            self.z[i0..i0 + lanes].copy_from_slice(&g.z[..lanes]);
            self.r2[i0..i0 + lanes].copy_from_slice(&g.r2[..lanes]);
        }
    }
}

/// One vector of neighbours' displacements and squared distances, per lane.
#[derive(Default)]
struct Group {
    x: [f64; 16],
    y: [f64; 16],
    z: [f64; 16],
    r2: [f64; 16],
}

/// The minimum-image displacements `x_a - x_b` of the neighbours `ids` (one per lane)
/// and their squared distances into `g`: per periodic axis of period `l`, `d - l` where
/// `d > l/2` and `d + l` where `d < -l/2` by selects, the very subtractions
/// `CellGrid::displacement` makes, so the same bits; a group with a lane still more than
/// half a period away (points more than 1.5 periods apart, not seen in a wrapped
/// domain) is redone entry by entry by `CellGrid::displacement` itself.
#[inline(always)]
fn periodic_images<S: Simd>(
    s: S,
    c: &PassCtx<'_>,
    nb: &[Packed],
    pa: &Packed,
    pos_a: &[S::f64s; 3],
    ids: &[u32],
    g: &mut Group,
) {
    let lanes = S::F64_LANES;
    let [xb, yb, zb, _] = columns(s, nb, ids, |r| &r.pos_p);
    let mut d = [
        s.sub_f64s(pos_a[0], xb),
        s.sub_f64s(pos_a[1], yb),
        s.sub_f64s(pos_a[2], zb),
    ];
    let per = c.grid.periods();
    let mut far = false;
    for (ax, l) in per.into_iter().enumerate() {
        if l > 0.0 {
            let half = 0.5 * l;
            let lv = s.splat_f64s(l);
            let down = s.less_than_f64s(s.splat_f64s(half), d[ax]);
            let up = s.less_than_f64s(d[ax], s.splat_f64s(-half));
            d[ax] = s.select_f64s(
                down,
                s.sub_f64s(d[ax], lv),
                s.select_f64s(up, s.add_f64s(d[ax], lv), d[ax]),
            );
            S::as_mut_simd_f64s(&mut g.x[..lanes]).0[0] = d[ax];
            far |= g.x[..lanes].iter().any(|v| v.abs() > half);
        }
    }
    if far {
        let pos = pa.pos();
        for (j, &b) in ids.iter().enumerate() {
            let e = c.grid.displacement(pos, nb[b as usize].pos());
            (g.x[j], g.y[j], g.z[j]) = (e[0], e[1], e[2]);
            g.r2[j] = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        }
        return;
    }
    let r2 = s.add_f64s(
        s.add_f64s(s.mul_f64s(d[0], d[0]), s.mul_f64s(d[1], d[1])),
        s.mul_f64s(d[2], d[2]),
    );
    S::as_mut_simd_f64s(&mut g.x[..lanes]).0[0] = d[0];
    S::as_mut_simd_f64s(&mut g.y[..lanes]).0[0] = d[1];
    S::as_mut_simd_f64s(&mut g.z[..lanes]).0[0] = d[2];
    S::as_mut_simd_f64s(&mut g.r2[..lanes]).0[0] = r2;
}

/// The four columns of one group of [`Packed`] (`field` picks it) over the neighbours
/// `ids` (one per lane): `lanes` rows loaded whole and transposed (AVX2: 4 loads and 8
/// shuffles for 16 values).
#[inline(always)]
fn columns<S: Simd>(
    s: S,
    nb: &[Packed],
    ids: &[u32],
    field: impl Fn(&Packed) -> &[f64; 4],
) -> [S::f64s; 4] {
    let lanes = S::F64_LANES;
    debug_assert_eq!(ids.len(), lanes);
    if lanes == 1 {
        let (v, _) = S::as_simd_f64s(field(&nb[ids[0] as usize]));
        [v[0], v[1], v[2], v[3]]
    } else if lanes == 4 {
        let row = |j: usize| S::as_simd_f64s(field(&nb[ids[j] as usize])).0[0];
        s.deinterleave_shfl_f64s([row(0), row(1), row(2), row(3)])
    } else {
        // any other width: the rows through a stack buffer
        let mut buf = [0.0f64; 4 * 16];
        for (j, &b) in ids.iter().enumerate() {
            buf[4 * j..4 * j + 4].copy_from_slice(field(&nb[b as usize]));
        }
        let (v, _) = S::as_simd_f64s(&buf[..4 * lanes]);
        s.deinterleave_shfl_f64s([v[0], v[1], v[2], v[3]])
    }
}

/// Displacements `x_a - x_b` and squared distances of one vector of neighbours: from
/// the transposed positions `(xb, yb, zb)` (the scalar arithmetic of
/// `CellGrid::displacement` without periodic axes, unfused), or, on periodic grids,
/// from the tile's slots `j..j + lanes`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn separation<S: Simd>(
    s: S,
    c: &PassCtx<'_>,
    pa: &[S::f64s; 3],
    xb: S::f64s,
    yb: S::f64s,
    zb: S::f64s,
    t: &Tile,
    j: usize,
) -> ([S::f64s; 3], S::f64s) {
    if c.periodic {
        let lanes = S::F64_LANES;
        let col = |v: &[f64; TILE + PAD]| S::as_simd_f64s(&v[j..j + lanes]).0[0];
        ([col(&t.x), col(&t.y), col(&t.z)], col(&t.r2))
    } else {
        displacement(s, pa, xb, yb, zb)
    }
}

/// `x_a - x_b` and its square, `(d_x d_x + d_y d_y) + d_z d_z` unfused: the scalar
/// arithmetic of `CellGrid::displacement` without periodic axes, lane by lane.
#[inline(always)]
fn displacement<S: Simd>(
    s: S,
    pa: &[S::f64s; 3],
    xb: S::f64s,
    yb: S::f64s,
    zb: S::f64s,
) -> ([S::f64s; 3], S::f64s) {
    let x = [
        s.sub_f64s(pa[0], xb),
        s.sub_f64s(pa[1], yb),
        s.sub_f64s(pa[2], zb),
    ];
    let r2 = s.add_f64s(
        s.add_f64s(s.mul_f64s(x[0], x[0]), s.mul_f64s(x[1], x[1])),
        s.mul_f64s(x[2], x[2]),
    );
    (x, r2)
}

/// Kernel constants in the form the reference [`Kernel`](chrono_core::particles::Kernel)
/// evaluates them (same products, same order).
#[derive(Clone, Copy)]
struct KConst {
    inv_h: f64,
    norm: f64,
    /// `norm / h^2`.
    c: f64,
}

impl KConst {
    fn new(c: &PassCtx<'_>) -> Self {
        let k = c.kernel;
        let h = k.h();
        // recover `sigma / h^d` exactly as the kernel holds it: W(0) = norm for both
        // kernels (Wendland: 1 * 1 * norm; cubic: norm * 1)
        let norm = k.w(0.0);
        let inv_h = 1.0 / h;
        Self {
            inv_h,
            norm,
            c: norm * inv_h * inv_h,
        }
    }
}

/// `(W, F)` of the kernel `KER` at distance `r` (lanes), as the reference evaluates
/// them; `want_w = false` skips `W`.
#[inline(always)]
fn kernel_wf<S: Simd, const KER: u8>(
    s: S,
    k: KConst,
    r: S::f64s,
    want_w: bool,
) -> (S::f64s, S::f64s) {
    let q = s.mul_f64s(r, s.splat_f64s(k.inv_h));
    let zero = s.splat_f64s(0.0);
    let in2 = s.less_than_f64s(q, s.splat_f64s(2.0));
    if KER == WENDLAND {
        // t = 1 - q/2; W = norm t^4 (2 q + 1); F = -5 c t^3
        let t = s.negate_mul_add_e_f64s(s.splat_f64s(0.5), q, s.splat_f64s(1.0));
        let t2 = s.mul_f64s(t, t);
        let w = if want_w {
            let w = s.mul_f64s(
                s.mul_f64s(s.mul_f64s(s.splat_f64s(k.norm), t2), t2),
                s.mul_add_e_f64s(s.splat_f64s(2.0), q, s.splat_f64s(1.0)),
            );
            s.select_f64s(in2, w, zero)
        } else {
            zero
        };
        let f = s.mul_f64s(s.mul_f64s(s.mul_f64s(s.splat_f64s(-5.0 * k.c), t), t), t);
        (w, s.select_f64s(in2, f, zero))
    } else {
        let in1 = s.less_than_f64s(q, s.splat_f64s(1.0));
        // inner piece, q < 1
        let w1 = if want_w {
            let q15 = s.mul_f64s(s.splat_f64s(1.5), q);
            let a = s.negate_mul_add_e_f64s(q15, q, s.splat_f64s(1.0));
            let q75 = s.mul_f64s(s.mul_f64s(s.splat_f64s(0.75), q), q);
            s.mul_f64s(s.splat_f64s(k.norm), s.mul_add_e_f64s(q75, q, a))
        } else {
            zero
        };
        let f1 = s.mul_f64s(
            s.splat_f64s(k.c),
            s.mul_add_e_f64s(s.splat_f64s(2.25), q, s.splat_f64s(-3.0)),
        );
        // outer piece, 1 <= q < 2 (q clamped to >= 1 so the inner lanes stay finite)
        let t = s.sub_f64s(s.splat_f64s(2.0), q);
        let w2 = if want_w {
            s.mul_f64s(s.mul_f64s(s.mul_f64s(s.splat_f64s(k.norm * 0.25), t), t), t)
        } else {
            zero
        };
        let q1 = s.max_f64s(q, s.splat_f64s(1.0));
        let f2 = s.div_f64s(s.mul_f64s(s.mul_f64s(s.splat_f64s(-0.75 * k.c), t), t), q1);
        let w = s.select_f64s(in1, w1, s.select_f64s(in2, w2, zero));
        let f = s.select_f64s(in1, f1, s.select_f64s(in2, f2, zero));
        (w, f)
    }
}

/// Start of particle `a`'s kept sequence in [`Support::seq`]: its list offset plus
/// [`PAD`] per earlier particle (the padding of a particle's last, partial tile can
/// exceed its list by up to `lanes - 1` entries; full tiles never do).
#[inline(always)]
fn base(c: &PassCtx<'_>, a: usize) -> usize {
    c.list.offsets[a] + PAD * a
}

/// The in-support neighbour sequence of each fluid particle, as the continuity pass's
/// tiles kept it (padded to whole vectors with the particle's own index), for the force
/// pass of the same step (same positions). Scratch owned by the system: its buffers are
/// reused.
#[derive(Debug, Default)]
pub(crate) struct Support {
    /// Particle `a`'s sequence starts at `offsets[a] + PAD a`.
    seq: Vec<u32>,
    /// Its length (0 for wall markers).
    len: Vec<u32>,
}

impl Support {
    /// The buffers (capacity, address), for the no-allocation fingerprint.
    pub(crate) fn fingerprint(&self) -> [(usize, usize); 2] {
        [
            (self.seq.capacity(), self.seq.as_ptr() as usize),
            (self.len.capacity(), self.len.as_ptr() as usize),
        ]
    }

    /// Entries kept in total (padding included).
    #[cfg(test)]
    fn total(&self) -> usize {
        self.len.iter().map(|&l| l as usize).sum()
    }
}

/// Continuity (with diffusion) and XSPH of particle `a` (see
/// [`interact::continuity_pass`](crate::interact)).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn continuity_one<S: Simd, const KER: u8, const DIFF: u8>(
    s: S,
    c: &PassCtx<'_>,
    nb: &[Packed],
    pa: &Packed,
    a: usize,
    kc: KConst,
    support2: f64,
    t: &mut Tile,
    out: &mut Deriv,
    seq: &mut [u32],
    len: &mut u32,
) {
    // frozen particles of the active domain: no row, nothing evaluated
    if !pa.fluid() || !c.evaluates_fluid(a) {
        out.drho = 0.0;
        out.xsph = [0.0; 3];
        *len = 0;
        return;
    }
    let lanes = S::F64_LANES;
    let zero = s.splat_f64s(0.0);
    let (mut sum, mut diff) = (zero, zero);
    let (mut xs0, mut xs1, mut xs2) = (zero, zero, zero);
    let va = pa.vel();
    let va = [
        s.splat_f64s(va[0]),
        s.splat_f64s(va[1]),
        s.splat_f64s(va[2]),
    ];
    let rho_a = s.splat_f64s(pa.rho());
    let p_a = s.splat_f64s(pa.p());
    let half = s.splat_f64s(0.5);
    let xsph = s.splat_f64s(c.xsph);
    let g = [
        s.splat_f64s(c.gravity[0]),
        s.splat_f64s(c.gravity[1]),
        s.splat_f64s(c.gravity[2]),
    ];
    let inv_c2 = s.splat_f64s(c.inv_c2);
    let pos_a = pa.pos();
    let pos_a = [
        s.splat_f64s(pos_a[0]),
        s.splat_f64s(pos_a[1]),
        s.splat_f64s(pos_a[2]),
    ];
    let mut w = 0usize;
    for chunk in c.list.neighbors(a).chunks(TILE) {
        let kp = if c.periodic {
            t.compact(s, c, nb, pa, &pos_a, a as u32, chunk, support2)
        } else {
            t.compact_simd(s, nb, pa, &pos_a, a as u32, chunk, support2)
        };
        seq[w..w + kp].copy_from_slice(&t.idx[..kp]);
        w += kp;
        for j in (0..kp).step_by(lanes) {
            let ids = &t.idx[j..j + lanes];
            let [xb, yb, zb, pb] = columns(s, nb, ids, |r| &r.pos_p);
            let [vxb, vyb, vzb, rho_b] = columns(s, nb, ids, |r| &r.vel_rho);
            let [_, mb, vb, flb] = columns(s, nb, ids, |r| &r.pr2_m_vol_fl);
            let (x, r2) = separation(s, c, &pos_a, xb, yb, zb, t, j);
            let r = s.sqrt_f64s(r2);
            let (wk, fk) = kernel_wf::<S, KER>(s, kc, r, true);
            let vab = [
                s.sub_f64s(va[0], vxb),
                s.sub_f64s(va[1], vyb),
                s.sub_f64s(va[2], vzb),
            ];
            // sum += V_b F (v_ab . x_ab)
            let vdx = s.mul_add_e_f64s(
                vab[2],
                x[2],
                s.mul_add_e_f64s(vab[1], x[1], s.mul_f64s(vab[0], x[0])),
            );
            sum = s.mul_add_e_f64s(s.mul_f64s(vb, fk), vdx, sum);
            // XSPH (fluid b only: the fluid flag zeroes the mass)
            let rho_ab = s.mul_f64s(half, s.add_f64s(rho_a, rho_b));
            let mf = s.mul_f64s(mb, flb);
            let k = s.div_f64s(s.mul_f64s(s.mul_f64s(xsph, mf), wk), rho_ab);
            xs0 = s.negate_mul_add_e_f64s(k, vab[0], xs0);
            xs1 = s.negate_mul_add_e_f64s(k, vab[1], xs1);
            xs2 = s.negate_mul_add_e_f64s(k, vab[2], xs2);
            // delta-SPH, fluid b only: psi_ba (-F) V_b
            if DIFF != DIFF_NONE {
                let psi = if DIFF == DIFF_MC {
                    s.sub_f64s(rho_b, rho_a)
                } else {
                    let gx = s.mul_add_e_f64s(
                        g[2],
                        x[2],
                        s.mul_add_e_f64s(g[1], x[1], s.mul_f64s(g[0], x[0])),
                    );
                    s.mul_f64s(s.mul_add_e_f64s(rho_ab, gx, s.sub_f64s(pb, p_a)), inv_c2)
                };
                let vf = s.mul_f64s(vb, flb);
                diff = s.negate_mul_add_e_f64s(s.mul_f64s(vf, psi), fk, diff);
            }
        }
    }
    *len = w as u32;
    let sum = s.reduce_sum_f64s(sum);
    let diff = s.reduce_sum_f64s(diff);
    out.drho = pa.rho() * sum + c.diffusion_coef * diff;
    out.xsph = [
        s.reduce_sum_f64s(xs0),
        s.reduce_sum_f64s(xs1),
        s.reduce_sum_f64s(xs2),
    ];
}

/// Acceleration of particle `a` (see [`interact::force_pass`](crate::interact)) over
/// `seq`, the sequence the continuity pass kept for it (see [`Support`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn force_one<S: Simd, const KER: u8, const AV: bool>(
    s: S,
    c: &PassCtx<'_>,
    pa: &Packed,
    kc: KConst,
    t: &mut Tile,
    out: &mut Deriv,
    shift: Option<&mut [f64; 3]>,
    nb: &[Packed],
    seq: &[u32],
) {
    if !pa.fluid() {
        out.acc = [0.0; 3];
        if let Some(g) = shift {
            *g = [0.0; 3];
        }
        return;
    }
    // the shifting's concentration gradient: same pairs, positions and volumes
    let sh = if shift.is_some() { c.shift } else { 0 };
    let mut gc = [s.splat_f64s(0.0); 3];
    let clump = s.splat_f64s(crate::shifting::CLUMP_R);
    let inv_w_dp = s.splat_f64s(c.inv_w_dp);
    let one = s.splat_f64s(1.0);
    // the body force enters lane 0 first, as the reference starts its sum with it
    let mut acc = [
        s.partial_load_f64s(&[c.accel[0]]),
        s.partial_load_f64s(&[c.accel[1]]),
        s.partial_load_f64s(&[c.accel[2]]),
    ];
    let va = pa.vel();
    let va = [
        s.splat_f64s(va[0]),
        s.splat_f64s(va[1]),
        s.splat_f64s(va[2]),
    ];
    let rho_a = s.splat_f64s(pa.rho());
    let pr2_a = s.splat_f64s(pa.pr2());
    let half = s.splat_f64s(0.5);
    let h = c.kernel.h();
    let eta2 = s.splat_f64s(0.01 * h * h);
    let ach = s.splat_f64s(-c.alpha * c.eos.sound_speed * h);
    let two_mu = s.splat_f64s(2.0 * c.mu);
    let zero = s.splat_f64s(0.0);
    let pos_a = pa.pos();
    let pos_a = [
        s.splat_f64s(pos_a[0]),
        s.splat_f64s(pos_a[1]),
        s.splat_f64s(pos_a[2]),
    ];
    let lanes = S::F64_LANES;
    // each chunk is a whole number of vectors: the sequence is, and TILE is a multiple
    // of every lane count
    for chunk in seq.chunks(TILE) {
        if c.periodic {
            t.displacements(s, c, nb, pa, &pos_a, chunk);
        }
        for j in (0..chunk.len()).step_by(lanes) {
            let ids = &chunk[j..j + lanes];
            let [xb, yb, zb, _] = columns(s, nb, ids, |r| &r.pos_p);
            let [vxb, vyb, vzb, rho_b] = columns(s, nb, ids, |r| &r.vel_rho);
            let [pr2_b, mb, vb, _] = columns(s, nb, ids, |r| &r.pr2_m_vol_fl);
            let (x, r2) = separation(s, c, &pos_a, xb, yb, zb, t, j);
            let (wk, fk) = kernel_wf::<S, KER>(s, kc, s.sqrt_f64s(r2), sh == 2);
            if sh != 0 {
                // grad C += V_b (1 + R (W_ab / W(dp))^4) F x_ab
                let mut f = s.mul_f64s(vb, fk);
                if sh == 2 {
                    let q = s.mul_f64s(wk, inv_w_dp);
                    let q2 = s.mul_f64s(q, q);
                    f = s.mul_f64s(f, s.mul_add_e_f64s(clump, s.mul_f64s(q2, q2), one));
                }
                for k in 0..3 {
                    gc[k] = s.mul_add_e_f64s(f, x[k], gc[k]);
                }
            }
            let vv = [
                s.sub_f64s(va[0], vxb),
                s.sub_f64s(va[1], vyb),
                s.sub_f64s(va[2], vzb),
            ];
            let rho_ab = s.mul_f64s(half, s.add_f64s(rho_a, rho_b));
            // pressure: -m_b (p_a/rho_a^2 + p_b/rho_b^2) F
            let mut coef = s.mul_f64s(s.mul_f64s(s.neg_f64s(mb), s.add_f64s(pr2_a, pr2_b)), fk);
            if AV {
                let vx = s.mul_add_e_f64s(
                    vv[2],
                    x[2],
                    s.mul_add_e_f64s(vv[1], x[1], s.mul_f64s(vv[0], x[0])),
                );
                let pi = s.div_f64s(
                    s.mul_f64s(ach, vx),
                    s.mul_f64s(rho_ab, s.add_f64s(r2, eta2)),
                );
                // approaching pairs only (v_ab . x_ab < 0)
                let pi = s.select_f64s(s.less_than_f64s(vx, zero), pi, zero);
                coef = s.negate_mul_add_e_f64s(s.mul_f64s(mb, pi), fk, coef);
            }
            // Morris: m_b 2 mu F / rho_ab^2
            let visc = s.div_f64s(
                s.mul_f64s(s.mul_f64s(mb, two_mu), fk),
                s.mul_f64s(rho_ab, rho_ab),
            );
            for k in 0..3 {
                acc[k] = s.add_f64s(
                    acc[k],
                    s.mul_add_e_f64s(coef, x[k], s.mul_f64s(visc, vv[k])),
                );
            }
        }
    }
    out.acc = [
        s.reduce_sum_f64s(acc[0]),
        s.reduce_sum_f64s(acc[1]),
        s.reduce_sum_f64s(acc[2]),
    ];
    if let Some(g) = shift {
        *g = if sh == 0 {
            [0.0; 3]
        } else {
            [
                s.reduce_sum_f64s(gc[0]),
                s.reduce_sum_f64s(gc[1]),
                s.reduce_sum_f64s(gc[2]),
            ]
        };
    }
}

#[path = "pairs_tasks.rs"]
mod tasks;
pub(crate) use tasks::{continuity_pass, force_pass};

#[cfg(test)]
#[path = "pairs_tests.rs"]
mod tests;
