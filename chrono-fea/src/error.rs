//! The error type of chrono-fea.

use thiserror::Error;

/// Errors from building a mesh or solving it. Every variant names what was wrong: the
/// field and value for bad input, the load step and residual for a solve that failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FeaError {
    /// A material, node, element or solver setting is out of range.
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field, e.g. `material.young`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What a valid value is.
        reason: String,
    },
    /// Newton's method did not reach the residual tolerance within its iteration cap.
    #[error(
        "static solve did not converge at load step {step} of {steps} (load factor {load_factor}): \
         residual {residual:.3e} N > tolerance {tolerance:.3e} N after {iterations} Newton iterations"
    )]
    NotConverged {
        /// The load step (1-based).
        step: usize,
        /// Number of load steps.
        steps: usize,
        /// The load factor of that step, in (0, 1].
        load_factor: f64,
        /// The last residual norm (free dof), N.
        residual: f64,
        /// The tolerance it had to reach, N.
        tolerance: f64,
        /// Newton iterations done.
        iterations: usize,
    },
    /// The tangent stiffness could not be factorized (a mechanism: not enough supports).
    #[error("singular tangent stiffness at load step {step}: {detail}")]
    Singular {
        /// The load step (1-based), 0 outside a load-stepped solve.
        step: usize,
        /// What the factorization reported.
        detail: String,
    },
    /// A sparse matrix could not be built (out of memory, bad indices).
    #[error("sparse assembly failed: {0}")]
    Assembly(String),
    /// A state or force became NaN or infinite.
    #[error("non-finite {quantity} at load step {step}")]
    NonFinite {
        /// The load step (1-based).
        step: usize,
        /// Which quantity.
        quantity: &'static str,
    },
}

/// Result alias of chrono-fea.
pub type Result<T> = std::result::Result<T, FeaError>;

impl FeaError {
    /// Convenience constructor for [`FeaError::InvalidParameter`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        FeaError::InvalidParameter {
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Checks that `v` is finite and `> 0`.
pub(crate) fn positive(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(FeaError::invalid(field, v, "must be finite and > 0"))
    }
}

/// Checks that `v` is finite and `>= 0`.
pub(crate) fn non_negative(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(FeaError::invalid(field, v, "must be finite and >= 0"))
    }
}

/// Checks that every component of `v` is finite.
pub(crate) fn finite3(field: &str, v: &nalgebra::Vector3<f64>) -> Result<()> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(FeaError::invalid(
            field,
            format!("[{}, {}, {}]", v.x, v.y, v.z),
            "must be finite",
        ))
    }
}

/// Check a global coordinate vector: `ndof` entries (`per_node` per node), all finite; the
/// error names the length or the first bad entry.
pub(crate) fn check_coordinates(q: &[f64], ndof: usize, per_node: usize) -> Result<()> {
    if q.len() != ndof {
        return Err(FeaError::invalid(
            "coordinates.len",
            q.len(),
            format!("must be {ndof} ({per_node} per node)"),
        ));
    }
    if let Some(i) = q.iter().position(|x| !x.is_finite()) {
        return Err(FeaError::invalid(
            format!("coordinates[{i}]"),
            q[i],
            "must be finite",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::FeaError;

    /// A chrono-fea error raised inside a step keeps its cause: the chrono-core error's
    /// message and its source both name the real field.
    #[test]
    fn a_fea_error_in_a_step_keeps_its_cause() {
        let e =
            crate::implicit::core_error(FeaError::invalid("material.young", -1.0, "must be > 0"));
        assert!(e.to_string().contains("material.young"), "{e}");
        let source = std::error::Error::source(&e).expect("a source");
        assert!(source.to_string().contains("material.young"), "{source}");
    }
}
