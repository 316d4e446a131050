//! The assembled cone complementarity problem.

use std::ops::Range;

use rayon::prelude::*;

use super::cone::{project_box, project_friction_cone, project_unilateral};
use super::reduce::{self, sum_by};
use super::rows::{ConstraintRows, RowGroup, RowId};
use super::variables::{BlockId, Variables};
use crate::error::{ChronoError, Result};

/// Below this many rows, row-wise loops run on the calling thread.
const PAR_MIN_ROWS: usize = 4096;

/// The global row ranges of the four groups, in this order.
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
}

/// Scratch space for the operations of a [`CcpProblem`]; a solver owns one and reuses it,
/// so iterations allocate nothing.
#[derive(Debug, Clone, Default)]
pub struct CcpWork {
    /// A velocity-sized vector (`ndof`).
    pub v: Vec<f64>,
    /// Partial sums of deterministic reductions.
    pub partials: Vec<f64>,
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
    }
}

/// The CCP of one step:
///
/// ```text
/// find g:  Y ∋ g ⊥ -(N g + r) ∈ Y°,   N = D'M^-1 D + E,   r = b + D'M^-1 k
/// ```
///
/// equivalently `min f(g) = 1/2 g'N g + r'g` over `g ∈ Y` (the product of the groups'
/// sets: free, boxes, half-lines, Coulomb cones). `k = M v + h f` is the momentum before
/// constraints; the new velocity is `v+ = M^-1 (k + D g)` ([`CcpProblem::velocities`]), so
/// `N g + r = D' v+ + b + E g` is the constraint velocity.
///
/// `N` is never formed: [`apply_n`](Self::apply_n) does `D' (M^-1 D g) + E g` with `M^-1 D`
/// cached per entry. Row-wise and block-wise loops are rayon-parallel for large problems and
/// every reduction is done in a fixed order ([`reduce`](super::reduce)), so results are
/// bit-identical for any thread count.
#[derive(Debug, Clone, Default)]
pub struct CcpProblem {
    vars: Variables,
    n_rows: usize,
    // Jacobian, CSR by row: entries (row, block), coefficients per entry.
    row_ptr: Vec<u32>,
    ent_row: Vec<u32>,
    ent_block: Vec<u32>,
    ent_off: Vec<u32>,
    ent_coef: Vec<u32>,
    coefs: Vec<f64>,
    minv: Vec<f64>,
    // Transpose index: for each block, its entries in row order.
    tr_ptr: Vec<u32>,
    tr_ent: Vec<u32>,
    b: Vec<f64>,
    eps: Vec<f64>,
    diag: Vec<f64>,
    r: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    mu: Vec<f64>,
    v_free: Vec<f64>,
    sections: Sections,
    group_start: [usize; 4],
}

const GROUP_ORDER: [RowGroup; 4] = [
    RowGroup::Bilateral,
    RowGroup::Box,
    RowGroup::Unilateral,
    RowGroup::Friction,
];

fn group_name(g: RowGroup) -> &'static str {
    match g {
        RowGroup::Bilateral => "bilateral",
        RowGroup::Box => "box",
        RowGroup::Unilateral => "unilateral",
        RowGroup::Friction => "friction",
    }
}

impl CcpProblem {
    /// An empty problem (assemble it with [`assemble`](Self::assemble)).
    pub fn new() -> Self {
        Self::default()
    }

    /// Assemble from the step's variables, rows and momentum `k = M v + h f` (length `ndof`).
    /// Reuses this problem's buffers. Rejects malformed input (a row naming a block that does
    /// not exist, coefficient counts that do not match a block, non-finite numbers, negative
    /// compliance or friction, `lo > hi`) with an error naming the row.
    pub fn assemble(&mut self, vars: &Variables, rows: &ConstraintRows, k: &[f64]) -> Result<()> {
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
        self.vars.clone_from(vars);
        let nblocks = vars.len();
        for v in [
            &mut self.row_ptr,
            &mut self.ent_row,
            &mut self.ent_block,
            &mut self.ent_off,
            &mut self.ent_coef,
        ] {
            v.clear();
        }
        for v in [
            &mut self.coefs,
            &mut self.minv,
            &mut self.b,
            &mut self.eps,
            &mut self.lo,
            &mut self.hi,
            &mut self.mu,
        ] {
            v.clear();
        }
        self.row_ptr.push(0);

        let mut row = 0usize;
        for (gi, &group) in GROUP_ORDER.iter().enumerate() {
            let g = &rows.groups[group as usize];
            self.group_start[gi] = row;
            let name = group_name(group);
            for i in 0..g.n_rows() {
                let (e0, e1) = (g.row_ptr[i] as usize, g.row_ptr[i + 1] as usize);
                for e in e0..e1 {
                    let blk = g.ent_block[e] as usize;
                    if blk >= nblocks {
                        return Err(ChronoError::UnknownHandle {
                            kind: "variable block",
                            index: blk,
                            field: format!("rows.{name}[{i}]"),
                        });
                    }
                    let nd = vars.block_ndof(BlockId(blk as u32));
                    let c0 = g.ent_coef[e] as usize;
                    let c1 = if e + 1 < g.ent_coef.len() {
                        g.ent_coef[e + 1] as usize
                    } else {
                        g.coefs.len()
                    };
                    if c1 - c0 != nd {
                        return Err(ChronoError::invalid(
                            format!("rows.{name}[{i}].coefs.len()"),
                            c1 - c0,
                            format!("must equal the ndof ({nd}) of block {blk}"),
                        ));
                    }
                    let c = &g.coefs[c0..c1];
                    if let Some(j) = c.iter().position(|x| !x.is_finite()) {
                        return Err(ChronoError::invalid(
                            format!("rows.{name}[{i}].coefs[{j}]"),
                            c[j],
                            "must be finite",
                        ));
                    }
                    self.ent_row.push(row as u32);
                    self.ent_block.push(blk as u32);
                    self.ent_off.push(vars.offset(BlockId(blk as u32)) as u32);
                    self.ent_coef.push(self.coefs.len() as u32);
                    self.coefs.extend_from_slice(c);
                    let start = self.minv.len();
                    self.minv.resize(start + nd, 0.0);
                    vars.mass(BlockId(blk as u32))
                        .apply_inverse(c, &mut self.minv[start..]);
                }
                self.row_ptr.push(self.ent_row.len() as u32);
                if !g.b[i].is_finite() {
                    return Err(ChronoError::invalid(
                        format!("rows.{name}[{i}].b"),
                        g.b[i],
                        "must be finite",
                    ));
                }
                if !(g.eps[i].is_finite() && g.eps[i] >= 0.0) {
                    return Err(ChronoError::invalid(
                        format!("rows.{name}[{i}].eps"),
                        g.eps[i],
                        "must be finite and >= 0",
                    ));
                }
                self.b.push(g.b[i]);
                self.eps.push(g.eps[i]);
                row += 1;
            }
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
                        return Err(ChronoError::invalid(
                            format!("rows.friction[{i}].mu"),
                            g.mu[i],
                            "must be finite and >= 0",
                        ));
                    }
                    self.mu.extend_from_slice(&g.mu);
                }
                _ => {}
            }
        }
        self.n_rows = row;
        let gs = self.group_start;
        self.sections = Sections {
            bilateral: gs[0]..gs[1],
            boxed: gs[1]..gs[2],
            unilateral: gs[2]..gs[3],
            friction: gs[3]..row,
        };

        // Transpose index (counting sort of entries by block, stable: row order kept).
        self.tr_ptr.clear();
        self.tr_ptr.resize(nblocks + 1, 0);
        for &blk in &self.ent_block {
            self.tr_ptr[blk as usize + 1] += 1;
        }
        for i in 0..nblocks {
            self.tr_ptr[i + 1] += self.tr_ptr[i];
        }
        self.tr_ent.clear();
        self.tr_ent.resize(self.ent_block.len(), 0);
        {
            // cursor per block, reusing `diag` storage would alias; use a local pass instead.
            let mut cursor: Vec<u32> = self.tr_ptr[..nblocks].to_vec();
            for (e, &blk) in self.ent_block.iter().enumerate() {
                let c = &mut cursor[blk as usize];
                self.tr_ent[*c as usize] = e as u32;
                *c += 1;
            }
        }

        // Diagonal of N, free velocity, r.
        self.diag.clear();
        self.diag.resize(self.n_rows, 0.0);
        for i in 0..self.n_rows {
            let mut d = self.eps[i];
            for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
                let c0 = self.ent_coef[e] as usize;
                let nd = self.entry_ndof(e);
                for j in 0..nd {
                    d += self.coefs[c0 + j] * self.minv[c0 + j];
                }
            }
            self.diag[i] = d;
        }
        self.v_free.resize(vars.ndof(), 0.0);
        vars.apply_inverse(k, &mut self.v_free);
        self.r.clear();
        self.r.resize(self.n_rows, 0.0);
        for i in 0..self.n_rows {
            self.r[i] = self.b[i] + self.row_dot(i, &self.v_free);
        }
        Ok(())
    }

    #[inline]
    fn entry_ndof(&self, e: usize) -> usize {
        self.vars.block_ndof(BlockId(self.ent_block[e]))
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

    /// The variables this problem was assembled from.
    pub fn variables(&self) -> &Variables {
        &self.vars
    }

    /// The row ranges of the groups.
    #[inline]
    pub fn sections(&self) -> &Sections {
        &self.sections
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

    /// The right-hand side `r = b + D'M^-1 k`.
    #[inline]
    pub fn r(&self) -> &[f64] {
        &self.r
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

    /// `D_i' v` for one row.
    #[inline]
    pub fn row_dot(&self, i: usize, v: &[f64]) -> f64 {
        let mut s = 0.0;
        for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let c0 = self.ent_coef[e] as usize;
            let off = self.ent_off[e] as usize;
            let nd = self.entry_ndof(e);
            let c = &self.coefs[c0..c0 + nd];
            let x = &v[off..off + nd];
            for j in 0..nd {
                s += c[j] * x[j];
            }
        }
        s
    }

    /// `v += s M^-1 D_i` for one row (the velocity change caused by an impulse `s` on row `i`).
    #[inline]
    pub fn row_add_minv(&self, i: usize, s: f64, v: &mut [f64]) {
        for e in self.row_ptr[i] as usize..self.row_ptr[i + 1] as usize {
            let c0 = self.ent_coef[e] as usize;
            let off = self.ent_off[e] as usize;
            let nd = self.entry_ndof(e);
            let c = &self.minv[c0..c0 + nd];
            let x = &mut v[off..off + nd];
            for j in 0..nd {
                x[j] += s * c[j];
            }
        }
    }

    /// `v = M^-1 D g` (length `ndof`), gathered block by block (parallel for large systems).
    pub fn minv_d(&self, gamma: &[f64], v: &mut [f64]) {
        assert_eq!(gamma.len(), self.n_rows);
        assert_eq!(v.len(), self.ndof());
        let gather = |block: usize, out: &mut [f64]| {
            out.fill(0.0);
            let nd = out.len();
            for t in self.tr_ptr[block] as usize..self.tr_ptr[block + 1] as usize {
                let e = self.tr_ent[t] as usize;
                let g = gamma[self.ent_row[e] as usize];
                if g != 0.0 {
                    let c0 = self.ent_coef[e] as usize;
                    let c = &self.minv[c0..c0 + nd];
                    for j in 0..nd {
                        out[j] += g * c[j];
                    }
                }
            }
        };
        let par = self.ndof() >= 8192;
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

    /// `out = N g = D'(M^-1 D g) + E g`. `work` must come from [`CcpWork::for_problem`].
    pub fn apply_n(&self, gamma: &[f64], out: &mut [f64], work: &mut CcpWork) {
        assert_eq!(out.len(), self.n_rows);
        work.resize(self);
        self.minv_d(gamma, &mut work.v);
        let v = &work.v;
        let f = |(i, o): (usize, &mut f64)| *o = self.row_dot(i, v) + self.eps[i] * gamma[i];
        if self.n_rows >= PAR_MIN_ROWS {
            out.par_iter_mut().enumerate().for_each(f);
        } else {
            out.iter_mut().enumerate().for_each(f);
        }
    }

    /// `out = N g + r`, the gradient of the objective (= the constraint velocities).
    pub fn gradient(&self, gamma: &[f64], out: &mut [f64], work: &mut CcpWork) {
        self.apply_n(gamma, out, work);
        let r = &self.r;
        if self.n_rows >= PAR_MIN_ROWS {
            out.par_iter_mut()
                .zip(r.par_iter())
                .for_each(|(o, ri)| *o += ri);
        } else {
            out.iter_mut().zip(r).for_each(|(o, ri)| *o += ri);
        }
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
    /// rows to `>= 0`, friction triplets onto their Coulomb cones.
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
            fr.par_chunks_mut(3)
                .zip(self.mu.par_iter())
                .for_each(|(g, &mu)| project_friction_cone(mu, g));
        } else {
            fr.chunks_mut(3)
                .zip(&self.mu)
                .for_each(|(g, &mu)| project_friction_cone(mu, g));
        }
    }

    /// The step scale of row `i` used by the residual: `1 / diag(N)_i`, averaged over the three
    /// rows of a friction triplet so that the scaled step keeps the cone's shape.
    #[inline]
    pub fn residual_scale(&self, i: usize) -> f64 {
        let fr = &self.sections.friction;
        let d = if fr.contains(&i) {
            let t = fr.start + 3 * ((i - fr.start) / 3);
            (self.diag[t] + self.diag[t + 1] + self.diag[t + 2]) / 3.0
        } else {
            self.diag[i]
        };
        if d > 0.0 { 1.0 / d } else { 0.0 }
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
    /// problem sizes. Rows with a zero diagonal contribute their gradient (free rows) or its
    /// projection.
    pub fn residual(&self, gamma: &[f64], grad: &[f64], work: &mut CcpWork) -> f64 {
        if self.n_rows == 0 {
            return 0.0;
        }
        let s = &self.sections;
        let (lo, hi) = (&self.lo, &self.hi);
        let term = |i: usize| -> f64 {
            let sc = self.residual_scale(i);
            let rho = if s.bilateral.contains(&i) {
                grad[i]
            } else if s.boxed.contains(&i) {
                let k = i - s.boxed.start;
                if sc > 0.0 {
                    (gamma[i] - project_box(gamma[i] - sc * grad[i], lo[k], hi[k])) / sc
                } else {
                    0.0
                }
            } else if s.unilateral.contains(&i) {
                if sc > 0.0 {
                    (gamma[i] - project_unilateral(gamma[i] - sc * grad[i])) / sc
                } else {
                    grad[i].min(0.0)
                }
            } else {
                let t = s.friction.start + 3 * ((i - s.friction.start) / 3);
                let j = i - t;
                if sc > 0.0 {
                    let mut z = [
                        gamma[t] - sc * grad[t],
                        gamma[t + 1] - sc * grad[t + 1],
                        gamma[t + 2] - sc * grad[t + 2],
                    ];
                    project_friction_cone(self.mu[(t - s.friction.start) / 3], &mut z);
                    (gamma[i] - z[j]) / sc
                } else {
                    0.0
                }
            };
            rho * rho
        };
        (sum_by(self.n_rows, &mut work.partials, term) / self.n_rows as f64).sqrt()
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
