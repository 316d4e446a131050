//! Projected successive over-relaxation (projected Gauss–Seidel with relaxation).
//!
//! The method of Chrono's `ChSolverPSOR` (Anitescu and Tasora 2010, "An iterative approach
//! for cone complementarity problems for nonsmooth dynamics", Comput. Optim. Appl. 47(2)),
//! i.e. block coordinate descent on `f(g) = 1/2 g'N g + r'g` over `g ∈ Y`, matrix-free: the
//! solver keeps `w = M^-1 D g` up to date, so a row's constraint velocity is
//! `c_i = (N g + r)_i = D_i' w + eps_i g_i + r_i` (equivalently `D_i' v + b_i + eps_i g_i`
//! with `v = M^-1 k + w` the new velocity) at the cost of one sparse row.

use chrono_core::descriptor::{
    CcpProblem, CcpSolver, CcpWork, FusedTriplet, PER_BODY_ROWS, SolveStats, SolverSettings,
    SphereContact,
};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::dense::{DenseLdl, MAX_BLOCK};

mod colour;
mod momentum;
mod parts;
mod unit;
use colour::Colouring;
use parts::{Partition, Shared};
pub(crate) use unit::sym3_max_eigen;
use unit::{
    Setup, SweepData, UnitUpdate, Vel, apply_update, as_triplet, current, diagonal_cone_scale,
    gershgorin_bound, triplet, unit_update,
};

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
    /// The exact minimizer of `f` over the triplet's cone where its block is
    /// `N_tt = diag(a, b, b)` (a sphere's contact with a sphere or a fixed body: the
    /// contact arm is along the normal, so the normal and tangential rows decouple and both
    /// tangents see the same mass): the unconstrained step `z = g - omega N_tt^-1 c`
    /// projected onto the cone in the metric of `N_tt`, i.e. in the coordinates
    /// `(z_n, k z_u, k z_w)` with `k = sqrt(b / a)` onto the cone of friction `mu k`
    /// (Euclidean), scaled back. With `omega = 1` this is block coordinate descent with
    /// exact block minimization. Other blocks take [`TripletStep::MaxEigen`]'s step.
    Exact,
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
    /// Sweep in parallel by parts (see `psor/parts.rs`): the variable blocks cut into one
    /// contiguous range per rayon thread, each part's own units swept in storage order on
    /// its thread, then the units that straddle two parts on one thread. Each part is plain
    /// Gauss–Seidel (unlike [`parallel`](Self::parallel)'s colours); the iterates depend on
    /// the thread count (bit-reproducible for a given count). Problems with fewer than two
    /// parts' worth of units (2 048 each) sweep sequentially. Takes precedence over
    /// `parallel`. Default `false`.
    pub partitioned: bool,
    /// Nesterov momentum over the iterations: after the sweeps of iteration `k` give
    /// `T(y_k)`, `y_{k+1} = T(y_k) + beta_k (T(y_k) - T(y_{k-1}))` with
    /// `beta_k = (k - 1) / (k + 2)`, restarted (`k = 1`) when the sweep's step
    /// `T(y_k) - y_k` points against the momentum `T(y_k) - T(y_{k-1})` (the gradient-free
    /// restart of O'Donoghue and Candès 2015, "Adaptive restart for accelerated gradient
    /// schemes", Found. Comput. Math. 15). A Gauss–Seidel sweep is not a gradient step, so
    /// this is the accelerated-projection heuristic without its rate guarantee: a residual
    /// check above 1e3 times the best one, or three checks in a row without a new best,
    /// return to the best iterate with plain sweeps until a check improves on it (a random
    /// problem with rolling cones diverged to 1e153 m/s without the first; another
    /// wandered between 2e-3 and 0.2 m/s for 200 000 sweeps without the second), and the
    /// solve returns the best iterate seen. `y` is not projected (as in FISTA): each unit
    /// of the next sweep projects its own update, so the checked iterates are feasible;
    /// projecting `y` as well cost a third of the pour's solve (at the pour's 12 sweeps
    /// the unprojected step also ends closer to the solution, at other caps either may:
    /// docs/performance.md). `M^-1 D y` follows by linearity (vector updates); the
    /// explicit part is recomputed from `g` at every check (its rounding drifted over
    /// thousands of iterations), the matrix-free spheres' part is not (docs/performance.md).
    /// Default `false`.
    pub momentum: bool,
    /// Sweep the friction triplets between spheres matrix-free
    /// ([`CcpProblem::mf_contact`]): each reads and updates the world-frame velocities of
    /// its spheres from its normal, arms and frame (10 numbers) instead of its 72 explicit
    /// coefficients. Different rounding from the explicit rows. Default `false`.
    pub matrix_free: bool,
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
            partitioned: false,
            momentum: false,
            matrix_free: false,
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
pub(super) enum Unit {
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
/// changed), so the plain sweep runs on one thread; the setup and the residual checks use
/// the parallel problem operations, and the result is bit-identical for any rayon thread
/// count. Two parallel sweeps: by colours ([`PsorOptions::parallel`], Jacobi within a
/// colour, bit-identical for any thread count) and by parts ([`PsorOptions::partitioned`],
/// Gauss–Seidel within a part, bit-reproducible for a given thread count).
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
    /// What the sweeps read, set up once per solve.
    setup: Setup,
    grad: Vec<f64>,
    best: Vec<f64>,
    units: Vec<Unit>,
    /// The colouring, when sweeping in parallel.
    colouring: Option<Colouring>,
    /// Updates of the units of one colour (parallel sweep).
    deltas: Vec<UnitUpdate>,
    /// The parts, when sweeping by parts.
    partition: Partition,
    /// Whether this solve sweeps by parts (the problem had two parts' worth of units).
    by_parts: bool,
    /// `g` shared by the parts (bits of each row).
    shared: Shared,
    /// Momentum: `T(y_{k-1})`, its `M^-1 D g`, and `y_k`.
    g_prev: Vec<f64>,
    w_prev: Vec<f64>,
    /// The pure spheres' world-frame `M^-1 D g` (6 each), and its previous value.
    ws: Vec<f64>,
    ws_prev: Vec<f64>,
    y: Vec<f64>,
    /// This solve's explicit `M^-1 D g` stays zero (only matrix-free spheres have rows):
    /// the momentum step leaves it.
    w_zero: bool,
    /// Scratch of the fixed-order sums.
    partials: Vec<f64>,
}

impl Psor {
    /// A solver with the common settings `settings` and default [`PsorOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    /// The accelerated PSOR for granular material (solver name `apsor`): exact block
    /// minimization of sphere triplets ([`TripletStep::Exact`]), forward sweeps with
    /// Nesterov momentum and restart after each ([`PsorOptions::momentum`]), parallel
    /// sweeps by parts ([`PsorOptions::partitioned`]), matrix-free sphere triplets
    /// ([`PsorOptions::matrix_free`]) and a residual check every 5 iterations. On the
    /// 10 000-grain pour of `granular-settle` its 12 sweeps leave the bed stiller than
    /// APGD's 100 iterations at a third of the solve time (docs/performance.md, "An
    /// accelerated PSOR"); symmetric sweeps (`symmetric`) cost more per unit of accuracy
    /// there.
    pub fn accelerated(settings: SolverSettings) -> Self {
        Self::new(settings).with_options(PsorOptions {
            triplet_step: TripletStep::Exact,
            symmetric: false,
            momentum: true,
            partitioned: true,
            matrix_free: true,
            check_every: 5,
            ..PsorOptions::default()
        })
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

    /// Sweep in parallel by parts or not (see [`PsorOptions::partitioned`]).
    pub fn with_partitioned(mut self, partitioned: bool) -> Self {
        self.options.partitioned = partitioned;
        self
    }

    /// Nesterov momentum over the iterations or not (see [`PsorOptions::momentum`]).
    pub fn with_momentum(mut self, momentum: bool) -> Self {
        self.options.momentum = momentum;
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
        self.setup.factors.clear();
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
                let factor = self.setup.factors.len();
                for a in 0..len {
                    for b in 0..len {
                        self.setup.factors.push(problem.n_entry(i + a, i + b));
                    }
                }
                DenseLdl::factor(&mut self.setup.factors[factor..], len);
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
            self.setup.step[i] = inv(diag[i]);
        }
        self.setup_triplets(problem);
        self.units
            .extend(s.friction.clone().step_by(3).map(Unit::Triplet));
        for t in s.rolling.clone().step_by(6) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => diag[t..t + 6].iter().sum::<f64>() / 6.0,
                TripletStep::MaxEigen | TripletStep::Exact => {
                    let b = problem.cone_block(t).expect("a rolling contact");
                    gershgorin_bound(b, 6)
                }
            };
            self.setup.step[t..t + 6].fill(inv(lambda));
            self.units.push(Unit::Rolling(t));
        }
        let n = PER_BODY_ROWS;
        for t in s.rolling_per_body.clone().step_by(n) {
            let lambda = match self.options.triplet_step {
                TripletStep::Average => diag[t..t + n].iter().sum::<f64>() / n as f64,
                TripletStep::MaxEigen | TripletStep::Exact => {
                    let b = problem.cone_block(t).expect("a per-body rolling contact");
                    gershgorin_bound(b, n)
                }
            };
            self.setup.step[t..t + n].fill(inv(lambda));
            self.units.push(Unit::RollingPerBody(t));
        }
        self.by_parts = self.options.partitioned
            && self
                .partition
                .rebuild(problem, &self.units, rayon::current_num_threads());
        self.colouring = if self.options.parallel && !self.by_parts {
            self.colour(problem)
        } else {
            None
        };
        if self.colouring.is_some() {
            // the coloured sweep writes the explicit velocities only
            self.setup.mf.clear();
        }
    }

    /// The friction triplets' part of the setup, each triplet on its own (in parallel for
    /// many): its matrix-free contact (if [`PsorOptions::matrix_free`]), its fused rows
    /// otherwise, and its step: `omega / lambda_max(N_tt)` on its three rows, or for
    /// [`TripletStep::Exact`] on a `diag(a, b, b)` block `omega / a`, `omega / b` and the
    /// cone scale `sqrt(b / a)`. A matrix-free contact's block comes from its geometry.
    fn setup_triplets(&mut self, problem: &CcpProblem) {
        let (omega, step_kind) = (self.options.omega, self.options.triplet_step);
        let inv = |d: f64| if d > 0.0 { omega / d } else { 0.0 };
        let fr = problem.sections().friction.clone();
        let nt = fr.len() / 3;
        let (diag, eps) = (problem.diag(), problem.eps());
        let matrix_free = self.options.matrix_free && problem.mf_spheres() > 0;
        // below PAR_MIN_TRIPLETS one rayon job: the calling thread
        let len = PAR_MIN_TRIPLETS;
        let setup = &mut self.setup;
        setup.mf.clear();
        setup.mf_contacts.clear();
        if matrix_free {
            // indexed by triplet (an unused default where a triplet is not matrix-free),
            // each value written once
            (0..nt)
                .into_par_iter()
                .with_min_len(len)
                .map(|k| match problem.mf_contact(k) {
                    Some(c) => (true, problem.mf_sphere_contact(c)),
                    None => (false, SphereContact::default()),
                })
                .unzip_into_vecs(&mut setup.mf, &mut setup.mf_contacts);
        }
        if nt >= len && (!matrix_free || problem.n_matrix_free() < nt) {
            // the explicit blocks are built lazily: once, before the parallel loop
            problem.prepare_cone_blocks();
        }
        setup.fused.clear();
        setup.fused.resize(nt, None);
        setup.cone_scale.clear();
        setup.cone_scale.resize(nt, 0.0);
        let (mf, contacts) = (&setup.mf, &setup.mf_contacts);
        let one = |k: usize, (fused, (scale, step)): (&mut Option<FusedTriplet>, (&mut f64, &mut [f64]))| {
            let t = fr.start + 3 * k;
            let own = mf.get(k).copied().unwrap_or(false).then(|| {
                let mut x = contacts[k].block();
                x[0] += eps[t];
                x[3] += eps[t + 1];
                x[5] += eps[t + 2];
                x
            });
            if own.is_none() {
                *fused = problem.fused_triplet(t);
            }
            let b = match (step_kind, &own) {
                (TripletStep::Average, _) => {
                    step.fill(inv((diag[t] + diag[t + 1] + diag[t + 2]) / 3.0));
                    return;
                }
                (_, Some(x)) => &x[..],
                (_, None) => problem.cone_block(t).expect("a triplet"),
            };
            if step_kind == TripletStep::Exact {
                *scale = diagonal_cone_scale(b);
                if *scale > 0.0 {
                    step.copy_from_slice(&[inv(b[0]), inv(b[3]), inv(b[3])]);
                    return;
                }
            }
            let m = [[b[0], b[1], b[2]], [b[1], b[3], b[4]], [b[2], b[4], b[5]]];
            step.fill(inv(sym3_max_eigen(&m)));
        };
        let steps = &mut setup.step[fr.clone()];
        (setup.fused.par_iter_mut())
            .zip(setup.cone_scale.par_iter_mut().zip(steps.par_chunks_mut(3)))
            .with_min_len(len)
            .enumerate()
            .for_each(|(k, x)| one(k, x));
    }

    /// The sweeps of one iteration (forwards, then backwards if symmetric) by parts: `g`
    /// through its shared copy.
    fn sweep_parts(&mut self, problem: &CcpProblem, g: &mut [f64]) {
        let part = &self.partition;
        self.shared.store(g);
        let data = SweepData {
            problem,
            setup: &self.setup,
            omega: self.options.omega,
        };
        let shared = self.shared.rows();
        let (w, ws) = (&mut self.w, &mut self.ws);
        part.sweep(&data, &self.units, shared, w, ws, true);
        if self.options.symmetric {
            part.sweep(&data, &self.units, shared, w, ws, false);
        }
        self.shared.load(g);
    }

    /// One sweep over all units, forwards or backwards.
    fn sweep(&mut self, problem: &CcpProblem, g: &mut [f64], forward: bool) {
        if self.colouring.is_some() {
            return self.sweep_coloured(problem, g, forward);
        }
        let data = SweepData {
            problem,
            setup: &self.setup,
            omega: self.options.omega,
        };
        let n = self.units.len();
        for k in 0..n {
            let unit = self.units[if forward { k } else { n - 1 - k }];
            let mut vel = Vel {
                w: &mut self.w,
                base: 0,
                ws: &mut self.ws,
                sbase: 0,
            };
            if let Some((t, k)) = as_triplet(&data, unit) {
                let cur = [g[t], g[t + 1], g[t + 2]];
                let new = triplet(&data, t, k, cur, &mut vel);
                g[t..t + 3].copy_from_slice(&new);
                continue;
            }
            let cur = current(unit, g);
            let d = unit_update(&data, unit, &cur, &vel.read());
            apply_update(&data, unit, &d, &cur, &mut vel);
            g[d.start..d.start + d.len].copy_from_slice(&d.new[..d.len]);
        }
    }
}

/// Friction triplets from which the setup runs in parallel.
const PAR_MIN_TRIPLETS: usize = 2048;

/// With momentum, a residual check this many times the best residual seen counts as
/// running away (see [`PsorOptions::momentum`]).
const DIVERGED: f64 = 1e3;

/// With momentum, this many checks in a row without a new best residual count as
/// stalled (see [`PsorOptions::momentum`]).
const STALLED: usize = 3;

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
        for v in [&mut self.setup.step, &mut self.grad, &mut self.best] {
            v.resize(m, 0.0);
        }

        sanitize_and_project(problem, gamma);
        // (the cone blocks are built lazily, by the serial setup, if a unit needs them)
        self.setup(problem);
        let matrix_free = !self.setup.mf.is_empty();
        self.w_zero = matrix_free && problem.explicit_free();
        self.ws.clear();
        if matrix_free {
            // the two halves of the gradient kept: the explicit velocities (the spheres'
            // blocks are not read by the sweeps) and the spheres' world-frame ones, computed
            // in the scratch (sized above) and kept by swapping
            problem.minv_d_explicit(gamma, &mut self.work.v);
            problem.mf_gather(gamma, &mut self.work.w);
            problem.rows_from_velocity(gamma, &self.work, &mut self.grad, Some(problem.r()));
            std::mem::swap(&mut self.w, &mut self.work.v);
            std::mem::swap(&mut self.ws, &mut self.work.w);
        } else {
            problem.minv_d(gamma, &mut self.w);
            problem.gradient(gamma, &mut self.grad, &mut self.work);
        }
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

        if self.options.momentum {
            self.w_prev.clear();
            self.w_prev.extend_from_slice(&self.w);
            self.ws_prev.clear();
            self.ws_prev.extend_from_slice(&self.ws);
            self.g_prev.clear();
            self.g_prev.extend_from_slice(gamma);
            self.y.clear();
            self.y.extend_from_slice(gamma);
        }
        let mut k_mom = 1.0;
        let mut accelerating = self.options.momentum;
        // checks in a row that did not improve on the best
        let mut stalled = 0;
        for it in 1..=max_it {
            iterations = it;
            if self.by_parts {
                self.sweep_parts(problem, gamma);
            } else {
                self.sweep(problem, gamma, true);
                if self.options.symmetric {
                    self.sweep(problem, gamma, false);
                }
            }
            n_apply += 1 + usize::from(self.options.symmetric);
            let check = it % self.options.check_every == 0 || it == max_it;
            if check {
                if matrix_free || self.options.momentum {
                    // the spheres' velocities are world-frame, and momentum's explicit `w`
                    // follows by linearity (its rounding drifted by 1e-11 over thousands of
                    // iterations on a random problem): the explicit product, and that `w`
                    // recomputed from `g` (the spheres' velocities are not: see the docs)
                    problem.gradient(gamma, &mut self.grad, &mut self.work);
                    if self.options.momentum && !matrix_free {
                        problem.minv_d(gamma, &mut self.w);
                    }
                } else {
                    // c = D'w + E g + r with the current w = M^-1 D g.
                    let (w, g, eps, r) = (&self.w, &*gamma, problem.eps(), problem.r());
                    fill_with(&mut self.grad, |i| {
                        problem.row_dot(i, w) + eps[i] * g[i] + r[i]
                    });
                }
                n_apply += 1;
                let res = problem.residual(gamma, &self.grad, &mut self.work);
                history.push(it, res, n_apply, || {
                    problem.objective_from_gradient(gamma, &self.grad, &mut self.work)
                });
                let finite = res.is_finite()
                    && self.w.iter().all(|x| x.is_finite())
                    && self.ws.iter().all(|x| x.is_finite());
                if !finite && !accelerating {
                    // (an accelerated run that went non-finite restarts from the best below)
                    grad_is_best = false;
                    break;
                }
                grad_is_best = finite && res < best_res;
                if grad_is_best {
                    best_res = res;
                    self.best.copy_from_slice(gamma);
                }
                if res <= tol {
                    break;
                }
                if self.options.momentum {
                    stalled = if grad_is_best { 0 } else { stalled + 1 };
                    if grad_is_best {
                        accelerating = true;
                    } else if accelerating
                        && (!finite || res > DIVERGED * best_res || stalled >= STALLED)
                    {
                        // the accelerated iterates ran away or wander without improving
                        // (momentum is not a descent method for Gauss-Seidel sweeps):
                        // back to the best one, plain sweeps until a check improves on it
                        self.restart_from_best(problem, gamma, matrix_free);
                        k_mom = 1.0;
                        accelerating = false;
                    }
                }
            }
            if accelerating && it < max_it {
                self.extrapolate(gamma, &mut k_mom);
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
