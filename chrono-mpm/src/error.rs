//! The error type of chrono-mpm.

use thiserror::Error;

/// Errors from building or stepping an MPM body. Every variant names what was wrong: the
/// field and value for bad input, the marker and step for a run that failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MpmError {
    /// A material, grid or marker setting is out of range (or not finite).
    #[error("invalid parameter `{field}` = {value}: {reason}")]
    InvalidParameter {
        /// The field, e.g. `material.young`.
        field: String,
        /// The rejected value, as text.
        value: String,
        /// What a valid value is.
        reason: String,
    },
    /// A marker lies outside the region the grid can carry (its B-spline stencil would
    /// leave the grid).
    #[error(
        "marker {marker} at ({x}, {y}, {z}) m is outside the grid's bounds [{lo:?}, {hi:?}] m at step {step}"
    )]
    OutOfBounds {
        /// The marker index.
        marker: usize,
        /// Its position, m.
        x: f64,
        /// Its position, m.
        y: f64,
        /// Its position, m.
        z: f64,
        /// Lower corner of the admissible region, m.
        lo: [f64; 3],
        /// Upper corner of the admissible region, m.
        hi: [f64; 3],
        /// The step (0 before the first step).
        step: u64,
    },
    /// The explicit time step exceeds its stability limit.
    #[error(
        "time step `{field}` = {value} s exceeds the explicit limit {limit:.4e} s (CFL {cfl} x dx {dx} m / wave speed {wave_speed:.4e} m/s)"
    )]
    TimeStep {
        /// The field, `dt`.
        field: &'static str,
        /// The requested step, s.
        value: f64,
        /// The largest stable step, s.
        limit: f64,
        /// The CFL number used.
        cfl: f64,
        /// Grid spacing, m.
        dx: f64,
        /// Elastic wave speed plus the largest marker speed, m/s.
        wave_speed: f64,
    },
    /// The state became non-finite or degenerate (a diverging run).
    #[error("diverged: marker {marker} at step {step} (t = {time} s): {what}")]
    Diverged {
        /// The marker index.
        marker: usize,
        /// The step at which it was detected.
        step: u64,
        /// The simulation time at the start of that step, s.
        time: f64,
        /// Which quantity.
        what: String,
    },
    /// Writing output failed (an error of chrono-core's io).
    #[error(transparent)]
    Io(#[from] chrono_core::ChronoError),
}

/// Result alias of chrono-mpm.
pub type Result<T> = std::result::Result<T, MpmError>;

/// An [`MpmError::InvalidParameter`] for `field` = `value`.
pub(crate) fn invalid(field: &str, value: impl std::fmt::Display, reason: &str) -> MpmError {
    MpmError::InvalidParameter {
        field: field.to_string(),
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

/// `Ok(v)` when `v` is finite and `> 0`, else an error naming `field`.
pub(crate) fn positive(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(invalid(field, v, "must be finite and > 0"))
    }
}

/// `Ok(v)` when `v` is finite and `>= min`, else an error naming `field` with `reason`.
pub(crate) fn at_least(field: &str, v: f64, min: f64, reason: &str) -> Result<f64> {
    if v.is_finite() && v >= min {
        Ok(v)
    } else {
        Err(invalid(field, v, reason))
    }
}
