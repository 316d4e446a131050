//! The descriptor: what a solver sees, and nothing more.
//!
//! - [`Variables`]: contiguous generalized velocities in blocks, each with a mass operator
//!   that applies `M` and `M^-1` ([`MassOperator`]): particles, rigid bodies, and coupled
//!   blocks whose (iteration) matrix is factorized by a domain crate ([`CoupledMass`]).
//! - [`ConstraintRows`]: sparse Jacobian rows `D_i'` (one per row of the problem, seed
//!   notation: `D` has one column per row), each with a right-hand side `b_i` and a compliance
//!   `eps_i`, grouped by kind: bilateral (free), box-bounded, unilateral (`>= 0`), and
//!   friction cones (3 rows `n, u, w` with `mu`), rolling/spinning friction cones (6 rows), per-body rolling cones (10 rows).
//! - [`CcpProblem`]: `N = D'M^-1 D + E`, `r = b + D'M^-1 k` and the cone of each row group,
//!   with allocation-free, rayon-parallel, deterministic `apply_n`, `project` and `residual`.
//! - [`ProblemFile`]: a problem saved to / loaded from a file (binary or JSON), bit for bit.
//! - [`CcpSolver`]: the trait solvers implement (in `chrono-ccp`).
//!
//! The problem solved is the cone complementarity problem of Anitescu and Tasora,
//! equivalently the conic QP `min 1/2 g'N g + r'g, g_i in Y_i`; the new velocities are
//! `v+ = M^-1 (k + D g)`.

mod assemble;
mod cone;
mod cone_simd;
mod coupled;
mod file;
mod file_binary;
#[cfg(test)]
mod file_fuzz;
mod frame_rows;
mod frames;
mod frames_simd;
#[cfg(test)]
mod frames_tests;
mod fused;
mod held;
mod mf_sweep;
mod n_plan;
mod ops;
mod packed;
mod problem;
pub mod reduce;
mod row_checks;
mod rows;
mod solver;
#[cfg(test)]
mod tests;
mod variables;

pub use cone::{
    project_box, project_friction_cone, project_rolling_cone, project_rolling_per_body_cone,
    project_unilateral,
};
pub use cone_simd::{friction_residual_terms, project_friction_cones};
pub use coupled::{CoupledMass, DenseMass, dense_matrix};
pub use file::{FrameData, ProblemFile, ProblemFormat};
pub use fused::FusedTriplet;
pub use held::HeldSubproblem;
pub use mf_sweep::SphereContact;
pub use n_plan::NEntryPlan;
pub use ops::UNIT_ROWS;
pub use packed::PackedRows;
pub use problem::{CcpProblem, CcpWork, Sections, upper_index};
pub(crate) use rows::FrameKind;
pub use rows::{ConstraintRows, ContactFrame, N_GROUPS, PER_BODY_ROWS, RowEntry, RowGroup, RowId};
pub use solver::{CcpSolver, IterationRecord, SolveStats, SolverSettings};
pub use variables::{BlockId, MassOperator, Run, Variables};
