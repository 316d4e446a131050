//! # chrono-ccp
//!
//! Iterative solvers of the cone complementarity problem (CCP) assembled by
//! [`chrono_core::descriptor::CcpProblem`]:
//!
//! ```text
//! find g:  Y ∋ g ⊥ -(N g + r) ∈ Y°,     N = D'M^-1 D + E,   r = b + D'M^-1 k
//! ```
//!
//! equivalently the convex conic QP `min f(g) = 1/2 g'N g + r'g` over `g ∈ Y`, the product of
//! free rows (bilateral), intervals `[lo, hi]` (box rows), half-lines `g >= 0` (unilateral
//! rows), Coulomb cones `|(g_u, g_w)| <= mu g_n` (friction triplets) and rolling/spinning
//! friction cones (6 rows per contact, Tasora and Anitescu 2013) (Anitescu and Tasora
//! 2010, "An iterative approach for cone complementarity problems for nonsmooth dynamics",
//! Comput. Optim. Appl. 47(2)). `g` are impulses (N s), `N g + r` constraint velocities (m/s).
//!
//! Solvers see only the `CcpProblem` (no physics types) and implement
//! [`CcpSolver`]:
//!
//! - [`Jacobi`]: projected Jacobi with a safe (backtracked) step, parallel.
//! - [`Psor`]: projected Gauss–Seidel / SOR (symmetric option, joints relaxed as blocks),
//!   matrix-free, sequential sweeps or parallel graph-coloured sweeps.
//! - [`Apgd`]: Nesterov accelerated projected gradient with backtracking, adaptive restart
//!   and an optional Jacobi metric (Mazhar et al. 2015, ACM TOG 34(3)), parallel.
//! - [`BarzilaiBorwein`]: spectral projected gradient with a non-monotone line search
//!   (Birgin, Martínez and Raydan 2000), parallel.
//! - [`Cg`], [`Minres`]: Krylov solvers for problems whose rows are all bilateral.
//! - [`TwoPhase`]: a bilateral-only phase (Krylov), then the full CCP warm-started from it.
//!
//! All stop on the same measure, [`CcpProblem::residual`](chrono_core::descriptor::CcpProblem::residual)
//! (RMS of the diagonally scaled projected-gradient step, m/s), so their speed-vs-error
//! curves compare; all report their cost in `apply_n`-equivalents
//! ([`SolveStats::apply_n`]) and optionally a per-iteration history (residual, objective,
//! cost, wall time); all treat `gamma` as a warm start, return the iterate with the lowest
//! residual they saw, stop (not converged) instead of propagating NaN, and are bit-for-bit
//! reproducible for a given problem whatever the rayon thread count. [`by_name`] builds any
//! of them from its name.
//!
//! ```
//! use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
//! use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
//! use chrono_core::math::GRAVITY;
//!
//! // A 2 kg particle resting on the ground (normal +z), one step of h = 0.01 s under gravity.
//! let (m, h) = (2.0, 0.01);
//! let mut vars = Variables::new();
//! let p = vars.add(MassOperator::particle(m).unwrap());
//! let mut rows = ConstraintRows::new();
//! let n = [RowEntry { block: p, coefs: &[0.0, 0.0, 1.0] }];
//! let u = [RowEntry { block: p, coefs: &[1.0, 0.0, 0.0] }];
//! let w = [RowEntry { block: p, coefs: &[0.0, 1.0, 0.0] }];
//! rows.push_friction(0.5, [&n, &u, &w], [0.0; 3], [0.0; 3]);
//! let k = [0.0, 0.0, m * GRAVITY.z * h]; // k = M v + h f with v = 0
//! let mut problem = CcpProblem::new();
//! problem.assemble(&vars, &rows, &k).unwrap();
//!
//! let mut gamma = vec![0.0; problem.n_rows()];
//! let stats = Apgd::new(SolverSettings::default()).solve(&problem, &mut gamma);
//! assert!(stats.converged);
//! assert!((gamma[0] + m * GRAVITY.z * h).abs() < 1e-6); // the normal impulse holds the weight
//! ```
//!
//! Errors are [`CcpError`] (convertible into [`chrono_core::ChronoError`]). The cargo
//! feature `testing` (off by default) adds the module `testing`: seeded generators of test
//! problems (random small CCPs, particle lattices, box stacks, a settled granular pile, a
//! bilateral net) and an explicit row-by-row complementarity check, the ones this crate's
//! tests and the `xtask` solver benchmarks use.

/// The `name`, `settings` and `settings_mut` methods of a [`CcpSolver`] whose settings are
/// its field `settings`.
macro_rules! solver_accessors {
    ($name:expr) => {
        fn name(&self) -> &'static str {
            $name
        }

        fn settings(&self) -> &SolverSettings {
            &self.settings
        }

        fn settings_mut(&mut self) -> &mut SolverSettings {
            &mut self.settings
        }
    };
}

/// The builder methods `with_tolerance`, `with_max_iterations` and `with_record_history`
/// of a solver whose [`SolverSettings`] are its field `settings` (inside its inherent
/// `impl`).
macro_rules! settings_builders {
    () => {
        /// Set the residual tolerance (m/s).
        pub fn with_tolerance(mut self, tolerance: f64) -> Self {
            self.settings.tolerance = tolerance;
            self
        }

        /// Set the iteration cap.
        pub fn with_max_iterations(mut self, max_iterations: usize) -> Self {
            self.settings.max_iterations = max_iterations;
            self
        }

        /// Record the residual history.
        pub fn with_record_history(mut self, record_history: bool) -> Self {
            self.settings.record_history = record_history;
            self
        }
    };
}

pub mod admm;
pub mod apgd;
pub mod bb;
pub mod capture;
pub mod cg;
mod dense;
pub mod error;
mod hubs;
pub mod jacobi;
pub mod local_direct;
pub mod minres;
pub mod psor;
pub mod schur;
mod sparse_bilateral;
#[cfg(feature = "testing")]
pub mod testing;
mod timed;
pub mod two_phase;
mod util;

pub use admm::{Admm, AdmmOptions};
pub use apgd::{Apgd, ApgdOptions};
pub use bb::BarzilaiBorwein;
pub use capture::{Capture, load_capture};
pub use cg::{Cg, KrylovOptions, NotBilateral, check_bilateral, relative_residual};
pub use chrono_core::descriptor::{CcpSolver, IterationRecord, SolveStats, SolverSettings};
pub use error::CcpError;
pub use jacobi::{Jacobi, JacobiOptions};
pub use local_direct::{FarSolver, LocalDirect, LocalDirectOptions};
pub use minres::Minres;
pub use psor::{Psor, PsorOptions, TripletStep};
pub use schur::Schur;
pub use timed::TimedSolver;
pub use two_phase::TwoPhase;

/// The names accepted by [`by_name`]: the CCP solvers, then the bilateral-only ones.
pub const SOLVER_NAMES: [&str; 13] = [
    "jacobi",
    "psor",
    "psor-sym",
    "psor-par",
    "apsor",
    "apgd",
    "bb",
    "two-phase",
    "schur",
    "admm",
    "local-direct",
    "cg",
    "minres",
];

/// A solver by name (see [`SOLVER_NAMES`]; `psor-sym` is PSOR with symmetric sweeps,
/// `psor-par` PSOR with parallel coloured sweeps, `apsor` the accelerated PSOR of
/// [`Psor::accelerated`]) with
/// the given settings, or an error naming the unknown value.
pub fn by_name(name: &str, settings: SolverSettings) -> Result<Box<dyn CcpSolver>, CcpError> {
    Ok(match name {
        "jacobi" => Box::new(Jacobi::new(settings)),
        "psor" => Box::new(Psor::new(settings)),
        "psor-sym" => Box::new(Psor::new(settings).with_symmetric(true)),
        "psor-par" => Box::new(Psor::new(settings).with_parallel(true)),
        "apsor" => Box::new(Psor::accelerated(settings)),
        "apgd" => Box::new(Apgd::new(settings)),
        "bb" => Box::new(BarzilaiBorwein::new(settings)),
        "two-phase" => Box::new(TwoPhase::new(settings)),
        "schur" => Box::new(Schur::new(settings)),
        "admm" => Box::new(Admm::new(settings)),
        "local-direct" => Box::new(LocalDirect::new(settings)),
        "cg" => Box::new(Cg::new(settings)),
        "minres" => Box::new(Minres::new(settings)),
        other => {
            return Err(CcpError::UnknownSolver {
                name: other.to_string(),
            });
        }
    })
}

#[cfg(test)]
mod builder_tests {
    use super::*;

    #[test]
    fn settings_builders_set_the_common_settings() {
        let a = Apgd::new(SolverSettings::default())
            .with_tolerance(3e-7)
            .with_max_iterations(17)
            .with_record_history(true);
        let p = Psor::new(SolverSettings::default())
            .with_tolerance(4e-6)
            .with_max_iterations(23)
            .with_record_history(true);
        let (sa, sp) = (a.settings(), p.settings());
        assert_eq!(
            (sa.tolerance, sa.max_iterations, sa.record_history),
            (3e-7, 17, true)
        );
        assert_eq!(
            (sp.tolerance, sp.max_iterations, sp.record_history),
            (4e-6, 23, true)
        );
    }
}
