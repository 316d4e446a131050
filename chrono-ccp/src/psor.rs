//! Projected successive over-relaxation (projected Gauss–Seidel with relaxation).
//!
//! The method of Chrono's `ChSolverPSOR` (Anitescu and Tasora 2010, "An iterative approach
//! for cone complementarity problems for nonsmooth dynamics", Comput. Optim. Appl. 47(2)),
//! i.e. block coordinate descent on `f(g) = 1/2 g'N g + r'g` over `g ∈ Y`, matrix-free: the
//! solver keeps `w = M^-1 D g` up to date, so a row's constraint velocity is
//! `c_i = (N g + r)_i = D_i' w + eps_i g_i + r_i` (equivalently `D_i' v + b_i + eps_i g_i`
//! with `v = M^-1 k + w` the new velocity) at the cost of one sparse row.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, PER_BODY_ROWS, SolveStats, SolverSettings,
    project_friction_cone, project_rolling_cone, project_rolling_per_body_cone, upper_index,
};
use serde::{Deserialize, Serialize};

use crate::dense::{DenseLdl, MAX_BLOCK};
use rayon::prelude::*;

use crate::util::{
    History, check_gamma_len, empty_stats, fill_with, final_stats, sanitize_and_project,
};

/// How the single step size of a friction triplet `(n, u, w)` is chosen.
///
/// A triplet is updated as one block, `g_t <- P_cone(g_t - h c_t)`, with one scalar step `h`
/// for its three rows so that the scaled step keeps the cone's shape (a per-row step would
/// distort the cone and the projection would no longer be the right one).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum TripletStep {
    /// `h = omega / lambda_max(N_tt)`, with `N_tt` the 3x3 diagonal block of `N` of the
    /// triplet (computed once per solve from the rows, eigenvalue in closed form). This is a
    /// projected gradient step on the block with step `<= 1/L_block`, so every triplet update
    /// decreases `f` for `0 < omega < 2` and the sweep is a convergent block coordinate
    /// descent (Tseng 2001). The default.
    #[default]
    MaxEigen,
    /// `h = omega / mean(diag N_tt)`, Chrono's choice (`SchurComplementUpdateConstraints`
    /// averaging). Larger steps, but `lambda_max(N_tt)` can reach `3 mean(diag N_tt)`, so a
    /// triplet update can overshoot and the iteration is not guaranteed to converge.
    Average,
}

/// Options of [`Psor`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PsorOptions {
    /// Relaxation factor `omega` in `(0, 2)`: `g_i <- P(g_i - omega c_i / N_ii)`. `1` is plain
    /// projected Gauss–Seidel (exact minimization along each unilateral/box/bilateral row);
    /// `> 1` over-relaxes. Default `1.0`, as in Chrono.
    pub omega: f64,
    /// Symmetric sweeps: one iteration is a forward sweep followed by a backward sweep (the
    /// symmetric SOR ordering, less biased towards the first rows). Default `false`.
    pub symmetric: bool,
    /// Compute the residual (one `apply_n`, about the cost of one sweep) every this many
    /// iterations; `>= 1`. Default `1`.
    pub check_every: usize,
    /// Step of the friction triplets. Default [`TripletStep::MaxEigen`].
    pub triplet_step: TripletStep,
    /// Relax consecutive bilateral rows that touch the same variable blocks (the rows of
    /// one joint) together, as one block: `g_b <- g_b - omega N_bb^+ c_b` with the dense
    /// block `N_bb` factored once per solve (block Gauss–Seidel). Scalar Gauss–Seidel on
    /// such rows contracts the error by only `1 - det/prod(diag)` per sweep, which is
    /// `~2e-4` for the 5 rows of a revolute joint holding a bob of inertia `4e-5 kg m^2` on a
    /// 1 m arm: thousands of sweeps do not converge and the unconverged joint impulses made
    /// `rigid-pendulum` diverge. The block update is exact for one joint. Default `true`.
    pub block_bilateral: bool,
    /// Sweep in parallel by colours: the units are coloured greedily so that units of one
    /// colour share no variable block; a sweep visits the colours in order and updates
    /// the units of a colour concurrently (rayon), each from the same `w` (Jacobi inside a
    /// colour, Gauss–Seidel across colours: the usual graph-coloured Gauss–Seidel, e.g.
    /// Saad, "Iterative Methods for Sparse Linear Systems", 2nd ed., sec. 12.4). The order
    /// differs from the storage order, so the iterates differ from the sequential sweep;
    /// deterministic for any thread count. Falls back to sequential sweeps if more than 64
    /// colours are needed. Default `false`.
    pub parallel: bool,
}

impl Default for PsorOptions {
    fn default() -> Self {
        Self {
            omega: 1.0,
            symmetric: false,
            check_every: 1,
            triplet_step: TripletStep::MaxEigen,
            block_bilateral: true,
            parallel: false,
        }
    }
}

impl PsorOptions {
    fn validate(&self) {
        assert!(
            self.omega > 0.0 && self.omega < 2.0,
            "PsorOptions.omega = {} must be in (0, 2)",
            self.omega
        );
        assert!(
            self.check_every >= 1,
            "PsorOptions.check_every must be >= 1"
        );
    }
}

/// One unit of a sweep: a scalar row, a group of bilateral rows relaxed together, a friction
/// triplet or a rolling contact (either model).
#[derive(Debug, Clone, Copy)]
enum Unit {
    /// Bilateral, box or unilateral row.
    Row(usize),
    /// Bilateral rows `start..start + len` with the same blocks; factor at `factor`.
    Bilateral {
        start: usize,
        len: usize,
        factor: usize,
    },
    /// Friction triplet starting at this row.
    Triplet(usize),
    /// Rolling contact (6 rows) starting at this row.
    Rolling(usize),
    /// Per-body rolling contact ([`PER_BODY_ROWS`] rows) starting at this row.
    RollingPerBody(usize),
}

/// Projected SOR solver of the CCP `Y ∋ g ⊥ -(N g + r) ∈ Y°`.
///
/// One iteration sweeps the units in storage order — bilateral rows, box rows, unilateral
/// rows, friction triplets, rolling contacts — (then backwards, if
/// [`PsorOptions::symmetric`]). A scalar row `i` does `g_i <- P_i(g_i - omega c_i / N_ii)`
/// with `c_i = (N g + r)_i` (clamped to `[lo, hi]` for box rows, to `>= 0` for unilateral
/// rows, unchanged for bilateral rows); consecutive bilateral rows on the same blocks (a
/// joint) are relaxed as one block `g_b <- g_b - omega N_bb^+ c_b`
/// ([`PsorOptions::block_bilateral`]); a friction triplet or rolling contact does a scalar
/// step for all its rows ([`TripletStep`]; for rolling contacts `1 / lambda_max` bounded by
/// Gershgorin's theorem) and the joint cone projection. Each change of `g` is applied at
/// once to `w = M^-1 D g` (`row_add_minv`), so later rows see it (Gauss–Seidel).
///
/// Stopping: the common residual [`CcpProblem::residual`] (m/s, RMS of the diagonally scaled
/// projected-gradient step) every [`PsorOptions::check_every`] iterations, against
/// [`SolverSettings::tolerance`]. The gradient for it is `D'w + E g + r` (the row half of an
/// `apply_n`, as `w` is kept current). The iterate with the lowest residual seen is returned.
///
/// Differences from Chrono's `ChSolverPSOR` (Anitescu and Tasora 2010): no `sharpness`
/// blend; the residual is the common one (Chrono uses the largest violation); friction
/// triplets use a step that guarantees descent ([`TripletStep::MaxEigen`]) unless asked
/// otherwise; joints are relaxed as blocks; a non-finite iterate stops the solve and
/// returns the best finite one.
///
/// Gauss–Seidel is inherently sequential (each row reads the velocity the previous rows just
/// changed), so the sweep runs on one thread; the setup and the residual checks use the
/// parallel problem operations. A graph-coloured parallel PSOR (rows of one colour share no
/// variable block and can be relaxed concurrently) is future work. The result is bit-identical
/// for any rayon thread count.
///
/// Cost accounting ([`SolveStats::apply_n`]): a sweep counts as one `apply_n` (it streams the
/// Jacobian once in each direction), a residual check as one more.
#[derive(Debug, Clone, Default)]
pub struct Psor {
    settings: SolverSettings,
    options: PsorOptions,
    work: CcpWork,
    /// `M^-1 D g`, ndof.
    w: Vec<f64>,
    /// Step per row (`omega / N_ii`; per cone block, one value on its rows).
    step: Vec<f64>,
    grad: Vec<f64>,
    best: Vec<f64>,
    units: Vec<Unit>,
    /// Factored dense blocks of the bilateral groups.
    factors: Vec<f64>,
    /// The colouring, when sweeping in parallel.
    colouring: Option<Colouring>,
    /// Updates of the units of one colour (parallel sweep).
    deltas: Vec<UnitUpdate>,
}

impl Psor {
    /// A solver with the common settings `settings` and default [`PsorOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// Set the relaxation factor `omega` (see [`PsorOptions::omega`]).
    ///
    /// # Panics
    /// If `omega` is not in `(0, 2)`.
    pub fn with_omega(mut self, omega: f64) -> Self {
        self.options.omega = omega;
        self.options.validate();
        self
    }

    /// Use symmetric (forward + backward) sweeps.
    pub fn with_symmetric(mut self, symmetric: bool) -> Self {
        self.options.symmetric = symmetric;
        self
    }

    /// Check the residual every `check_every` iterations.
    ///
    /// # Panics
    /// If `check_every == 0`.
    pub fn with_check_every(mut self, check_every: usize) -> Self {
        self.options.check_every = check_every;
        self.options.validate();
        self
    }

    /// Choose the friction-triplet step (see [`TripletStep`]).
    pub fn with_triplet_step(mut self, triplet_step: TripletStep) -> Self {
        self.options.triplet_step = triplet_step;
        self
    }

    /// Relax the rows of a joint as one block or not (see [`PsorOptions::block_bilateral`]).
    pub fn with_block_bilateral(mut self, block_bilateral: bool) -> Self {
        self.options.block_bilateral = block_bilateral;
        self
    }

    /// Sweep in parallel by colours or not (see [`PsorOptions::parallel`]).
    pub fn with_parallel(mut self, parallel: bool) -> Self {
        self.options.parallel = parallel;
        self
    }

    settings_builders!();

    /// Replace all PSOR-specific options.
    ///
    /// # Panics
    /// If an option is out of range (see [`PsorOptions`]).
    pub fn with_options(mut self, options: PsorOptions) -> Self {
        options.validate();
        self.options = options;
        self
    }

    /// The PSOR-specific options.
    pub fn options(&self) -> &PsorOptions {
        &self.options
    }

    /// The PSOR-specific options, mutable (checked at the start of every solve).
    pub fn options_mut(&mut self) -> &mut PsorOptions {
        &mut self.options
    }

    /// Build the units of a sweep, their steps and the bilateral block factors.
    fn setup(&mut self, problem: &CcpProblem) {
        let omega = self.options.omega;
        let diag = problem.diag();
        let s = problem.sections().clone();
        let inv = |d: f64| if d > 0.0 { omega / d } else { 0.0 };
        self.units.clear();
        self.factors.clear();
        let mut i = s.bilateral.start;
        while i < s.bilateral.end {
            let mut len = 1;
            if self.options.block_bilateral {
                while i + len < s.bilateral.end
                    && len < MAX_BLOCK
                    && problem.row_blocks(i + len).eq(problem.row_blocks(i))
                {
                    len += 1;
                }
            }
            if len == 1 {
                self.units.push(Unit::Row(i));
            } else {
                let factor = self.factors.len();
                for a in 0..len {
                    for b in 0..len {
                        self.factors.push(problem.n_entry(i + a, i + b));
                    }
                }
                DenseLdl::factor(&mut self.factors[factor..], len);
                self.units.push(Unit::Bilateral {
                    start: i,
                    len,
                    factor,
                });
            }
            i += len;
        }
        for i in s.boxed.start..s.unilateral.end {
            self.units.push(Unit::Row(i));
        }
        for i in 0..s.friction.start {
            self.step[i] = inv(diag[i]);
        }
        for t in s.friction.clone().step_by(3) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => (diag[t] + diag[t + 1] + diag[t + 2]) / 3.0,
                TripletStep::MaxEigen => {
                    let b = problem.cone_block(t).expect("a triplet");
                    sym3_max_eigen(&[[b[0], b[1], b[2]], [b[1], b[3], b[4]], [b[2], b[4], b[5]]])
                }
            };
            self.step[t..t + 3].fill(inv(lambda));
            self.units.push(Unit::Triplet(t));
        }
        for t in s.rolling.clone().step_by(6) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => diag[t..t + 6].iter().sum::<f64>() / 6.0,
                TripletStep::MaxEigen => {
                    let b = problem.cone_block(t).expect("a rolling contact");
                    gershgorin_bound(b, 6)
                }
            };
            self.step[t..t + 6].fill(inv(lambda));
            self.units.push(Unit::Rolling(t));
        }
        let n = PER_BODY_ROWS;
        for t in s.rolling_per_body.clone().step_by(n) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => diag[t..t + n].iter().sum::<f64>() / n as f64,
                TripletStep::MaxEigen => {
                    let b = problem.cone_block(t).expect("a per-body rolling contact");
                    gershgorin_bound(b, n)
                }
            };
            self.step[t..t + n].fill(inv(lambda));
            self.units.push(Unit::RollingPerBody(t));
        }
        self.colouring = if self.options.parallel {
            self.colour(problem)
        } else {
            None
        };
    }

    /// One sweep over all units, forwards or backwards.
    fn sweep(&mut self, problem: &CcpProblem, g: &mut [f64], forward: bool) {
        if self.colouring.is_some() {
            return self.sweep_coloured(problem, g, forward);
        }
        let data = SweepData {
            problem,
            step: &self.step,
            factors: &self.factors,
            omega: self.options.omega,
        };
        let n = self.units.len();
        for k in 0..n {
            let unit = self.units[if forward { k } else { n - 1 - k }];
            let d = unit_update(&data, unit, g, &self.w);
            for j in 0..d.len {
                let i = d.start + j;
                let dg = d.new[j] - g[i];
                if dg != 0.0 {
                    problem.row_add_minv(i, dg, &mut self.w);
                    g[i] = d.new[j];
                }
            }
        }
    }

    /// One coloured sweep: the colours in order (reversed backwards); within a colour every
    /// unit is updated from the same `w` in parallel (they share no variable block), then
    /// `g` is written and `w` updated block by block in parallel.
    fn sweep_coloured(&mut self, problem: &CcpProblem, g: &mut [f64], forward: bool) {
        let col = self.colouring.as_ref().expect("coloured sweep");
        let data = SweepData {
            problem,
            step: &self.step,
            factors: &self.factors,
            omega: self.options.omega,
        };
        let nc = col.ptr.len() - 1;
        let nb = problem.variables().len();
        for k in 0..nc {
            let c = if forward { k } else { nc - 1 - k };
            let units_c = &col.order[col.ptr[c]..col.ptr[c + 1]];
            let (units, w) = (&self.units, &self.w);
            let gr: &[f64] = g;
            let update = |&u: &u32| unit_update(&data, units[u as usize], gr, w);
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
    fn colour(&self, problem: &CcpProblem) -> Option<Colouring> {
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
struct Colouring {
    /// Units of colour `c`: `order[ptr[c]..ptr[c + 1]]` (storage order within a colour).
    ptr: Vec<usize>,
    order: Vec<u32>,
    /// For colour `c` and block `b`, the index (within the colour) of the unit touching it,
    /// or `u32::MAX`: `block_unit[c * n_blocks + b]`.
    block_unit: Vec<u32>,
}

impl Unit {
    /// The first row and the number of rows.
    fn rows(self) -> (usize, usize) {
        match self {
            Unit::Row(i) => (i, 1),
            Unit::Bilateral { start, len, .. } => (start, len),
            Unit::Triplet(t) => (t, 3),
            Unit::Rolling(t) => (t, 6),
            Unit::RollingPerBody(t) => (t, PER_BODY_ROWS),
        }
    }
}

/// What a unit update reads besides `g` and `w`.
struct SweepData<'a> {
    problem: &'a CcpProblem,
    step: &'a [f64],
    factors: &'a [f64],
    omega: f64,
}

/// The new values of a unit's rows `start..start + len`.
#[derive(Debug, Clone, Copy)]
struct UnitUpdate {
    start: usize,
    len: usize,
    new: [f64; MAX_BLOCK],
}

/// The constraint velocity `c_i = D_i'w + eps_i g_i + r_i` of row `i`.
#[inline]
fn velocity(problem: &CcpProblem, i: usize, g: &[f64], w: &[f64]) -> f64 {
    problem.row_dot(i, w) + problem.eps()[i] * g[i] + problem.r()[i]
}

/// The relaxation of one unit from the current `g` and `w = M^-1 D g` (pure: the caller
/// writes the new values and updates `w`).
#[inline]
fn unit_update(d: &SweepData, unit: Unit, g: &[f64], w: &[f64]) -> UnitUpdate {
    let problem = d.problem;
    let s = problem.sections();
    let mut new = [0.0; MAX_BLOCK];
    let (start, len) = unit.rows();
    match unit {
        Unit::Row(i) => {
            let z = g[i] - d.step[i] * velocity(problem, i, g, w);
            new[0] = if i < s.boxed.start {
                z
            } else if i < s.unilateral.start {
                let (lo, hi) = problem.box_bounds();
                let k = i - s.boxed.start;
                z.clamp(lo[k], hi[k])
            } else {
                z.max(0.0)
            };
        }
        Unit::Bilateral { start, len, factor } => {
            let mut c = [0.0; MAX_BLOCK];
            for j in 0..len {
                c[j] = velocity(problem, start + j, g, w);
            }
            DenseLdl::solve(&d.factors[factor..factor + len * len], len, &mut c[..len]);
            for j in 0..len {
                new[j] = g[start + j] - d.omega * c[j];
            }
        }
        Unit::Triplet(t) | Unit::Rolling(t) | Unit::RollingPerBody(t) => {
            let h = d.step[t];
            for j in 0..len {
                new[j] = g[t + j] - h * velocity(problem, t + j, g, w);
            }
            match unit {
                Unit::Triplet(_) => {
                    let mu = problem.friction_mu()[(t - s.friction.start) / 3];
                    project_friction_cone(mu, &mut new[..3]);
                }
                Unit::Rolling(_) => {
                    let mu = problem.rolling_mu()[(t - s.rolling.start) / 6];
                    project_rolling_cone(mu, &mut new[..6]);
                }
                _ => {
                    let c = (t - s.rolling_per_body.start) / PER_BODY_ROWS;
                    let mu = problem.rolling_per_body_mu()[c];
                    project_rolling_per_body_cone(mu, &mut new[..PER_BODY_ROWS]);
                }
            }
        }
    }
    UnitUpdate { start, len, new }
}

/// Gershgorin's upper bound on the largest eigenvalue of a symmetric `n x n` matrix given
/// as its row-major upper triangle: `max_i sum_j |a_ij|`.
fn gershgorin_bound(upper: &[f64], n: usize) -> f64 {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| upper[upper_index(n, i.min(j), i.max(j))].abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// The largest eigenvalue of a symmetric 3x3 matrix, in closed form (trigonometric solution of
/// the characteristic cubic; Smith 1961, "Eigenvalues of a symmetric 3x3 matrix", CACM 4(4)).
pub(crate) fn sym3_max_eigen(a: &[[f64; 3]; 3]) -> f64 {
    let p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if p1 == 0.0 {
        return a[0][0].max(a[1][1]).max(a[2][2]);
    }
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let (b00, b11, b22) = (a[0][0] - q, a[1][1] - q, a[2][2] - q);
    let p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let det = b00 * (b11 * b22 - a[1][2] * a[1][2]) - a[0][1] * (a[0][1] * b22 - a[1][2] * a[0][2])
        + a[0][2] * (a[0][1] * a[1][2] - b11 * a[0][2]);
    let half_det = (det / (p * p * p) / 2.0).clamp(-1.0, 1.0);
    let phi = half_det.acos() / 3.0;
    q + 2.0 * p * phi.cos()
}

impl CcpSolver for Psor {
    solver_accessors!("psor");

    /// Solve by projected SOR; see [`Psor`]. `gamma` is the warm start (non-finite entries
    /// are replaced by 0, then it is projected onto `Y`) and receives the solution.
    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        self.options.validate();
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        let (tol, max_it) = (self.settings.tolerance, self.settings.max_iterations);
        let mut history = History::new(self.settings.record_history, max_it);
        self.work.resize(problem);
        self.w.resize(problem.ndof(), 0.0);
        for v in [&mut self.step, &mut self.grad, &mut self.best] {
            v.resize(m, 0.0);
        }

        sanitize_and_project(problem, gamma);
        // the cone blocks are built lazily: once here, before the (parallel) sweeps
        problem.prepare_cone_blocks();
        self.setup(problem);
        problem.minv_d(gamma, &mut self.w);
        problem.gradient(gamma, &mut self.grad, &mut self.work);
        let mut n_apply = 1;
        let mut best_res = problem.residual(gamma, &self.grad, &mut self.work);
        self.best.copy_from_slice(gamma);
        // Is `grad` the gradient of `best`?
        let mut grad_is_best = true;
        let mut iterations = 0;
        if !best_res.is_finite() || best_res <= tol {
            return final_stats(
                problem,
                gamma,
                &self.grad,
                &mut self.work,
                0,
                n_apply,
                tol,
                history.into_records(),
            );
        }

        for it in 1..=max_it {
            iterations = it;
            self.sweep(problem, gamma, true);
            n_apply += 1;
            if self.options.symmetric {
                self.sweep(problem, gamma, false);
                n_apply += 1;
            }
            if it % self.options.check_every != 0 && it != max_it {
                continue;
            }
            // c = D'w + E g + r with the current w = M^-1 D g.
            let (w, g, eps, r) = (&self.w, &*gamma, problem.eps(), problem.r());
            fill_with(&mut self.grad, |i| {
                problem.row_dot(i, w) + eps[i] * g[i] + r[i]
            });
            n_apply += 1;
            let res = problem.residual(gamma, &self.grad, &mut self.work);
            history.push(it, res, n_apply, || {
                problem.objective_from_gradient(gamma, &self.grad, &mut self.work)
            });
            let finite = res.is_finite() && self.w.iter().all(|x| x.is_finite());
            if !finite {
                grad_is_best = false;
                break;
            }
            grad_is_best = res < best_res;
            if grad_is_best {
                best_res = res;
                self.best.copy_from_slice(gamma);
            }
            if res <= tol {
                break;
            }
        }
        gamma.copy_from_slice(&self.best);
        if !grad_is_best {
            problem.gradient(gamma, &mut self.grad, &mut self.work);
            n_apply += 1;
        }
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            iterations,
            n_apply,
            tol,
            history.into_records(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_eigen_of_known_matrices() {
        let d = [[2.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(sym3_max_eigen(&d), 5.0);
        // all-ones: eigenvalues 3, 0, 0
        let ones = [[1.0; 3]; 3];
        assert!((sym3_max_eigen(&ones) - 3.0).abs() < 1e-12);
        // [[2,1,0],[1,2,0],[0,0,1]]: eigenvalues 3, 1, 1
        let a = [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]];
        assert!((sym3_max_eigen(&a) - 3.0).abs() < 1e-12);
        // tridiagonal [[2,-1,0],[-1,2,-1],[0,-1,2]]: max eigenvalue 2 + sqrt(2)
        let t = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]];
        assert!((sym3_max_eigen(&t) - (2.0 + 2f64.sqrt())).abs() < 1e-12);
    }

    #[test]
    fn gershgorin_bounds_the_spectrum() {
        // [[2,-1,0],[-1,2,-1],[0,-1,2]] as an upper triangle: bound 4 >= 2 + sqrt 2.
        let upper = [2.0, -1.0, 0.0, 2.0, -1.0, 2.0];
        assert_eq!(gershgorin_bound(&upper, 3), 4.0);
    }
}
