//! The assembled cone complementarity problem: storage, assembly and row-level access.
//! The operators (`apply_n`, `project`, `residual` ...) are in `ops.rs`.

use std::ops::Range;

use super::rows::{ConstraintRows, N_GROUPS, PER_BODY_ROWS, RowGroup, RowId};
use super::variables::{BlockId, Variables};
use crate::error::{ChronoError, Result};

/// The global row ranges of the six groups, in this order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Sections {
    /// Bilateral (free) rows.
    pub bilateral: Range<usize>,
    /// Box-bounded rows.
    pub boxed: Range<usize>,
    /// Unilateral rows.
    pub unilateral: Range<usize>,
    /// Friction triplets (length a multiple of 3).
    pub friction: Range<usize>,
    /// Contacts with rolling and spinning friction (length a multiple of 6).
    pub rolling: Range<usize>,
    /// Contacts with per-body rolling resistance (length a multiple of [`PER_BODY_ROWS`]).
    pub rolling_per_body: Range<usize>,
}

impl Sections {
    /// The cone block (first row, number of rows) that contains row `i`: a friction
    /// triplet (3 rows), a rolling contact (6 rows), a per-body rolling contact
    /// ([`PER_BODY_ROWS`]), or the row itself (1).
    #[inline]
    pub fn block_of(&self, i: usize) -> (usize, usize) {
        let pb = &self.rolling_per_body;
        if i >= pb.start && i < pb.end {
            let n = PER_BODY_ROWS;
            (pb.start + n * ((i - pb.start) / n), n)
        } else if i >= self.rolling.start && i < self.rolling.end {
            (self.rolling.start + 6 * ((i - self.rolling.start) / 6), 6)
        } else if i >= self.friction.start && i < self.friction.end {
            (self.friction.start + 3 * ((i - self.friction.start) / 3), 3)
        } else {
            (i, 1)
        }
    }
}

/// Scratch space for the operations of a [`CcpProblem`]; a solver owns one and reuses it,
/// so iterations allocate nothing.
#[derive(Debug, Clone, Default)]
pub struct CcpWork {
    /// A velocity-sized vector (`ndof`).
    pub v: Vec<f64>,
    /// World-frame velocity changes of the matrix-free spheres (6 per sphere).
    pub w: Vec<f64>,
    /// Partial sums of deterministic reductions.
    pub partials: Vec<f64>,
    /// One value per friction triplet (the residual's terms).
    pub terms: Vec<f64>,
}

impl CcpWork {
    /// Scratch sized for `problem`.
    pub fn for_problem(problem: &CcpProblem) -> Self {
        let mut w = Self::default();
        w.resize(problem);
        w
    }

    /// Resize for `problem` (no allocation if already large enough).
    pub fn resize(&mut self, problem: &CcpProblem) {
        self.v.resize(problem.ndof(), 0.0);
        self.w.resize(6 * problem.mf.n_bodies(), 0.0);
    }
}

/// The CCP of one step:
///
/// ```text
/// find g:  Y ∋ g ⊥ -(N g + r) ∈ Y°,   N = D'M^-1 D + E,   r = b + D'M^-1 k
/// ```
///
/// equivalently `min f(g) = 1/2 g'N g + r'g` over `g ∈ Y` (the product of the groups'
/// sets: free, boxes, half-lines, Coulomb cones, rolling/spinning cones). `k = M v + h f`
/// is the momentum before constraints (N s); the new velocity is `v+ = M^-1 (k + D g)`
/// ([`velocities`](Self::velocities)), so `N g + r = D' v+ + b + E g` is the constraint
/// velocity (m/s; rad/s for torque rows). Anitescu and Tasora 2010, Comput. Optim. Appl.
/// 47(2).
///
/// # Storage
///
/// `N` is never formed. The Jacobian is stored twice, each copy laid out for one half of
/// `N g = D'(M^-1 D g) + E g`, so that one product streams each array once:
///
/// - by block (CSC-like): for each variable block its entries in row order, each with its
///   row index and its column of `M^-1 D` (contiguous per block); `M^-1 D g` gathers one
///   block at a time (parallel over blocks, no write conflicts);
/// - by row (CSR): for each row its entries, each with the block's dof offset and the
///   coefficients of `D_i'` (and of `M^-1 D_i`, for Gauss–Seidel's row updates).
///
/// Friction triplets pushed with a [`ContactFrame`](super::ContactFrame) (contacts between
/// spheres: rigid bodies with isotropic inertia) are in addition stored matrix-free — the
/// normal, the two lever arms and the frame's division, 10 numbers instead of 36
/// coefficients — and [`apply_n`](Self::apply_n) / [`gradient`](Self::gradient) use that
/// form for them (about 110 bytes per row and product instead of ~256); the explicit copies above stay the
/// reference for every row-level access (`row_dot`, `row_add_minv`, `n_entry`,
/// `constraint_rows`, `velocities`), and the two agree to rounding.
///
/// The crate's own contacts between rigid bodies come as their geometry alone
/// (`ConstraintRows::push_friction_frame`); when every row is such a triplet applied
/// matrix-free (a granular bed), the explicit coefficients are built only on the first
/// row-level access, and `diag(N)`, `r` and `velocities` come from the geometry
/// (`frame_rows.rs`; [`coefficients_deferred`](Self::coefficients_deferred)).
///
/// Row-wise and block-wise loops are rayon-parallel for large problems and every reduction
/// is done in a fixed order ([`reduce`](super::reduce)), so results are bit-identical for
/// any thread count.
#[derive(Debug, Clone, Default)]
pub struct CcpProblem {
    pub(super) vars: Variables,
    pub(super) n_rows: usize,
    // By row: entries of row i are row_ptr[i]..row_ptr[i+1].
    pub(super) row_ptr: Vec<u32>,
    pub(super) ent_block: Vec<u32>,
    pub(super) ent_off: Vec<u32>,
    /// Start of each entry's coefficients, with a final sentinel (len = entries + 1).
    pub(super) ent_coef: Vec<u32>,
    /// The span of each entry's coefficients outside which all are zero, relative to its
    /// first: `[lo, hi)` (see [`nonzero_span`](Self::nonzero_span)).
    pub(super) ent_span: Vec<[u32; 2]>,
    pub(super) coefs: Vec<f64>,
    pub(super) minv: Vec<f64>,
    // By block: entries of block b are tr_ptr[b]..tr_ptr[b+1] (row order), their M^-1 D
    // coefficients tr_minv[tr_cptr[b]..] contiguous (tr_row, tr_ent and tr_minv empty
    // when every block with rows is a matrix-free sphere's: M^-1 D is then read through
    // the spheres' contact sides).
    pub(super) tr_ptr: Vec<u32>,
    pub(super) tr_cptr: Vec<u32>,
    pub(super) tr_row: Vec<u32>,
    pub(super) tr_minv: Vec<f64>,
    /// The entry of each slot of the block order.
    pub(super) tr_ent: Vec<u32>,
    /// Scratch of the assembly's row checks: each block's dof count.
    pub(super) block_ndof: Vec<u32>,
    /// Scratch of the counting sort of the block order: each block's next slot.
    pub(super) tr_cursor: Vec<u32>,
    pub(super) k: Vec<f64>,
    pub(super) b: Vec<f64>,
    pub(super) eps: Vec<f64>,
    pub(super) diag: Vec<f64>,
    pub(super) scale: Vec<f64>,
    pub(super) r: Vec<f64>,
    pub(super) lo: Vec<f64>,
    pub(super) hi: Vec<f64>,
    pub(super) mu: Vec<f64>,
    pub(super) mu_rolling: Vec<[f64; 3]>,
    pub(super) mu_per_body: Vec<[f64; 3]>,
    /// Upper triangles of the diagonal blocks of `N`: 6 per triplet, then 21 per rolling
    /// contact, then 55 per per-body rolling contact (row-major upper triangles); built on
    /// first use after each assembly ([`CcpProblem::cone_block`]).
    pub(super) cone_blocks: ConeBlocks,
    pub(super) v_free: Vec<f64>,
    pub(super) sections: Sections,
    pub(super) group_start: [usize; N_GROUPS],
    /// The triplets applied matrix-free ([`super::ContactFrame`]).
    pub(super) mf: super::frames::MatrixFree,
    /// True if every row is a frame-only triplet applied matrix-free
    /// ([`super::frame_rows`]): `coefs` and `minv` are then empty, built on first use
    /// into `lazy`.
    pub(super) deferred: bool,
    pub(super) lazy: std::sync::OnceLock<super::frame_rows::LazyCoefs>,
    /// Scratch of the assembly of frame-only triplets: per triplet its frame or `NONE`.
    pub(super) only_of: Vec<u32>,
    /// Scratch of the assembly of frame-only triplets: per block its first dof if it is
    /// an oriented rigid body's, else `NONE`.
    pub(super) block_offsets: Vec<u32>,
    /// Scratch of a deferred assembly: the spheres' free velocities, world frame.
    pub(super) v_free_w: Vec<f64>,
}

pub(super) const GROUP_ORDER: [RowGroup; N_GROUPS] = [
    RowGroup::Bilateral,
    RowGroup::Box,
    RowGroup::Unilateral,
    RowGroup::Friction,
    RowGroup::Rolling,
    RowGroup::RollingPerBody,
];

pub(super) fn group_name(g: RowGroup) -> &'static str {
    match g {
        RowGroup::Bilateral => "bilateral",
        RowGroup::Box => "box",
        RowGroup::Unilateral => "unilateral",
        RowGroup::Friction => "friction",
        RowGroup::Rolling => "rolling",
        RowGroup::RollingPerBody => "rolling_per_body",
    }
}

/// Index of entry `(j, k)`, `j <= k`, in the row-major upper triangle of an `n x n` matrix
/// (the layout of [`CcpProblem::cone_block`]).
#[inline]
pub fn upper_index(n: usize, j: usize, k: usize) -> usize {
    j * n - j * (j + 1) / 2 + k
}

impl CcpProblem {
    /// An empty problem (assemble it with [`assemble`](Self::assemble)).
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of rows `m` (the length of `g`).
    #[inline]
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    /// Number of dof of the variables.
    #[inline]
    pub fn ndof(&self) -> usize {
        self.vars.ndof()
    }

    /// Number of Jacobian entries (row, block) with their coefficients: `nnz(D) =`
    /// [`n_coefs`](Self::n_coefs).
    #[inline]
    pub fn n_entries(&self) -> usize {
        self.ent_block.len()
    }

    /// Number of stored Jacobian coefficients, `nnz(D)`.
    #[inline]
    pub fn n_coefs(&self) -> usize {
        self.ent_coef.last().map_or(0, |&c| c as usize)
    }

    /// The variables this problem was assembled from.
    pub fn variables(&self) -> &Variables {
        &self.vars
    }

    /// The momentum `k = M v + h f` the problem was assembled from (N s).
    pub fn momentum(&self) -> &[f64] {
        &self.k
    }

    /// The row ranges of the groups.
    #[inline]
    pub fn sections(&self) -> &Sections {
        &self.sections
    }

    /// True if every row is bilateral (a linear problem `N g = -r`).
    pub fn is_bilateral_only(&self) -> bool {
        self.sections.bilateral.len() == self.n_rows
    }

    /// The global row of a pushed row.
    #[inline]
    pub fn row_index(&self, id: RowId) -> usize {
        self.group_start[id.group as usize] + id.index as usize
    }

    /// `diag(N)_i = D_i'M^-1 D_i + eps_i`.
    #[inline]
    pub fn diag(&self) -> &[f64] {
        &self.diag
    }

    /// The step scale of every row ([`residual_scale`](Self::residual_scale)).
    #[inline]
    pub fn scales(&self) -> &[f64] {
        &self.scale
    }

    /// The right-hand side `r = b + D'M^-1 k`.
    #[inline]
    pub fn r(&self) -> &[f64] {
        &self.r
    }

    /// The stabilization terms `b`.
    #[inline]
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// Add `delta` to the stabilization term of row `i` (`b_i` and `r_i`), e.g. the normal
    /// shift of the de Saxcé passes ([`crate::FrictionLaw::Coulomb`]).
    ///
    /// # Panics
    /// If `i >= n_rows()`.
    pub fn add_to_bias(&mut self, i: usize, delta: f64) {
        self.b[i] += delta;
        self.r[i] += delta;
    }

    /// The compliances `eps`.
    #[inline]
    pub fn eps(&self) -> &[f64] {
        &self.eps
    }

    /// The friction coefficient of each triplet of the friction section.
    #[inline]
    pub fn friction_mu(&self) -> &[f64] {
        &self.mu
    }

    /// `[mu_slide, mu_spin, mu_roll]` of each contact of the rolling section.
    #[inline]
    pub fn rolling_mu(&self) -> &[[f64; 3]] {
        &self.mu_rolling
    }

    /// `[mu_slide, mu_spin, mu_roll]` of each contact of the per-body rolling section.
    #[inline]
    pub fn rolling_per_body_mu(&self) -> &[[f64; 3]] {
        &self.mu_per_body
    }

    /// Lower and upper bounds of the box section.
    #[inline]
    pub fn box_bounds(&self) -> (&[f64], &[f64]) {
        (&self.lo, &self.hi)
    }

    /// The unconstrained new velocity `M^-1 k`.
    #[inline]
    pub fn free_velocity(&self) -> &[f64] {
        &self.v_free
    }

    /// The step scale of row `i` used by the residual and the diagonal metric of the
    /// solvers: `1 / diag(N)_i`, with `diag(N)` averaged over the rows of a friction triplet
    /// or rolling contact so that the scaled step keeps the cone's shape (0 for a zero
    /// diagonal). Cached at assembly.
    #[inline]
    pub fn residual_scale(&self, i: usize) -> f64 {
        self.scale[i]
    }

    /// The variable blocks row `i` touches, in the order they were pushed.
    pub fn row_blocks(&self, i: usize) -> impl Iterator<Item = BlockId> + '_ {
        self.ent_block[self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize]
            .iter()
            .map(|&b| BlockId(b))
    }

    /// The entries of row `i`: each block it touches with the coefficients of `M^-1 D_i` on
    /// that block's dof (the velocity change of the block per unit impulse on the row).
    pub fn row_minv_entries(&self, i: usize) -> impl Iterator<Item = (BlockId, &[f64])> + '_ {
        (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize).map(|e| {
            (
                BlockId(self.ent_block[e]),
                &self.minv()[self.ent_coef[e] as usize..self.ent_coef[e + 1] as usize],
            )
        })
    }

    /// The entries of row `i` with both coefficient sets: each block it touches, the
    /// block's first dof, the coefficients of `D_i` (the row's Jacobian on that block) and of
    /// `M^-1 D_i`. For operators built from rows, e.g. a coarse (Galerkin) `P'N P`.
    pub fn row_entries(
        &self,
        i: usize,
    ) -> impl Iterator<Item = (BlockId, usize, &[f64], &[f64])> + '_ {
        (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize).map(|e| {
            let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
            (
                BlockId(self.ent_block[e]),
                self.ent_off[e] as usize,
                &self.coefs()[c0..c1],
                &self.minv()[c0..c1],
            )
        })
    }

    /// The coefficients of entry `e` that may be non-zero, `coefs[a..b]` (absolute
    /// positions). A row on a coupled block (an implicit mesh node's contact or
    /// attachment) has a few non-zero coefficients among the block's thousands of dof;
    /// the products over `D_i` (`n_entry`, `row_dot`, `diag(N)`) skip the zeros outside
    /// the span, which changes no sum (`s + 0 b = s` for finite `b`). Entries of up to 6
    /// coefficients keep their whole range (their unrolled loops).
    #[inline]
    pub(super) fn nonzero_span(&self, e: usize) -> (usize, usize) {
        let c0 = self.ent_coef[e] as usize;
        let [lo, hi] = self.ent_span[e];
        (c0 + lo as usize, c0 + hi as usize)
    }

    /// The entry `N_ij = D_i'M^-1 D_j + eps_i delta_ij` (sparse: sums over the blocks both
    /// rows touch).
    pub fn n_entry(&self, i: usize, j: usize) -> f64 {
        let mut s = if i == j { self.eps[i] } else { 0.0 };
        for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            for f in self.row_ptr[j] as usize..self.row_ptr[j + 1] as usize {
                if self.ent_block[e] == self.ent_block[f] {
                    let (c0, c1) = self.nonzero_span(e);
                    let m0 = self.ent_coef[f] as usize + (c0 - self.ent_coef[e] as usize);
                    for (a, b) in self.coefs()[c0..c1].iter().zip(&self.minv()[m0..]) {
                        s += a * b;
                    }
                }
            }
        }
        s
    }

    /// The diagonal block `N_tt` of the friction triplet or rolling contact whose first row
    /// is `t`, as a row-major upper triangle (6 values for a triplet, 21 for a rolling
    /// contact, 55 for a per-body rolling contact); cached at assembly. `None` if `t` does
    /// not start a cone block.
    pub fn cone_block(&self, t: usize) -> Option<&[f64]> {
        self.cone_block_in(self.prepare_cone_blocks(), t)
    }

    /// Builds the cone blocks of [`cone_block`](Self::cone_block) now (else on its first
    /// call), e.g. before parallel sweeps read them; returns them in their layout.
    pub fn prepare_cone_blocks(&self) -> &[f64] {
        self.cone_blocks.get(|buf| self.fill_cone_blocks(buf))
    }

    fn cone_block_in<'a>(&self, blocks: &'a [f64], t: usize) -> Option<&'a [f64]> {
        let s = &self.sections;
        let nf = s.friction.len() / 3;
        let (pb, n) = (&s.rolling_per_body, PER_BODY_ROWS);
        if pb.contains(&t) && (t - pb.start).is_multiple_of(n) {
            let size = n * (n + 1) / 2;
            let o = 6 * nf + 21 * (s.rolling.len() / 6) + size * ((t - pb.start) / n);
            return Some(&blocks[o..o + size]);
        }
        if s.friction.contains(&t) && (t - s.friction.start).is_multiple_of(3) {
            let c = (t - s.friction.start) / 3;
            Some(&blocks[6 * c..6 * c + 6])
        } else if s.rolling.contains(&t) && (t - s.rolling.start).is_multiple_of(6) {
            let c = (t - s.rolling.start) / 6;
            let o = 6 * nf + 21 * c;
            Some(&blocks[o..o + 21])
        } else {
            None
        }
    }

    /// `D_i' v` for one row.
    #[inline]
    pub fn row_dot(&self, i: usize, v: &[f64]) -> f64 {
        self.row_dot_in(i, v, 0)
    }

    /// `D_i' v` for one row whose blocks all lie in `v`, a window of the dof vector that
    /// starts at dof `base` (e.g. one part of a partitioned sweep).
    ///
    /// # Panics
    /// If an entry of the row lies outside the window.
    #[inline]
    pub fn row_dot_in(&self, i: usize, v: &[f64], base: usize) -> f64 {
        let mut s = 0.0;
        for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
            let off = self.ent_off[e] as usize - base;
            // A rigid body's 6 dof as fixed-size arrays (no per-coefficient bounds checks or
            // loop control); the same sums in the same order, so the same bits.
            if let (Some(c), Some(x)) = (
                self.coefs().get(c0..c0 + 6).filter(|_| c1 - c0 == 6),
                v.get(off..off + 6),
            ) {
                let (c, x): (&[f64; 6], &[f64; 6]) =
                    (c.try_into().expect("6"), x.try_into().expect("6"));
                for k in 0..6 {
                    s += c[k] * x[k];
                }
                continue;
            }
            // A particle's 3 dof with no zero span trimmed off (density rows, MPM
            // markers): unrolled, the same sums in the same order as below.
            if c1 - c0 == 3
                && self.ent_span[e] == [0, 3]
                && let (Some(c), Some(x)) = (self.coefs().get(c0..c0 + 3), v.get(off..off + 3))
            {
                s += c[0] * x[0];
                s += c[1] * x[1];
                s += c[2] * x[2];
                continue;
            }
            let (a0, a1) = self.nonzero_span(e);
            let x = &v[off + (a0 - c0)..off + (a1 - c0)];
            for (c, x) in self.coefs()[a0..a1].iter().zip(x) {
                s += c * x;
            }
        }
        s
    }

    /// `v += s M^-1 D_i` for one row (the velocity change caused by an impulse `s` on row `i`).
    #[inline]
    pub fn row_add_minv(&self, i: usize, s: f64, v: &mut [f64]) {
        self.row_add_minv_in(i, s, v, 0)
    }

    /// `v += s M^-1 D_i` for one row whose blocks all lie in `v`, a window of the dof
    /// vector that starts at dof `base`.
    ///
    /// # Panics
    /// If an entry of the row lies outside the window.
    #[inline]
    pub fn row_add_minv_in(&self, i: usize, s: f64, v: &mut [f64], base: usize) {
        for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
            let off = self.ent_off[e] as usize - base;
            if c1 - c0 == 6 {
                let x: &mut [f64; 6] = (&mut v[off..off + 6]).try_into().expect("6");
                let c: &[f64; 6] = self.minv()[c0..c0 + 6].try_into().expect("6");
                for k in 0..6 {
                    x[k] += s * c[k];
                }
                continue;
            }
            let x = &mut v[off..off + (c1 - c0)];
            for (x, c) in x.iter_mut().zip(&self.minv()[c0..c1]) {
                *x += s * c;
            }
        }
    }

    /// Row `i`'s entries: each block and its `D` coefficients.
    pub(super) fn row_entries_raw(&self, i: usize) -> impl Iterator<Item = (u32, &[f64])> + '_ {
        (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize).map(|e| {
            (
                self.ent_block[e],
                &self.coefs()[self.ent_coef[e] as usize..self.ent_coef[e + 1] as usize],
            )
        })
    }

    /// Rebuild the rows this problem was assembled from (same groups, order, entries, `b`,
    /// `eps`, bounds and friction coefficients), e.g. to save it ([`super::ProblemFile`]) or
    /// to assemble a sub-problem. `assemble(variables(), &rows, momentum())` reproduces this
    /// problem bit for bit (frame-only triplets come back as frame-only triplets, so a
    /// problem whose coefficients were deferred is deferred again; the variables carry the
    /// rotations they need).
    pub fn constraint_rows(&self) -> ConstraintRows {
        let mut rows = ConstraintRows::new();
        self.push_rows(0..self.n_rows, &mut rows);
        rows
    }

    /// Push the rows `range` (whole cone blocks) into `rows`, in their groups.
    pub(super) fn push_rows(&self, range: Range<usize>, rows: &mut ConstraintRows) {
        self.push_rows_mapped(range, None, rows);
    }

    /// [`push_rows`](Self::push_rows) with the variable blocks renumbered by `map` (parent
    /// block -> new block; every block the rows touch must be mapped).
    pub(super) fn push_rows_mapped(
        &self,
        range: Range<usize>,
        map: Option<&[u32]>,
        rows: &mut ConstraintRows,
    ) {
        let block = |b: u32| BlockId(map.map_or(b, |m| m[b as usize]));
        let entries = |i: usize| -> Vec<super::RowEntry<'_>> {
            (self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize)
                .map(|e| super::RowEntry {
                    block: block(self.ent_block[e]),
                    coefs: &self.coefs()[self.ent_coef[e] as usize..self.ent_coef[e + 1] as usize],
                })
                .collect()
        };
        let s = &self.sections;
        let mut i = range.start;
        while i < range.end {
            if s.bilateral.contains(&i) {
                rows.push_bilateral(&entries(i), self.b[i], self.eps[i]);
                i += 1;
            } else if s.boxed.contains(&i) {
                let k = i - s.boxed.start;
                rows.push_box(&entries(i), self.b[i], self.eps[i], self.lo[k], self.hi[k]);
                i += 1;
            } else if s.unilateral.contains(&i) {
                rows.push_unilateral(&entries(i), self.b[i], self.eps[i]);
                i += 1;
            } else if s.friction.contains(&i) {
                let k = (i - s.friction.start) / 3;
                // A frame-only triplet goes back as one (its blocks renumbered), so that
                // the rows assemble to the same problem, bit for bit.
                if let Some(&f) = self.only_of.get(k).filter(|&&f| f != super::frames::NONE) {
                    let mut frame = self.mf.frames[f as usize].1;
                    for b in frame.blocks.iter_mut().flatten() {
                        *b = block(b.0);
                    }
                    rows.push_friction_frame(
                        self.mu[k],
                        frame,
                        [self.b[i], self.b[i + 1], self.b[i + 2]],
                        [self.eps[i], self.eps[i + 1], self.eps[i + 2]],
                    );
                    i += 3;
                    continue;
                }
                let (e0, e1, e2) = (entries(i), entries(i + 1), entries(i + 2));
                let id = rows.push_friction(
                    self.mu[k],
                    [&e0, &e1, &e2],
                    [self.b[i], self.b[i + 1], self.b[i + 2]],
                    [self.eps[i], self.eps[i + 1], self.eps[i + 2]],
                );
                let frames = &self.mf.frames;
                if let Ok(f) = frames.binary_search_by_key(&(k as u32), |&(t, _)| t) {
                    let mut frame = frames[f].1;
                    for b in frame.blocks.iter_mut().flatten() {
                        *b = block(b.0);
                    }
                    rows.set_contact_frame(id, frame);
                }
                i += 3;
            } else if s.rolling_per_body.contains(&i) {
                let n = PER_BODY_ROWS;
                let e: Vec<_> = (0..n).map(|j| entries(i + j)).collect();
                rows.push_rolling_per_body(
                    self.mu_per_body[(i - s.rolling_per_body.start) / n],
                    std::array::from_fn(|j| &e[j][..]),
                    std::array::from_fn(|j| self.b[i + j]),
                    std::array::from_fn(|j| self.eps[i + j]),
                );
                i += n;
            } else {
                let e: Vec<_> = (0..6).map(|j| entries(i + j)).collect();
                let mut b = [0.0; 6];
                let mut eps = [0.0; 6];
                b.copy_from_slice(&self.b[i..i + 6]);
                eps.copy_from_slice(&self.eps[i..i + 6]);
                rows.push_rolling_friction(
                    self.mu_rolling[(i - s.rolling.start) / 6],
                    [&e[0], &e[1], &e[2], &e[3], &e[4], &e[5]],
                    b,
                    eps,
                );
                i += 6;
            }
        }
    }

    /// Assemble into `out` the sub-problem of the rows `range` with the other rows' impulses
    /// held at `gamma`: `N_RR x = -(r_R + N_RO g_O)`, i.e. the same variables with momentum
    /// `k + D_O g_O`. Used by the two-phase strategy (solve the bilateral rows first, then
    /// everything). `range` must not cut a friction triplet or rolling contact.
    pub fn subproblem(
        &self,
        range: Range<usize>,
        gamma: &[f64],
        out: &mut CcpProblem,
    ) -> Result<()> {
        if range.end > self.n_rows || range.start > range.end {
            return Err(ChronoError::invalid(
                "subproblem range",
                format!("{range:?}"),
                format!("must lie in 0..{}", self.n_rows),
            ));
        }
        for edge in [range.start, range.end] {
            if edge < self.n_rows && self.sections.block_of(edge).0 != edge {
                return Err(ChronoError::invalid(
                    "subproblem range",
                    format!("{range:?}"),
                    "must not cut a friction triplet or rolling contact",
                ));
            }
        }
        let mut rows = ConstraintRows::new();
        self.push_rows(range.clone(), &mut rows);
        self.assemble_with_held(&rows, |i| range.contains(&i), gamma, out)
    }

    /// Assemble into `out` the sub-problem of the rows `rows` (strictly increasing, whole
    /// cone blocks; any subset, not only a contiguous range) with the other rows' impulses
    /// held at `gamma`, as [`subproblem`](Self::subproblem). The sub-problem's row `k` is
    /// this problem's row `rows[k]` (the groups keep their order). Errors name a list that
    /// is not increasing, out of range, or cuts a friction triplet or rolling contact.
    pub fn subproblem_rows(
        &self,
        rows: &[usize],
        gamma: &[f64],
        out: &mut CcpProblem,
    ) -> Result<()> {
        let mut member = vec![false; self.n_rows];
        let mut sub = ConstraintRows::new();
        for (i, len) in self.whole_blocks(rows)? {
            self.push_rows(i..i + len, &mut sub);
            member[i..i + len].fill(true);
        }
        self.assemble_with_held(&sub, |i| member[i], gamma, out)
    }

    /// The cone blocks `(first row, length)` of `rows` (strictly increasing, whole cone
    /// blocks), or an error naming the first entry that breaks that.
    pub(super) fn whole_blocks(&self, rows: &[usize]) -> Result<Vec<(usize, usize)>> {
        let mut out = Vec::new();
        let mut k = 0;
        while k < rows.len() {
            let i = rows[k];
            let bad = |why: &str| {
                Err(ChronoError::invalid(
                    format!("subproblem rows[{k}]"),
                    i,
                    why.to_string(),
                ))
            };
            if i >= self.n_rows || (k > 0 && i <= rows[k - 1]) {
                return bad("rows must be increasing and below the row count");
            }
            let (start, len) = self.sections.block_of(i);
            if start != i || rows.len() < k + len || rows[k + len - 1] != i + len - 1 {
                return bad("must not cut a friction triplet or rolling contact");
            }
            out.push((i, len));
            k += len;
        }
        Ok(out)
    }

    /// Assemble `rows` with the momentum `k + D_O g_O` of the rows `O` not `inside`.
    fn assemble_with_held(
        &self,
        rows: &ConstraintRows,
        inside: impl Fn(usize) -> bool,
        gamma: &[f64],
        out: &mut CcpProblem,
    ) -> Result<()> {
        let mut dv = vec![0.0; self.ndof()];
        for i in (0..self.n_rows).filter(|&i| !inside(i)) {
            if gamma[i] != 0.0 {
                for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                    let (c0, c1) = (self.ent_coef[e] as usize, self.ent_coef[e + 1] as usize);
                    let off = self.ent_off[e] as usize;
                    for (x, c) in dv[off..off + (c1 - c0)]
                        .iter_mut()
                        .zip(&self.coefs()[c0..c1])
                    {
                        *x += gamma[i] * c;
                    }
                }
            }
        }
        let k: Vec<f64> = self.k.iter().zip(&dv).map(|(a, b)| a + b).collect();
        out.assemble(&self.vars, rows, &k)
    }
}

/// The lazily built cone blocks of a [`CcpProblem`]: filled on the first
/// [`CcpProblem::cone_block`] after an assembly, from a buffer kept across assemblies (no
/// allocation per step once warm). Thread-safe: concurrent first calls build once.
#[derive(Debug, Default)]
pub(super) struct ConeBlocks {
    built: std::sync::OnceLock<Vec<f64>>,
    spare: std::sync::Mutex<Vec<f64>>,
}

impl Clone for ConeBlocks {
    fn clone(&self) -> Self {
        let c = Self::default();
        if let Some(v) = self.built.get() {
            let _ = c.built.set(v.clone());
        }
        c
    }
}

impl ConeBlocks {
    /// Forgets the blocks (a new assembly), keeping their buffer.
    pub(super) fn reset(&mut self) {
        if let Some(v) = self.built.take() {
            *self.spare.get_mut().unwrap_or_else(|e| e.into_inner()) = v;
        }
    }

    /// The blocks, built by `fill` into the kept buffer on the first call.
    pub(super) fn get(&self, fill: impl FnOnce(&mut Vec<f64>)) -> &[f64] {
        self.built.get_or_init(|| {
            let mut buf =
                std::mem::take(&mut *self.spare.lock().unwrap_or_else(|e| e.into_inner()));
            fill(&mut buf);
            buf
        })
    }
}
