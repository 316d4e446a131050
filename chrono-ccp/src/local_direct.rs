//! Heavy-on-light contact by a block Gauss–Seidel: the rows around heavy bodies solved
//! directly (ADMM), the rest by APGD.
//!
//! A heavy body resting on light ones (a vehicle's wheels on grains, a tire mesh on a bed)
//! puts into `N` soft modes of eigenvalue `~1/M` beside the light bodies' `~1/m`: a
//! projected-gradient method converges in the RMS residual (dominated by the many light
//! rows) long before the heavy body's velocity is right. On a step captured from
//! `hmmwv-granular` with NSC grains (80 000 rows, 13 heavy bodies), APGD at 60 iterations
//! left the heavy bodies' velocities 8e-2 m/s from the converged ones, and still 5e-2 at
//! the RMS tolerance 1e-4 m/s (`chrono-ccp/examples/heavy_local.rs`,
//! `docs/validation-rigid.md`): enough to throw the vehicle off the bed within 0.6 s.
//!
//! The rows are split into two blocks:
//!
//! - **local** `L`: every row that is not a contact (joints, motors: bilateral and box
//!   rows), every contact touching a heavy body, and the contacts of the light bodies
//!   within [`LocalDirectOptions::hops`] contacts of those (the load path under the heavy
//!   body). A body is heavy when its mass is at least
//!   [`LocalDirectOptions::heavy_ratio`] times the median mass of the bodies in contact
//!   (coupled blocks, e.g. an implicit FEA mesh, count as heavy);
//! - **far** `F`: the other contacts.
//!
//! and solved by block Gauss–Seidel on the CCP (each block's sub-problem is the CCP of its
//! rows with the other block's impulses held, on the bodies its rows touch:
//! [`HeldSubproblem`], assembled once per solve, its momentum updated per sweep):
//!
//! ```text
//! repeat:  g_L <- ADMM( N_LL g_L + r_L + N_LF g_F )      (direct: insensitive to M / m)
//!          stop if the full residual <= tolerance
//!          g_F <- APGD( N_FF g_F + r_F + N_FL g_L ), a few iterations
//! ```
//!
//! (or accelerated PSOR on the far block: [`LocalDirectOptions::far_solver`]).
//!
//! Block Gauss–Seidel on a convex QP over a product of cones (each block's feasible set a
//! product of the rows' cones) decreases the objective at each block solve and converges
//! (Tseng, "Convergence of a block coordinate descent method for nondifferentiable
//! minimization", J. Optim. Theory Appl. 109(3), 2001). The sweep always ends with the local
//! solve, so the heavy bodies' rows are exact for the far impulses returned.
//!
//! Without heavy bodies the problem goes to the far solver unchanged (same result bit for
//! bit); when
//! every row is local, to ADMM. Cost: `settings.max_iterations` caps the APGD iterations
//! summed over the sweeps; `apply_n` counts the far APGD products, one full gradient per
//! sweep, and the local ADMM products scaled by the local block's share of the rows.

use chrono_core::descriptor::{
    BlockId, CcpProblem, CcpSolver, CcpWork, HeldSubproblem, MassOperator, SolveStats,
    SolverSettings,
};
use serde::{Deserialize, Serialize};

use crate::util::{check_gamma_len, empty_stats, final_stats, sanitize_and_project};
use crate::{Admm, AdmmOptions, Apgd, Psor};

/// Options of [`LocalDirect`] beyond the common [`SolverSettings`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LocalDirectOptions {
    /// A body is heavy when its mass is at least this times the median mass of the bodies
    /// in contact. Default 10.
    pub heavy_ratio: f64,
    /// Contact hops from the heavy bodies included in the local block. Default 2.
    pub hops: usize,
    /// A contact whose warm-start normal impulse moves its bodies at least this many times
    /// the median contact's (`g_n N_nn` against the median over the loaded contacts) is a
    /// seed of the local block like a heavy body's contacts: the load path of a heavy body
    /// through light ones, whatever its depth. Default 10.
    pub load_ratio: f64,
    /// APGD iterations on the far block per sweep. Default 20.
    pub far_iterations: usize,
    /// ADMM iteration cap of one local solve. Default 500.
    pub local_iterations: usize,
    /// Over-relaxation of the local ADMM solves ([`AdmmOptions::relaxation`], in `(0, 2)`).
    /// Default 1.6: on the local blocks of `hmmwv-granular --set method=nsc` it cut the ADMM
    /// iterations by 39 % (docs/validation-vehicle.md, "The NSC vehicle's solver"); plain
    /// ADMM (1) stays the default of [`Admm`] itself, which it does not help on the heavy
    /// box stack.
    pub admm_relaxation: f64,
    /// The far block's iterative solver (also the whole problem's when no body is heavy).
    /// Default [`FarSolver::Apgd`].
    pub far_solver: FarSolver,
}

/// The iterative solver of [`LocalDirect`]'s far block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FarSolver {
    /// Accelerated projected gradient ([`Apgd`]).
    Apgd,
    /// Accelerated projected SOR ([`Psor::accelerated`]: sweeps over the cone blocks with
    /// momentum and a stall restart), the granular pour's fastest solver (issue 23).
    Apsor,
}

impl FarSolver {
    /// By name: `apgd` or `apsor`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "apgd" => Some(Self::Apgd),
            "apsor" => Some(Self::Apsor),
            _ => None,
        }
    }

    fn make(self, settings: SolverSettings) -> Box<dyn CcpSolver> {
        match self {
            Self::Apgd => Box::new(Apgd::new(settings)),
            Self::Apsor => Box::new(Psor::accelerated(settings)),
        }
    }
}

impl Default for LocalDirectOptions {
    fn default() -> Self {
        Self {
            heavy_ratio: 10.0,
            hops: 2,
            load_ratio: 10.0,
            far_iterations: 20,
            local_iterations: 500,
            admm_relaxation: 1.6,
            far_solver: FarSolver::Apgd,
        }
    }
}

/// The ADMM solver of the local block, with the options' relaxation.
fn local_admm(settings: SolverSettings, options: &LocalDirectOptions) -> Admm {
    Admm::new(settings).with_options(AdmmOptions {
        relaxation: options.admm_relaxation,
        ..AdmmOptions::default()
    })
}

/// The block Gauss–Seidel solver of heavy-on-light contact (see the module documentation).
pub struct LocalDirect {
    settings: SolverSettings,
    options: LocalDirectOptions,
    local_solver: Admm,
    far_solver: Box<dyn CcpSolver>,
    local: Vec<usize>,
    far: Vec<usize>,
    /// The two blocks' sub-problems, assembled once per solve and updated per sweep.
    sub_local: HeldSubproblem,
    sub_far: HeldSubproblem,
    g_sub: Vec<f64>,
    grad: Vec<f64>,
    work: CcpWork,
    // partition scratch
    mass: Vec<f64>,
    mark: Vec<bool>,
}

impl LocalDirect {
    /// A solver with the given settings and default [`LocalDirectOptions`].
    pub fn new(settings: SolverSettings) -> Self {
        let sub_settings = SolverSettings {
            record_history: false,
            ..settings.clone()
        };
        let options = LocalDirectOptions::default();
        Self {
            local_solver: local_admm(sub_settings.clone(), &options),
            far_solver: options.far_solver.make(sub_settings.clone()),
            settings,
            options,
            local: Vec::new(),
            far: Vec::new(),
            sub_local: HeldSubproblem::new(),
            sub_far: HeldSubproblem::new(),
            g_sub: Vec::new(),
            grad: Vec::new(),
            work: CcpWork::default(),
            mass: Vec::new(),
            mark: Vec::new(),
        }
    }

    /// Replace the options.
    ///
    /// # Panics
    /// If `admm_relaxation` is outside `(0, 2)` (as [`Admm::with_options`]): a caller's bug.
    pub fn with_options(mut self, options: LocalDirectOptions) -> Self {
        self.local_solver = local_admm(self.local_solver.settings().clone(), &options);
        if options.far_solver != self.options.far_solver {
            self.far_solver = options.far_solver.make(self.far_solver.settings().clone());
        }
        self.options = options;
        self
    }

    /// The options.
    pub fn options(&self) -> &LocalDirectOptions {
        &self.options
    }

    /// The rows of the local block of the last solve (increasing).
    pub fn local_rows(&self) -> &[usize] {
        &self.local
    }

    /// Split the rows of `p` into the local and far blocks (whole cone blocks each).
    fn partition(&mut self, p: &CcpProblem, gamma: &[f64]) {
        let vars = p.variables();
        let nb = vars.len();
        self.mass.clear();
        self.mass
            .extend((0..nb).map(|b| match vars.mass(BlockId(b as u32)) {
                MassOperator::Particle { mass } | MassOperator::RigidBody { mass, .. } => *mass,
                // A shaft's inertia is no mass to compare; joints rows are local anyway.
                MassOperator::Scalar { .. } => 0.0,
                MassOperator::Coupled(_) => f64::INFINITY,
            }));
        let s = p.sections();
        let is_contact = |i: usize| !(s.bilateral.contains(&i) || s.boxed.contains(&i));
        // Median mass of the bodies in contact.
        self.mark.clear();
        self.mark.resize(nb, false);
        let mut in_contact = Vec::new();
        let mut i = 0;
        while i < p.n_rows() {
            let (start, len) = s.block_of(i);
            if is_contact(start) {
                for b in p.row_blocks(start) {
                    let b = b.0 as usize;
                    if !self.mark[b] {
                        self.mark[b] = true;
                        in_contact.push(self.mass[b]);
                    }
                }
            }
            i = start + len;
        }
        self.local.clear();
        self.far.clear();
        if in_contact.is_empty() {
            self.local.extend(0..p.n_rows());
            return;
        }
        let mid = in_contact.len() / 2;
        let median = *in_contact.select_nth_unstable_by(mid, f64::total_cmp).1;
        let heavy_mass = self.options.heavy_ratio * median;
        // `mark`: bodies of the local region, grown hop by hop from the heavy ones.
        for (m, h) in self.mass.iter().zip(self.mark.iter_mut()) {
            *h = *m >= heavy_mass && *m > 0.0;
        }
        let mut local_block = vec![false; p.n_rows()];
        // Load-carrying contacts (warm start): their bodies seed the region too.
        let load = |start: usize| gamma[start] * p.diag()[start];
        let mut loads = Vec::new();
        let mut i = 0;
        while i < p.n_rows() {
            let (start, len) = s.block_of(i);
            if is_contact(start) && gamma[start] > 0.0 {
                loads.push(load(start));
            }
            i = start + len;
        }
        if !loads.is_empty() {
            let mid = loads.len() / 2;
            let heavy_load =
                self.options.load_ratio * *loads.select_nth_unstable_by(mid, f64::total_cmp).1;
            let mut i = 0;
            while i < p.n_rows() {
                let (start, len) = s.block_of(i);
                if is_contact(start) && gamma[start] > 0.0 && load(start) >= heavy_load {
                    local_block[start] = true;
                    for b in p.row_blocks(start) {
                        self.mark[b.0 as usize] = true;
                    }
                }
                i = start + len;
            }
        }
        for hop in 0..=self.options.hops {
            let mut i = 0;
            while i < p.n_rows() {
                let (start, len) = s.block_of(i);
                if !local_block[start]
                    && (!is_contact(start) || p.row_blocks(start).any(|b| self.mark[b.0 as usize]))
                {
                    local_block[start] = true;
                }
                i = start + len;
            }
            if hop < self.options.hops {
                let mut i = 0;
                while i < p.n_rows() {
                    let (start, len) = s.block_of(i);
                    if local_block[start] && is_contact(start) {
                        for b in p.row_blocks(start) {
                            self.mark[b.0 as usize] = true;
                        }
                    }
                    i = start + len;
                }
            }
        }
        let mut i = 0;
        while i < p.n_rows() {
            let (start, len) = s.block_of(i);
            let dest = if local_block[start] {
                &mut self.local
            } else {
                &mut self.far
            };
            dest.extend(start..start + len);
            i = start + len;
        }
        // No heavy body: nothing is local but the joints, which APGD handles as it always
        // did (the load seeds only extend a heavy body's region).
        if !self.mass.iter().any(|&m| m >= heavy_mass && m > 0.0) {
            self.local.clear();
            self.far.clear();
            self.far.extend(0..p.n_rows());
        }
    }

    /// Solve the sub-problem of one block with the other held, from and into `gamma`: the
    /// block's rows are assembled on the first sweep (on the bodies they touch only) and
    /// afterwards only their momentum is updated for the other block's new impulses.
    fn solve_block(
        &mut self,
        p: &CcpProblem,
        local: bool,
        first: bool,
        cap: usize,
        gamma: &mut [f64],
    ) -> Option<SolveStats> {
        let (rows, sub) = if local {
            (&self.local, &mut self.sub_local)
        } else {
            (&self.far, &mut self.sub_far)
        };
        let built = if first {
            sub.build(p, rows, gamma)
        } else {
            sub.update(p, gamma)
        };
        if built.is_err() {
            // The partition is made of whole cone blocks in order, so only a momentum the
            // masses cannot take (impulses gone non-finite) fails: stop the sweeps, the
            // final residual reports it.
            return None;
        }
        self.g_sub.clear();
        self.g_sub.extend(rows.iter().map(|&r| gamma[r]));
        let solver: &mut dyn CcpSolver = if local {
            &mut self.local_solver
        } else {
            self.far_solver.as_mut()
        };
        let st = solver.settings_mut();
        st.max_iterations = cap;
        st.tolerance = 0.5 * self.settings.tolerance;
        let stats = solver.solve(sub.problem(), &mut self.g_sub);
        for (&r, &x) in rows.iter().zip(&self.g_sub) {
            gamma[r] = x;
        }
        Some(stats)
    }
}

impl CcpSolver for LocalDirect {
    solver_accessors!("local-direct");

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        check_gamma_len(problem, gamma);
        let m = problem.n_rows();
        if m == 0 {
            return empty_stats();
        }
        sanitize_and_project(problem, gamma);
        self.partition(problem, gamma);
        if self.local.is_empty() {
            *self.far_solver.settings_mut() = self.settings.clone();
            return self.far_solver.solve(problem, gamma);
        }
        if self.far.is_empty() {
            *self.local_solver.settings_mut() = self.settings.clone();
            return self.local_solver.solve(problem, gamma);
        }
        let share = self.local.len() as f64 / m as f64;
        let (mut far_left, mut sweeps, mut apply_n, mut local_n) =
            (self.settings.max_iterations, 0, 0, 0);
        self.grad.resize(m, 0.0);
        loop {
            let cap = self.options.local_iterations;
            let Some(st) = self.solve_block(problem, true, sweeps == 0, cap, gamma) else {
                problem.gradient(gamma, &mut self.grad, &mut self.work);
                break;
            };
            local_n += st.apply_n;
            sweeps += 1;
            problem.gradient(gamma, &mut self.grad, &mut self.work);
            apply_n += 1;
            let res = problem.residual(gamma, &self.grad, &mut self.work);
            if res <= self.settings.tolerance || far_left == 0 || !res.is_finite() {
                break;
            }
            let cap = self.options.far_iterations.min(far_left);
            let Some(st) = self.solve_block(problem, false, sweeps == 1, cap, gamma) else {
                problem.gradient(gamma, &mut self.grad, &mut self.work);
                break;
            };
            far_left -= st.iterations.min(far_left).max(1);
            apply_n += st.apply_n;
        }
        apply_n += (share * local_n as f64).ceil() as usize;
        final_stats(
            problem,
            gamma,
            &self.grad,
            &mut self.work,
            sweeps,
            apply_n,
            self.settings.tolerance,
            Vec::new(),
        )
    }
}
