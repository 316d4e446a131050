//! The error type of chrono-ccp.

use chrono_core::ChronoError;
use thiserror::Error;

/// Errors of chrono-ccp. Each variant names the value or row that was wrong.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CcpError {
    /// [`by_name`](crate::by_name) got a name that is not a solver.
    #[error("solver = `{name}` is not one of {}", crate::SOLVER_NAMES.join(", "))]
    UnknownSolver {
        /// The rejected name.
        name: String,
    },
    /// The sparse factorization of the bilateral block `N_BB` failed (the Schur solver
    /// then falls back to iterating on those rows).
    #[error("factorization of the {rows} bilateral rows failed at the {stage} stage: {detail}")]
    Factorization {
        /// Number of bilateral rows in the block.
        rows: usize,
        /// `pattern`, `symbolic` or `numeric`.
        stage: &'static str,
        /// The linear-algebra library's message.
        detail: String,
    },
    /// A row of a solution violates the complementarity conditions (reported by
    /// `testing::check_complementarity`).
    #[error("{kind} row {row}: {detail}")]
    NotComplementary {
        /// The row group: `bilateral`, `box`, `unilateral`, `friction`, `rolling`,
        /// `per-body rolling`, or `any` for a non-finite value.
        kind: &'static str,
        /// The (first) row index of the offending row or contact.
        row: usize,
        /// The values and the condition they violate.
        detail: String,
    },
}

impl From<CcpError> for ChronoError {
    /// A solver choice is a parameter (`solver`); the other variants become an invalid
    /// `ccp` parameter carrying their message.
    fn from(e: CcpError) -> Self {
        match e {
            CcpError::UnknownSolver { name } => ChronoError::invalid(
                "solver",
                name,
                format!("must be one of {}", crate::SOLVER_NAMES.join(", ")),
            ),
            other => ChronoError::invalid("ccp", "problem", other.to_string()),
        }
    }
}
