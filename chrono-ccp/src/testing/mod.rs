//! Test problems and checks for CCP solvers (cargo feature `testing`, off by default).
//!
//! Generators, all deterministic (seeded by [`chrono_core::rng::Rng::splitmix64`], so a
//! seed names one problem on every platform), built only through chrono-core's public
//! descriptor and [`System`](chrono_core::System) APIs:
//!
//! - [`random_problem`]: a small random CCP with every kind of row (bilateral, box,
//!   unilateral, friction, rolling, per-body rolling), well posed;
//! - [`lattice`]: particles on a lattice with frictional contacts (a granular-like problem
//!   of any size);
//! - [`particle_on_ground`], [`box_stack`], [`box_stack_ratio`]: small problems with known
//!   answers (the weight carried by the normal impulses);
//! - [`granular_pile`], [`heavy_stack`]: problems captured from settled scenes (the solver
//!   benchmarks of `cargo xtask validate ccp-solvers` and `ccp-apply-n`);
//! - [`bilateral_net`]: a particle net with distance rows only, for the Krylov solvers.
//!
//! Checks: [`check_complementarity`] verifies a solution row by row; [`dense_n`],
//! [`gradient`], [`objective`] and [`residual`] give the quantities it compares.
//!
//! ```
//! use chrono_ccp::testing::{check_complementarity, random_problem};
//! use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
//!
//! let problem = random_problem(7).unwrap();
//! let mut gamma = vec![0.0; problem.n_rows()];
//! let settings = SolverSettings {
//!     tolerance: 1e-11, // m/s
//!     max_iterations: 200_000,
//!     record_history: false,
//! };
//! assert!(Apgd::new(settings).solve(&problem, &mut gamma).converged);
//! check_complementarity(&problem, &gamma, 1e-9).unwrap();
//! ```

mod check;
mod random;
mod scenes;
mod structured;

pub use check::{check_complementarity, dense_n, gradient, objective, residual};
pub use random::{lattice, random_problem};
pub use scenes::{
    PILE_RADIUS, bilateral_net, granular_pile, heavy_stack, pyramid_base_for, pyramid_contacts,
};
pub use structured::{box_stack, box_stack_ratio, particle_on_ground, rigid_coefs};
